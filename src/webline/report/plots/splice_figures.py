"""The report's figure of a run's flying splices (docs/winder.md, S4): the tensions of the
spliced roll's zone around each splice, and a caption computed from them."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from webline.report.plots.frame import framed_figure
from webline.report.plots.mpl_text import legend_label, literal
from webline.report.text.display import Display
from webline.sim.results.result import Result
from webline.sim.results.splice_findings import SpliceWindow, splice_windows

BEFORE, AFTER = 0.5, 3.0  #: the time shown around a splice [s]


def disturbance(result: Result, window: SpliceWindow) -> tuple[float, str, float, float]:
    """(largest tension change [N] from just before the splice, its span, its time after
    the splice [s], the change of the zone's set tension [N] across the splice, as a taper
    sets it from the new diameter) in the zone's spans between the splice and the end of
    its window."""
    time = result.time
    before = max(int(np.searchsorted(time, window.time)) - 1, 0)
    after = (time >= window.time) & (time <= window.until)
    best = (0.0, result.span_names[window.spans[0]], 0.0)
    for k in window.spans:
        change = result.tension[after, k] - result.tension[before, k]
        j = int(np.argmax(np.abs(change)))
        if abs(change[j]) > abs(best[0]):
            best = (float(change[j]), result.span_names[k], float(time[after][j] - window.time))
    loadcell = result.line.zones[result.line.zone_of_span(window.spans[0])].loadcell
    ref = result.tension_ref[:, loadcell]
    first = int(np.argmax(after))
    step = float(ref[first] - ref[before]) if np.isfinite(ref[before]) else 0.0
    return (*best, step)


def splice_caption(result: Result, display: Display) -> str:
    """One sentence per splice: the roll, the instant, the new diameter, the mismatch and
    slack, and the largest tension change it caused (with the set tension's own change)."""
    parts = []
    for window in splice_windows(result.line, result.plan.dt, float(result.time[-1])):
        s = window.splice
        change, span, lag, step = disturbance(result, window)
        text = (f"{s.roll} spliced onto a {display.text(s.new_diameter, 'length')} roll at "
                f"t = {window.time:.4g} s (surface speed {100 * s.speed_mismatch:+.3g} %, "
                f"{_slack(s.slack, display)}): largest tension change "
                f"{display.text(change, 'force')} in {span}, {1000 * lag:.3g} ms after")
        if abs(step) > 1e-9 * max(abs(change), 1.0):
            text += f"; the zone's set tension changed by {display.text(step, 'force')}"
        text += "; " + old_roll_text(result, window, display)
        parts.append(text + ".")
    return "Flying splices: " + " ".join(parts)


def old_roll_text(result: Result, window: SpliceWindow, display: Display) -> str:
    """The old roll as it left the web (the last record before the splice) and the least
    time its drive needs to stop it at its torque limit, J ω / (n τ_max)."""
    node = 0 if window.splice.roll == result.node_names[0] else result.line.n_nodes - 1
    before = max(int(np.searchsorted(result.time, window.time)) - 1, 0)
    inertia = result.inertia[before, 0 if node == 0 else 1]
    omega = abs(result.omega[before, node])
    drive = result.line.spec.rollers[node].drive
    stop = inertia * omega / (drive.ratio * drive.torque_limit)
    return (f"the old {display.text(2.0 * result.radius[before, node], 'length')} roll "
            f"({display.text(inertia, 'inertia')}, {omega:.4g} rad/s) stops in {stop:.3g} s "
            "at the least (its drive's torque limit)")


def _slack(slack: float, display: Display) -> str:
    return f"slack {display.text(slack, 'length')}" if slack else "no slack"


def splice_figure(result: Result, display: Display) -> Figure:
    """Tension of the spliced roll's zone against its set tension around each splice (one
    panel a splice; the splice instant dashed)."""
    windows = splice_windows(result.line, result.plan.dt, float(result.time[-1]))
    fig = framed_figure(9.0, 3.2 * max(len(windows), 1))
    axes = np.atleast_1d(fig.subplots(max(len(windows), 1), 1))
    for ax, window in zip(axes, windows, strict=False):
        shown = ((result.time >= window.time - BEFORE)
                 & (result.time <= min(window.time + AFTER, window.until)))
        for c, k in enumerate(window.spans):
            ax.plot(result.time[shown], display.array(result.tension[shown, k], "force"),
                    lw=1.0, color=f"C{c}", label=legend_label(result.span_names[k]))
            ref = result.tension_ref[shown, k]
            if np.all(np.isfinite(ref)):
                ax.plot(result.time[shown], display.array(ref, "force"), lw=1.2, ls="--",
                        color="k", label="set tension")
        ax.axvline(window.time, color="C3", lw=1.0, ls=":")
        ax.set_title(literal(f"{window.splice.roll} spliced at t = {window.time:.4g} s"),
                     fontsize=9)
        ax.set_ylabel(display.label("tension", "force"))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    axes[-1].set_xlabel("time [s]")
    return fig
