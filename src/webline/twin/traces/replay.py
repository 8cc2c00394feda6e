"""``webline.twin.traces.replay``: the line driven by measured references, compared with every
measured signal."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.line import Line
from webline.model.lines import load_line
from webline.twin.traces.drive import driven_line
from webline.twin.traces.measurements import Measurements, load_measurements
from webline.twin.traces.metrics import signal_metrics
from webline.twin.traces.runs import Run, compared_time, run_case
from webline.twin.traces.signals import si_unit

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from webline.model.web_graph import BranchedLine


@dataclass(frozen=True)
class Replay:
    """A replay: the data, the driven line, the simulated signals at the compared points
    (``time`` [s]), the metrics table (``twin.traces.metrics.COLUMNS``, SI) and what drove it."""

    data: Measurements
    line: Line | BranchedLine
    run: Run
    time: np.ndarray
    metrics: Any
    notes: tuple[str, ...]

    @property
    def measured(self) -> dict[str, np.ndarray]:
        """The measured signals at the compared points [SI]."""
        return {n: self.data.signals[n][::self.data.stride] for n in self.data.names}

    def plot(self, signals: list[str] | None = None) -> Figure:
        """Overlay figure: measured and simulated, one panel per signal."""
        from webline.twin.traces.figures import overlay_figure

        return overlay_figure(self.time, self.measured, self.run.values,
                              signals or self.data.names, "replay")

    def __repr__(self) -> str:
        worst = ""
        frame = self.metrics
        if len(frame):
            row = frame.loc[frame["nrmse"].idxmax()]
            worst = f"; largest NRMSE {row['nrmse']:.3g} on {row['signal']}"
        return (f"<webline Replay of {Path(self.data.source).name} on {self.line.name!r}: "
                f"{len(frame)} signals compared{worst}>")


def as_measurements(data: Measurements | str | Path, line: Line | BranchedLine) -> Measurements:
    """``data`` loaded for ``line`` if it is a path."""
    return data if isinstance(data, Measurements) else load_measurements(data, line)


def replay(line: Line | BranchedLine | str | Path, data: Measurements | str | Path, *,
           scenario: str | None = None) -> Replay:
    """Simulate ``line`` driven by the references logged in ``data`` (a ``Measurements`` or
    a file path, see ``load_measurements``) and compare it with every measured signal.
    ``scenario`` starts from one of the line's scenarios (its disturbances, roll radii);
    the logged line speed, tension set points and initial roll radii replace the line's
    (``twin.traces.drive.driven_line``). The metrics are per signal: RMS, max abs error, NRMSE
    (RMS / measured range), bias (mean of simulated - measured), R², in SI units."""
    line = load_line(line)
    if scenario is not None:
        line = line.with_scenario(scenario)
    data = as_measurements(data, line)
    driven = driven_line(data, line)
    names = data.names
    run = run_case(driven.line, data, names)
    measured = {n: data.signals[n][::data.stride] for n in names}
    metrics = signal_metrics(run.values, measured, {n: si_unit(n) for n in names})
    notes = driven.notes + ((f"the simulation failed: {run.failure}",) if run.failure else ())
    return Replay(data, driven.line, run, compared_time(data), metrics, notes)
