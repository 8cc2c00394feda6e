"""Report figures of the winder functions (docs/winder.md): the rewind's set tension against
its diameter (taper), the dancers' positions, the diameter calculators' errors and the
flying splices."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from webline.report.plots.frame import framed_figure
from webline.report.plots.mpl_text import legend_label
from webline.report.plots.splice_figures import splice_caption, splice_figure
from webline.report.text.display import Display
from webline.sim.elements import layout as L
from webline.sim.results.result import Result
from webline.sim.results.splice_findings import splice_windows


def winder_figures(result: Result, display: Display) -> list[tuple[str, str, Figure]]:
    """(key, caption, figure) of every winder figure this run has."""
    out = []
    line = result.line
    last = line.n_nodes - 1
    zone = line.controlled_zone(last)
    if line.rewind.taper is not None and zone is not None:
        out.append(("taper", "Taper: the rewind zone's set and measured tension against the "
                    "rewind's diameter.", taper_figure(result, display,
                                                      line.zones[zone].loadcell)))
    dancers = np.flatnonzero(result.plan.nodes[:, L.N_DANCER] >= 0)
    if len(dancers):
        out.append(("dancer", "Dancer positions against their set positions.",
                    dancer_figure(result, display, [int(i) for i in dancers])))
    calculated = [d for d in range(len(line.drives))
                  if result.plan.drives[d, L.D_DCALC] > 0]
    if calculated:
        out.append(("diameter", "Calculated roll diameter less the true one.",
                    diameter_figure(result, display, calculated)))
    if splice_windows(line, result.plan.dt, float(result.time[-1])):
        out.append(("splice", splice_caption(result, display), splice_figure(result, display)))
    return out


def diameter_figure(result: Result, display: Display, drives: list[int]) -> Figure:
    """Error of each diameter calculator: calculated less true diameter over time."""
    fig = framed_figure(9.0, 3.6)
    ax = fig.subplots()
    for k, d in enumerate(drives):
        i = result.line.drives[d]
        error = 2.0 * (result.control_radius[:, d] - result.radius[:, i])
        ax.plot(result.time, display.array(error, "length"), lw=1.0, color=f"C{k}",
                label=legend_label(result.node_names[i]))
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(display.label("diameter error", "length"))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return fig


def taper_figure(result: Result, display: Display, span: int) -> Figure:
    """Set tension (the taper's) and the measured tension of ``span`` against diameter."""
    fig = framed_figure(7.0, 4.2)
    ax = fig.subplots()
    diameter = display.array(2.0 * result.radius[:, -1], "length")
    ax.plot(diameter, display.array(result.tension[:, span], "force"), lw=0.8, color="C0",
            label=legend_label(f"{result.span_names[span]} tension"))
    ax.plot(diameter, display.array(result.tension_ref[:, span], "force"), lw=1.6, ls="--",
            color="k", label="set tension (taper)")
    ax.set_xlabel(display.label("rewind diameter", "length"))
    ax.set_ylabel(display.label("tension", "force"))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return fig


def dancer_figure(result: Result, display: Display, nodes: list[int]) -> Figure:
    """Position of every dancer over time against its set position."""
    fig = framed_figure(9.0, 3.6)
    ax = fig.subplots()
    for k, i in enumerate(nodes):
        name = result.node_names[i]
        y = result.states[:, result.plan.state_names.index(f"{name}.position")]
        ax.plot(result.time, display.array(y, "length"), lw=1.0, color=f"C{k}",
                label=legend_label(name))
        ax.axhline(float(display.array(np.array(result.plan.nodes[i, L.N_DSET]), "length")),
                   color=f"C{k}", lw=0.8, ls="--")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(display.label("dancer position", "length"))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return fig
