"""The report's figures of a line with many spans: summaries whose cost does not grow with
the number of curves.

One curve (or one axes) per span, roller and drive draws a 500-span line in minutes, with
figures metres tall and legends nobody reads. Beyond ``DETAILED_SPANS`` spans the report draws
instead: the tension of every span as a heat map (span × time) under the band of the spans'
smallest, median and largest tension error; the band of the rollers' web speeds and of the
drives' speed-loop errors; the band of the drives' motor torques; and a condensed schematic
(one mark per roller, zones as bands). Each band is drawn from per-pixel-column extremes
(``BINS`` columns), so a one-tick peak still shows.
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from webline.line import Line
from webline.report.display import Display
from webline.report.frame import framed_figure
from webline.report.mpl_text import literal
from webline.report.tables import Table
from webline.sim.result import Result

#: a line with more spans than this gets the summarised figures (the built-in lines have at
#: most a dozen; a per-span figure of 24 spans is already 40 inches tall)
DETAILED_SPANS = 24
#: time columns of a band or heat map (about the pixel width of a figure at the report's dpi)
BINS = 600


def summarised(line: Line) -> bool:
    """Whether the report summarises ``line``'s figures (more than ``DETAILED_SPANS`` spans)."""
    return line.n_spans > DETAILED_SPANS


def _bins(n: int) -> np.ndarray:
    """Start indices of at most ``BINS`` consecutive, nearly equal slices of ``n`` records."""
    return np.unique(np.linspace(0, n, min(n, BINS) + 1).astype(int)[:-1])


def _band(ax: Axes, time: np.ndarray, values: np.ndarray, color: str, label: str) -> None:
    """Band of ``values`` [time, element] over the elements: smallest to largest (shaded,
    each time bin's extremes) and the median (a line, each bin's mean)."""
    finite = np.where(np.isfinite(values), values, np.nan)
    if finite.shape[1] == 0 or not np.isfinite(finite).any() or len(time) == 0:
        return
    starts = _bins(len(time))
    low = np.fmin.reduceat(np.nanmin(finite, axis=1), starts)
    high = np.fmax.reduceat(np.nanmax(finite, axis=1), starts)
    middle = np.nanmedian(finite, axis=1)
    counts = np.diff(np.append(starts, len(time)))
    mean_middle = np.add.reduceat(np.nan_to_num(middle), starts) / counts
    t = time[starts]
    ax.fill_between(t, low, high, color=color, alpha=0.3, lw=0,
                    label=f"{label}: smallest to largest")
    ax.plot(t, mean_middle, color=color, lw=1.0, label=f"{label}: median")


def _heat_map(fig: Figure, ax: Axes, time: np.ndarray, values: np.ndarray, label: str) -> None:
    """``values`` [time, span] as an image: a row per span, a column per time bin (its mean)."""
    starts = _bins(len(time))
    counts = np.diff(np.append(starts, len(time)))[:, None]
    image = np.add.reduceat(np.nan_to_num(values), starts, axis=0) / counts
    n = values.shape[1]
    end = float(time[-1]) if len(time) else 1.0
    mesh = ax.imshow(image.T, aspect="auto", origin="lower", interpolation="nearest",
                     extent=(float(time[0]) if len(time) else 0.0, end, 0.5, n + 0.5))
    fig.colorbar(mesh, ax=ax, label=label, pad=0.01)
    ax.set_ylabel("span (web order)")


