"""Simulations of a driven line compared point by point with the measurements: one run
(``replay``) or a batch of parameter cases (``fit``'s residuals and Jacobian columns)."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from webline.errors import LineFileError, SimulationError
from webline.line import Line
from webline.sim.results.run_result import RunResult
from webline.sim.simulate import simulate
from webline.twin.traces.layout import default_substeps
from webline.twin.traces.measurements import Measurements
from webline.twin.traces.signals import line_signals, simulated

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine


@dataclass(frozen=True)
class Run:
    """One simulated case: the result (None if the line was refused), its compared signals on
    the data's compared points (``Measurements.time[::stride]``; NaN after a failure) and why
    it failed, if it did."""

    result: RunResult | None
    values: dict[str, np.ndarray]
    failure: str = ""


def compared_time(data: Measurements) -> np.ndarray:
    """Times [s] at which simulations are compared with ``data``: every ``stride``-th tick."""
    return data.time[::data.stride]


def run_case(line: Line | BranchedLine, data: Measurements, names: Sequence[str],
             substeps: int | None = None) -> Run:
    """Simulate ``line`` over the data's duration, recording at its compared points, with
    ``substeps`` RK4 steps per tick (default: from the line's fastest mode)."""
    t = compared_time(data)
    empty = {n: np.full(len(t), math.nan) for n in names}
    try:
        result = simulate(line, data.duration, record_interval=data.stride * data.dt,
                          substeps=substeps, raise_on_failure=False)
    except (LineFileError, SimulationError) as exc:
        return Run(None, empty, str(exc))
    known = line_signals(line)
    raw = simulated(result, [known[n] for n in names])
    values = {}
    for name in names:
        y = np.full(len(t), math.nan)
        n = min(len(t), len(result.time))
        y[:n] = np.interp(t[:n], result.time, raw[name])
        values[name] = y
    return Run(result, values, result.failure_text)


def run_cases(base: Line | BranchedLine, data: Measurements, names: Sequence[str],
              cases: Sequence[Mapping[str, float]], workers: int | None = 1,
              substeps: int | None = None) -> list[Run]:
    """``run_case`` of ``base.replace(case)`` for each case [SI values], as one batch over
    ``workers`` threads (default 1; None: every core), every case with ``substeps`` RK4 steps
    per tick if given. A case the line refuses (a value out of its schema's range) comes
    back as a failed ``Run``."""
    def one(case: Mapping[str, float]) -> Run:
        try:
            line = base.replace(dict(case)) if case else base
        except LineFileError as exc:
            t = compared_time(data)
            return Run(None, {n: np.full(len(t), math.nan) for n in names}, str(exc))
        return run_case(line, data, names, substeps)

    workers = os.cpu_count() or 1 if workers is None else workers
    if workers <= 1 or len(cases) <= 1:
        return [one(c) for c in cases]
    with ThreadPoolExecutor(workers) as pool:
        return list(pool.map(one, cases))


def common_substeps(base: Line | BranchedLine, cases: Sequence[Mapping[str, float]]) -> int:
    """RK4 sub-steps per tick enough for every line of ``cases`` (``base`` changed by each):
    a fit keeps one number for all its simulations, since a step that changed with a
    parameter (through the fastest mode) would make the residuals jump as it crossed."""
    steps = default_substeps(base)
    for case in cases:
        try:
            steps = max(steps, default_substeps(base.replace(dict(case))))
        except (LineFileError, SimulationError):  # (a case past a step limit: its run says)
            continue
    return steps
