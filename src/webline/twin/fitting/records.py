"""The records of a fit (issue 36 item 2): each measured file with its own scenario, the line
its logged references drive, its compared signals and their noise levels; and what the fit
gives back for each (its residual scale, the runs before and after, its model checks).

A fit of one file is the one-record case of the same code."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.twin.fitting.checks import ModelChecks
from webline.twin.traces.drive import driven_line
from webline.twin.traces.measurements import Measurements
from webline.twin.traces.replay import as_measurements
from webline.twin.traces.runs import Run, compared_time
from webline.twin.traces.weights import noise_levels

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine

#: residual [noise levels] of a point a failed simulation did not reach
FAILED_RESIDUAL = 1e3
#: the first stage compares means over windows of this length [s]: an oscillation whose
#: phase shifts with a parameter (a light roller ringing on its spans) makes the residuals
#: of single samples a landscape of narrow valleys; its means lead into the right one, and
#: the second stage then fits every sample from there
SMOOTH_SECONDS = 0.1


@dataclass(frozen=True)
class FitRecord:
    """One record: ``label`` (its file's name, unique within the fit), the ``data``, the
    ``line`` with the record's scenario, that line ``driven`` by the record's logged
    references (``twin.traces.drive``) and what was taken from the data (``notes``), the
    compared signal ``names``, their ``measured`` values (signals x compared points [SI],
    NaN: not measured) and ``noise`` levels [SI] (each signal's weight is 1/noise)."""

    label: str
    scenario: str | None
    data: Measurements
    line: Line | BranchedLine
    driven: Line | BranchedLine
    notes: tuple[str, ...]
    names: tuple[str, ...]
    measured: np.ndarray
    noise: dict[str, float]

    @property
    def window(self) -> int:
        """Compared points per mean of the first (smoothed) stage: ``SMOOTH_SECONDS``."""
        return max(1, round(SMOOTH_SECONDS / self.data.sample_period))

    @cached_property
    def points(self) -> int:
        """Measured points compared (every signal's)."""
        return int(np.isfinite(self.measured).sum())

    def measured_signals(self) -> dict[str, np.ndarray]:
        """The measured signals at the compared points [SI], by name."""
        return dict(zip(self.names, self.measured, strict=True))

    def weighted(self, run: Run) -> np.ndarray:
        """(simulated - measured) / noise per signal and compared point; ``FAILED_RESIDUAL``
        where the simulation did not reach, NaN where nothing was measured."""
        r = np.empty_like(self.measured)
        for i, name in enumerate(self.names):  # in place: no temporaries of the whole record
            np.subtract(run.values[name], self.measured[i], out=r[i])
            r[i] *= 1.0 / self.noise[name]
        if np.count_nonzero(np.isfinite(r)) < self.points:  # the run stopped: NaN from there
            # on, a large residual wherever something was measured
            reached = np.isfinite(np.stack([run.values[n] for n in self.names]))
            r[~reached & np.isfinite(self.measured)] = FAILED_RESIDUAL
        return r


def record_labels(sources: Sequence[str]) -> list[str]:
    """Each source's file name, made unique by ``#2``, ``#3``… where two share one."""
    names = [Path(s).name for s in sources]
    out = []
    for i, name in enumerate(names):
        seen = names[:i].count(name)
        out.append(f"{name}#{seen + 1}" if seen or names.count(name) > 1 else name)
    return out


def scenario_list(scenario: str | Sequence[str | None] | None, count: int,
                  option: str = "scenario") -> list[str | None]:
    """One scenario per record: None or one name for all, or a list of one per record
    (``ArgumentError`` naming ``option`` when its length is neither)."""
    if scenario is None or isinstance(scenario, str):
        return [scenario] * count
    chosen = list(scenario)
    if len(chosen) == 1:
        return chosen * count
    if len(chosen) != count:
        raise ArgumentError(f"{option}: {len(chosen)} scenarios for {count} records: give "
                            "one for all, or one per record in the records' order")
    return chosen


def prepare_records(line: Line | BranchedLine, data: Sequence[Measurements | str | Path],
                    scenarios: Sequence[str | None],
                    signals: Sequence[str] | None) -> list[FitRecord]:
    """The records of ``data`` (one scenario each) on ``line``; ``signals`` limits the
    compared signals (a name no record measures is an error; a record compares those it
    has)."""
    loaded = []
    for item, scenario in zip(data, scenarios, strict=True):
        on = line.with_scenario(scenario) if scenario is not None else line
        loaded.append((scenario, on, as_measurements(item, on)))
    labels = record_labels([m.source for _, _, m in loaded])
    if signals is not None:
        missing = [n for n in signals if not any(n in m.signals for _, _, m in loaded)]
        if missing:
            where = ", ".join(m.source for _, _, m in loaded)
            raise ArgumentError(f"signals: {missing[0]!r} is not in {where}")
    records = []
    for label, (scenario, on, measurements) in zip(labels, loaded, strict=True):
        names = (tuple(measurements.names) if signals is None else
                 tuple(n for n in signals if n in measurements.signals))
        stride = measurements.stride
        values = {n: measurements.signals[n][::stride] for n in names}
        driven = driven_line(measurements, on)
        measured = (np.stack([values[n] for n in names]) if names else
                    np.empty((0, len(compared_time(measurements)))))
        records.append(FitRecord(label, scenario, measurements, on, driven.line,
                                 driven.notes, names, measured, noise_levels(values)))
    return records


@dataclass(frozen=True)
class RecordFit:
    """What a fit gives for one record: the runs with the line's and the fitted values
    (``before``, ``after``), its ``residual_scale`` √(Σr²/(m - n)) (r in noise levels, m its
    points, n the parameters acting on it: about 1 at the noise floor), its ``cost``
    (½Σr²), the residuals' ``correlation_time`` [s] and the ``checks`` of its residuals."""

    record: FitRecord
    before: Run
    after: Run
    residual_scale: float
    cost: float
    correlation_time: float
    checks: ModelChecks

    @property
    def label(self) -> str:
        return self.record.label

    @property
    def data(self) -> Measurements:
        return self.record.data

    @property
    def signals(self) -> tuple[str, ...]:
        return self.record.names

    @property
    def noise(self) -> dict[str, float]:
        return self.record.noise

    @property
    def time(self) -> np.ndarray:
        """The compared points [s]."""
        return compared_time(self.record.data)

    def residuals(self) -> dict[str, np.ndarray]:
        """Simulated with the fitted values minus measured, per signal [SI]."""
        return {n: self.after.values[n] - m
                for n, m in self.record.measured_signals().items()}


def residual_scale(r: np.ndarray, parameters: int) -> float:
    """√(Σr²/(m - n)) of weighted residuals ``r`` (NaN: not measured) for n ``parameters``."""
    flat = r[np.isfinite(r)]
    return math.sqrt(float(flat @ flat) / max(1, len(flat) - parameters))