def tension_summary(result: Result, display: Display) -> tuple[str, Figure]:
    """Caption and figure: the band of the loadcell spans' tension errors (tension minus
    reference) and every span's tension as a heat map (span × time)."""
    tension = display.array(result.tension, "force")
    ref = display.array(result.tension_ref, "force")
    loadcell = np.all(np.isfinite(ref), axis=0) if len(ref) else np.zeros(0, bool)
    fig = framed_figure(9.0, 7.0, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    error = tension[:, loadcell] - ref[:, loadcell]
    _band(top, result.time, error, "C0", "tension error")
    top.axhline(0.0, color="k", lw=0.6)
    top.set_ylabel(display.label("tension error", "force"))
    top.legend(fontsize=7, loc="upper right")
    top.set_title(f"{int(loadcell.sum())} loadcell spans", fontsize=9, loc="left")
    _heat_map(fig, bottom, result.time, tension, display.label("tension", "force"))
    bottom.set_title(f"all {result.line.n_spans} spans", fontsize=9, loc="left")
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
    bottom.set_xlabel("time [s]")
    caption = (f"Tension of the {result.line.n_spans} spans, summarised (more than "
               f"{DETAILED_SPANS} spans): the loadcell spans' smallest, median and largest "
               "error against their references, and every span's tension over time.")
    error_si = result.tension[:, loadcell] - result.tension_ref[:, loadcell]
    worst = _worst(error_si, [n for n, c in zip(result.span_names, loadcell, strict=True) if c])
    if worst:
        caption += (f" Largest error: {display.text(worst[1], 'force')} in "
                    f"{literal(worst[0])}.")
    return caption, fig


def _worst(error: np.ndarray, names: list[str]) -> tuple[str, float] | None:
    """The span with the largest absolute error [N], or None."""
    magnitude = np.where(np.isfinite(error), np.abs(error), -1.0)
    if magnitude.size == 0 or magnitude.max() < 0:
        return None
    _, column = np.unravel_index(int(np.argmax(magnitude)), magnitude.shape)
    return names[int(column)], float(magnitude.max())


def speed_summary(result: Result, display: Display) -> Figure:
    """The band of the web speeds at the rollers with the line speed reference, and the band
    of the drives' speed-loop errors (measured minus reference)."""
    from webline.profiles import breakpoints

    fig = framed_figure(9.0, 6.0, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    _band(top, result.time, display.array(result.speed, "speed"), "C0",
          f"web speed at {result.line.n_nodes} rollers")
    times, values = breakpoints(result.line.spec.speed)
    top.plot(result.time, display.array(np.interp(result.time, times, values), "speed"),
             color="k", ls="--", lw=1.0, label="line speed reference")
    top.set_ylabel(display.label("web speed", "speed"))
    error = display.array(result.drive_speed - result.speed_ref, "speed")
    _band(bottom, result.time, error, "C1", f"{len(result.drive_names)} drives")
    bottom.set_ylabel(display.label("speed-loop error", "speed"))
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    bottom.set_xlabel("time [s]")
    return fig


def torque_summary(result: Result, display: Display) -> Figure:
    """The band of the drives' motor torques (the unwind's brake included)."""
    fig = framed_figure(9.0, 3.8)
    ax = fig.subplots()
    _band(ax, result.time, display.array(result.torque, "torque"), "C2",
          f"{len(result.drive_names)} drives")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_ylabel(display.label("motor torque", "torque"))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    ax.set_xlabel("time [s]")
    return fig


def condensed_schematic(line: Line) -> Figure:
    """The line as one row of marks in web order: a roll (large), a driven roller (filled),
    an idler (open); loadcell spans marked below; each tension zone a shaded band."""
    from webline.spec.schema import DrivenSpec

    n = line.n_nodes
    fig = Figure(figsize=(12.0, 2.2))
    ax = fig.add_axes((0.02, 0.3, 0.96, 0.6))
    x = np.arange(n)
    ax.plot(x, np.zeros(n), color="#222222", lw=0.8, zorder=1)
    driven = np.array([isinstance(r, DrivenSpec) for r in line.spec.rollers])
    ax.scatter(x[driven], np.zeros(driven.sum()), s=14, color="#4e79a7", zorder=2,
               label=f"{int(driven.sum())} driven rollers")
    ax.scatter(x[~driven], np.zeros((~driven).sum()), s=14, facecolor="white",
               edgecolor="#333333", zorder=2, label=f"{int((~driven).sum())} idle rollers")
    ax.scatter([0, n - 1], [0, 0], s=120, color="#d8c49a", edgecolor="#333333", zorder=3,
               label="unwind and rewind")
    cells = [zone.loadcell for zone in line.zones]
    ax.scatter(np.array(cells) + 0.5, np.full(len(cells), -0.5), marker="^", s=10,
               color="#e15759", label=f"{len(cells)} loadcells")
    for k, zone in enumerate(line.zones):
        ax.axvspan(zone.first, zone.last, color=("#eef3f8", "#f7f1e8")[k % 2], zorder=0)
    ax.set_xlim(-1, n)
    ax.set_ylim(-1.0, 1.0)
    ax.set_yticks([])
    ax.set_xlabel("roller (web order, unwind = 0)")
    ax.legend(fontsize=7, loc="upper center", ncol=4, bbox_to_anchor=(0.5, 1.45), frameon=False)
    return fig


#: rows kept at each end of a table of a summarised line (``condensed``)
TABLE_ENDS = 8


def condensed(table: Table) -> Table:
    """``table`` with at most ``2 TABLE_ENDS`` rows: its first and last ``TABLE_ENDS``, and
    between them one row saying how many are left out and where they are (the report's
    ``summary.json``, the results file and the resolved line file hold every element)."""
    rows = table.rows
    if len(rows) <= 2 * TABLE_ENDS + 1:
        return table
    hidden = len(rows) - 2 * TABLE_ENDS
    gap = (f"… {hidden} more rows (every element is in summary.json, the results file and "
           "the resolved line file)",) + ("",) * (len(table.columns) - 1)
    return Table(table.key, f"{table.title} (the first and last {TABLE_ENDS} of {len(rows)})",
                 table.columns, (*rows[:TABLE_ENDS], gap, *rows[-TABLE_ENDS:]))
