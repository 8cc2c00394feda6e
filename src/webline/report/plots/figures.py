"""The report's figures (matplotlib, Agg): schematic, span tensions against their references,
web speeds, motor torques, roll radii and inertias, closed-loop poles. Every axis is in the
chosen units; time is in seconds.

Long runs are drawn at screen resolution: the minimum and maximum of each pixel column of a
signal (``webline.sim.results.decimate.envelope``), so peaks and ripple stay visible while drawing
and
files stay small.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter

from webline.analysis.modes import Mode
from webline.profiles import breakpoints
from webline.report.plots.big_lines import (
    condensed_schematic,
    speed_summary,
    summarised,
    tension_summary,
    torque_summary,
)
from webline.report.plots.frame import framed_figure, make_room_for_title
from webline.report.plots.mpl_text import legend_label, literal, power_label
from webline.report.plots.roll_figures import roll_modes_caption, roll_modes_figure
from webline.report.plots.schematic import schematic
from webline.report.plots.winder_figures import winder_figures
from webline.report.text.display import Display
from webline.sim.results.decimate import envelope
from webline.sim.results.result import Result


@dataclass(frozen=True)
class ReportFigure:
    """A figure with the file stem (``key``) and caption it gets in the report."""

    key: str
    caption: str
    figure: Figure


def _plot(ax: Axes, time: np.ndarray, values: np.ndarray, **style: object) -> None:
    ax.plot(*envelope(time, values), **style)  # type: ignore[arg-type]


def _floor_range(ax: Axes, scale: float, fraction: float = 0.02) -> None:
    """Widen ``ax``'s y range to at least ``fraction`` of ``scale`` (a signal's typical size),
    so that a signal that barely moves is drawn flat rather than as magnified round-off."""
    low, high = ax.get_ylim()
    least = fraction * abs(scale)
    if least > 0 and np.isfinite(least) and high - low < least:
        middle = (low + high) / 2
        ax.set_ylim(middle - least / 2, middle + least / 2)
    ax.ticklabel_format(axis="y", useOffset=False)


def _size(values: np.ndarray) -> float:
    """Typical size of a signal: its largest finite magnitude (1 if there is none)."""
    finite = np.abs(values[np.isfinite(values)])
    return float(finite.max()) if finite.size and finite.max() > 0 else 1.0


def _finish(fig: Figure, axes: Sequence[Axes], result: Result) -> None:
    """Grid, time label, and a marker where a failed run stopped."""
    for ax in axes:
        ax.grid(True, alpha=0.3)
        if result.failure is not None and len(result.time):
            ax.axvline(result.time[-1], color="#d62728", ls=":", lw=1.2)
    axes[-1].set_xlabel("time [s]")
    if result.failure is not None:
        make_room_for_title(fig)
        fig.suptitle(literal(f"run stopped: {result.failure.message}"), color="#d62728",
                     fontsize=9)


def tension_figure(result: Result, display: Display) -> Figure:
    """Tension of every span (solid) against its loadcell reference (dashed); slack shaded."""
    n = result.line.n_spans
    fig = framed_figure(9.0, 1.3 + 1.6 * n, rows=n)
    axes = fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]
    tension = display.array(result.tension, "force")
    ref = display.array(result.tension_ref, "force")
    for k, ax in enumerate(axes):
        _plot(ax, result.time, tension[:, k], color="C0", lw=1.0, label="tension")
        if np.all(np.isfinite(ref[:, k])):
            _plot(ax, result.time, ref[:, k], color="k", ls="--", lw=1.0, label="reference")
            title = f"{literal(result.span_names[k])} (loadcell)"
        else:
            title = f"{literal(result.span_names[k])} (no loadcell)"
        _shade(ax, result, result.span_names[k])
        ax.set_title(title, fontsize=9, loc="left")
        _floor_range(ax, _size(tension[:, k]))
        ax.set_ylabel(display.label("tension", "force"))
        ax.legend(fontsize=7, loc="upper right")
    _finish(fig, list(axes), result)
    return fig


#: colour of each kind of event shaded in the tension figure
SHADES = {"slack": "#d62728", "tension_limit": "#ff7f0e"}


def _shade(ax: Axes, result: Result, span: str) -> None:
    """Shade every slack and over-limit interval of ``span``: one collection and one legend
    entry per kind, however many intervals."""
    for event in result.events:
        if event.where == span and event.kind in SHADES:
            starts, ends = event.intervals[:, 0], event.intervals[:, 1]
            spans = list(zip(starts.tolist(), (ends - starts).tolist(), strict=True))
            ax.broken_barh(spans, (0.0, 1.0), transform=ax.get_xaxis_transform(),
                           color=SHADES[event.kind], alpha=0.25, lw=0,
                           label=f"{event.kind.replace('_', ' ')} ({event.count}x)")


def speed_figure(result: Result, display: Display) -> Figure:
    """Web speed at every roller with the line speed reference, and each drive's speed-loop
    error (measured minus reference)."""
    fig = framed_figure(9.0, 6.0, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    speed = display.array(result.speed, "speed")
    for i, name in enumerate(result.node_names):
        _plot(top, result.time, speed[:, i], lw=1.0, label=legend_label(name))
    times, values = breakpoints(result.line.spec.speed)
    line_ref = display.array(np.interp(result.time, times, values), "speed")
    _plot(top, result.time, line_ref, color="k", ls="--", lw=1.0, label="line speed reference")
    _floor_range(top, _size(speed))
    top.set_ylabel(display.label("web speed", "speed"))
    top.legend(fontsize=7, loc="lower right", ncol=2)
    error = display.array(result.drive_speed - result.speed_ref, "speed")
    for d, name in enumerate(result.drive_names):
        _plot(bottom, result.time, error[:, d], lw=1.0, label=legend_label(name))
    _floor_range(bottom, _size(speed), 0.002)
    bottom.set_ylabel(display.label("speed-loop error", "speed"))
    bottom.legend(fontsize=7, loc="upper right", ncol=2)
    _finish(fig, (top, bottom), result)
    return fig


def torque_figure(result: Result, display: Display) -> Figure:
    """Motor torque of every drive (positive drives the web forward; the unwind brakes)."""
    fig = framed_figure(9.0, 3.8)
    ax = fig.subplots()
    torque = display.array(result.torque, "torque")
    for d, name in enumerate(result.drive_names):
        _plot(ax, result.time, torque[:, d], lw=1.0, label=legend_label(name))
    ax.axhline(0.0, color="k", lw=0.6)
    _floor_range(ax, _size(torque))
    ax.set_ylabel(display.label("motor torque", "torque"))
    ax.legend(fontsize=7, loc="upper right", ncol=2)
    _finish(fig, (ax,), result)
    return fig


def roll_figure(result: Result, display: Display) -> Figure:
    """Radius and inertia (at the roll shaft, web included) of the unwind and rewind rolls."""
    fig = framed_figure(9.0, 5.0, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    radius = display.array(result.radius, "length")
    inertia = display.array(result.inertia, "inertia")
    for col, i in enumerate((0, result.line.n_nodes - 1)):
        name = legend_label(result.node_names[i])
        _plot(top, result.time, radius[:, i], lw=1.2, color=f"C{col}", label=name)
        _plot(bottom, result.time, inertia[:, col], lw=1.2, color=f"C{col}", label=name)
    top.set_ylabel(display.label("roll radius", "length"))
    bottom.set_ylabel(display.label("roll inertia", "inertia"))
    _floor_range(top, _size(radius))
    _floor_range(bottom, _size(inertia))
    for ax in (top, bottom):
        ax.legend(fontsize=7, loc="best")
    _finish(fig, (top, bottom), result)
    return fig


def slip_figure(result: Result, display: Display, nodes: Sequence[int]) -> Figure:
    """Slip velocity (surface minus web speed) and slip state of the rollers that may slip."""
    fig = framed_figure(9.0, 5.0, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    velocity = display.array(result.slip_velocity, "speed")
    for k, i in enumerate(nodes):
        name = legend_label(result.node_names[i])
        _plot(top, result.time, velocity[:, i], lw=1.0, color=f"C{k}", label=name)
        bottom.step(result.time, result.slipping[:, i] + 0.02 * k, where="post", lw=1.0,
                    color=f"C{k}", label=name)
    top.axhline(0.0, color="k", lw=0.6)
    top.set_ylabel(display.label("slip velocity", "speed"))
    bottom.set_yticks([0, 1], ["stuck", "slipping"])
    for ax in (top, bottom):
        ax.legend(fontsize=7, loc="upper right", ncol=2)
    _finish(fig, (top, bottom), result)
    return fig


def mrac_figure(result: Result, display: Display) -> Figure:
    """Per MRAC drive: the adapted gains k̂ on the tension deviation [m] and on the speed
    deviation [N·s], and the bias ĉ (a motor torque), over time."""
    fig = framed_figure(9.0, 6.5, rows=3)
    axes = fig.subplots(3, 1, sharex=True)
    gains = result.mrac_gains
    labels = ("gain on tension [m]", "gain on speed [N·s]")
    for d in np.flatnonzero(result.has_mrac):
        name = legend_label(result.drive_names[d])
        for q in range(2):
            _plot(axes[q], result.time, gains[:, d, q], lw=1.0, color=f"C{d}", label=name)
        _plot(axes[2], result.time, display.array(gains[:, d, 2], "torque"), lw=1.0,
              color=f"C{d}", label=name)
    for ax, label in zip(axes, (*labels, display.label("bias", "torque")), strict=True):
        ax.set_ylabel(label)
        ax.legend(fontsize=7, loc="upper right", ncol=2)
    _finish(fig, list(axes), result)
    return fig


def poles_figure(modes: Sequence[Mode]) -> Figure:
    """Closed-loop poles in the complex plane [1/s] (each pair drawn with its conjugate)."""
    fig = framed_figure(7.0, 4.2)
    ax = fig.subplots()
    values = np.array([m.eigenvalue for m in modes], dtype=complex)
    for sign in (1.0, -1.0):
        ax.plot(values.real, sign * values.imag, "x", color="C3", ms=8, mew=1.6)
    title = "closed-loop poles"
    least = min((m for m in modes if m.oscillatory), key=lambda m: m.damping, default=None)
    if least is not None:
        ax.plot([least.eigenvalue.real], [least.eigenvalue.imag], "o", mfc="none", color="k",
                ms=13)
        title += (f"; circled, least damped: ζ = {least.damping:.2f} at "
                  f"{least.frequency_hz:.3g} Hz ({literal(least.dominant)})")
    ax.axvline(0.0, color="k", lw=0.8)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xscale("symlog", linthresh=10.0)
    ax.xaxis.set_major_formatter(FuncFormatter(power_label))  # plain text, not mathtext
    ax.set_xlabel("real part [1/s] (symmetric log scale)")
    ax.set_ylabel("imaginary part [rad/s]")
    ax.grid(True, alpha=0.3)
    ax.set_title(title, fontsize=9)
    return fig


#: a figure job: builds one or more figures when called (in this process or a forked one)
FigureJob = Callable[[], list[ReportFigure]]


def figure_jobs(result: Result, display: Display,
                modes: Sequence[Mode] = ()) -> list[FigureJob]:
    """The jobs that build every figure of a run's report, in report order; each is
    independent of the others, so they may run in parallel (``webline.report.render``)."""
    def one(key: str, caption: str, make: Callable[[], Figure]) -> FigureJob:
        return lambda: [ReportFigure(key, caption, make())]

    jobs = _summarised_jobs(result, display) if summarised(result.line) else [
        one("schematic", "The line, drawn from its topology.",
            lambda: schematic(result.line, display)),
        one("tension", "Tension in every span against its reference.",
            lambda: tension_figure(result, display)),
        one("speed", "Web speed at every roller and each drive's speed-loop error.",
            lambda: speed_figure(result, display)),
        one("torque", "Motor torque of every drive.", lambda: torque_figure(result, display)),
        one("rolls", "Unwind and rewind roll radius and inertia.",
            lambda: roll_figure(result, display)),
    ]
    jobs += [one("rolls", "Unwind and rewind roll radius and inertia.",
                  lambda: roll_figure(result, display))] if summarised(result.line) else []
    slipping = [i for i in range(1, result.line.n_nodes - 1)
                if getattr(result.line.spec.rollers[i].contact, "type", "") == "traction"]
    if slipping:
        jobs.append(one("slip", "Web slip over the rollers with a traction contact.",
                        lambda: slip_figure(result, display, slipping)))
    jobs.append(lambda: [ReportFigure(*parts) for parts in winder_figures(result, display)])
    if result.has_mrac.any():
        jobs.append(one("mrac", "The MRAC's adapted gains and bias (thesis 6.68, E-6.14).",
                        lambda: mrac_figure(result, display)))
    if result.roll_modes is not None:  # a run across a roll: its modes along the way
        jobs.append(one("across_roll", roll_modes_caption(result.roll_modes, display),
                        lambda: roll_modes_figure(result.roll_modes, display)))  # type: ignore[arg-type]
    if result.wound_roll is not None:  # the rewind's roll stresses (docs/wound-roll.md)
        from webline.report.plots.wound_roll import wound_roll_caption, wound_roll_figure

        roll = result.wound_roll
        jobs.append(one("wound_roll", wound_roll_caption(roll), lambda: wound_roll_figure(roll)))
    if modes:
        jobs.append(one("poles", "Closed-loop poles at the operating point.",
                        lambda: poles_figure(modes)))
    return jobs


def _summarised_jobs(result: Result, display: Display) -> list[FigureJob]:
    """The schematic, tension, speed and torque figures of a line with many spans, each one
    figure of a size and cost independent of the number of spans (``report.plots.big_lines``)."""
    n = result.line.n_spans

    def tension() -> list[ReportFigure]:
        caption, fig = tension_summary(result, display)
        return [ReportFigure("tension", caption, fig)]

    return [
        lambda: [ReportFigure("schematic", f"The line, condensed ({n} spans): a mark per "
                              "roller in web order.", condensed_schematic(result.line))],
        tension,
        lambda: [ReportFigure("speed", "Web speed at the rollers and the drives' speed-loop "
                              "errors: smallest, median and largest at each instant.",
                              speed_summary(result, display))],
        lambda: [ReportFigure("torque", "Motor torque of the drives: smallest, median and "
                              "largest at each instant.", torque_summary(result, display))],
    ]
