"""A quick look at a ``Result`` from Python: ``Result.plot()`` and its display in Jupyter.

The full report (``webline.report``) has more; this is what a script or a notebook wants
after ``simulate``: the main signals over time, and a one-glance summary.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from webline.errors import ArgumentError
from webline.sim.results.decimate import envelope

if TYPE_CHECKING:
    from matplotlib.figure import Figure


class Run(Protocol):
    """What a quick look reads of a run (``webline.sim.results.run_result.RunResult``, named
    here rather than imported: it delegates to this module), besides ``PANELS``' views."""

    @property
    def line(self) -> Any: ...
    @property
    def time(self) -> np.ndarray: ...
    @property
    def tension_ref(self) -> np.ndarray: ...
    @property
    def status(self) -> str: ...
    @property
    def message(self) -> str: ...
    def summary(self) -> dict[str, Any]: ...

#: what each signal of ``plot`` draws: (Result attribute, y label, element names attribute)
PANELS = {
    "tension": ("tension", "tension [N]", "span_names"),
    "speed": ("drive_speed", "web speed at drives [m/s]", "drive_names"),
    "torque": ("torque", "motor torque [N·m]", "drive_names"),
    "radius": ("roll_radius", "roll radius [m]", "roll_names"),
}


def literal(text: str) -> str:
    """``text`` shown as written by matplotlib (a ``$`` would start mathtext)."""
    return text.replace("$", r"\$")


def plot_result(result: Run, signals: Sequence[str] = ("tension", "speed")) -> Figure:
    """A figure with one panel per signal (``tension``, ``speed``, ``torque``, ``radius``)
    over time [s], each line decimated to its min/max envelope; tension references dashed."""
    from matplotlib.figure import Figure

    unknown = [s for s in signals if s not in PANELS]
    if unknown or not signals:
        raise ArgumentError(f"signals: unknown {unknown}; choose from {list(PANELS)}")
    figure = Figure(figsize=(9, 2.6 * len(signals)), layout="constrained")
    axes = figure.subplots(len(signals), 1, sharex=True, squeeze=False)[:, 0]
    for ax, signal in zip(axes, signals, strict=True):
        attribute, label, names = PANELS[signal]
        values = getattr(result, attribute)
        for j in range(values.shape[1]):
            ax.plot(*envelope(result.time, values[:, j]), lw=1.0,
                    label=literal(getattr(result, names)[j]))
        if signal == "tension":
            for k in range(values.shape[1]):
                if np.all(np.isfinite(result.tension_ref[:, k])):
                    ax.plot(result.time, result.tension_ref[:, k], "k--", lw=0.7)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small", loc="best")
    axes[-1].set_xlabel("time [s]")
    figure.suptitle(literal(f"{result.line.name}: {result.status}"))
    return figure


def result_html(result: Run) -> str:
    """One-glance HTML: line, duration, status and message, tension statistics per span."""
    duration = float(result.time[-1]) if len(result.time) else 0.0
    colour = {"ok": "#1a7f37", "warning": "#9a6700"}.get(result.status, "#cf222e")
    rows = []
    for span, stats in result.summary()["spans"].items():
        error = stats.get("rms_error")
        rows.append(f"<tr><td>{html.escape(span)}</td><td>{stats['mean']:.4g}</td>"
                    f"<td>{stats['std']:.3g}</td><td>{'' if error is None else f'{error:.3g}'}"
                    "</td></tr>")
    message = f" — {html.escape(result.message)}" if result.message else ""
    return (f"<div><b>webline result</b>: {html.escape(result.line.name)}, {duration:.4g} s "
            f"simulated, <b style='color:{colour}'>{html.escape(result.status)}</b>{message}"
            "<table><tr><th>span</th><th>mean tension [N]</th><th>std [N]</th>"
            f"<th>RMS error [N]</th></tr>{''.join(rows)}</table></div>")


def result_text(result: Run) -> str:
    """A few lines for ``repr``: the line, how much was simulated in how many records, the
    verdict and why (a dataclass's own repr printed every array)."""
    duration = float(result.time[-1]) if len(result.time) else 0.0
    lines = [f"<webline Result: line {result.line.name!r}, {duration:.4g} s simulated, "
             f"{len(result.time)} records>", f"  status: {result.status}"]
    if result.message:
        lines.append(f"  {result.message}")
    lines.append("  signals: result.signals (xarray), .to_dataframe(), .metrics(), .plot()")
    return "\n".join(lines)
