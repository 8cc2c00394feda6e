"""Synthetic measurements for tests, benchmarks and the docs: a simulated run of a line with
changed parameters, written as a logger would record it (sensor noise, a time offset, its
own sample rate) to a CSV file."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from webline.line import Line
from webline.model.lines import load_line
from webline.profiles import breakpoints
from webline.sim.simulate import simulate
from webline.twin.traces.layout import layout
from webline.twin.traces.signals import Signal, line_signals, simulated

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine

#: white sensor noise (standard deviation) by signal kind [SI]: a loadcell amplifier's
#: ~0.25 % of a 200 N reading, an encoder-derived surface speed, a drive's torque estimate
NOISE = {"tension": 0.5, "speed": 2e-3, "torque": 0.02}


def synthetic_csv(path: str | Path, line: Line | BranchedLine | str, *,
                  changes: Mapping[str, object], duration: float,
                  scenario: str | None = None, rate: float = 200.0, offset: float = 0.0,
                  seed: int = 0,
                  noise: Mapping[str, float] | None = None,
                  signals: tuple[str, ...] = ("tension", "speed", "torque")) -> Path:
    """Simulate ``line`` with ``changes`` for ``duration`` [s] and write what a logger at
    ``rate`` [Hz] would record: the loadcell tensions, every roller's speed and every
    drive's torque with white noise (``NOISE``, or ``noise`` by kind [SI]), the master's
    speed reference and the tension references exactly (a PLC logs them), time stamps
    shifted by ``offset`` [s]. Any line, single-path or branched."""
    base = load_line(line)
    if scenario is not None:
        base = base.with_scenario(scenario)
    truth = base.replace(dict(changes)) if changes else base
    result = simulate(truth, duration, record_interval=1.0 / rate)
    rng = np.random.default_rng(seed)
    levels = {**NOISE, **(noise or {})}
    master = layout(truth).master
    chosen = logged_signals(truth, signals)
    values = simulated(result, chosen)
    reference = f"speed_ref[{master}]"
    if reference in values and not np.isfinite(values[reference]).any():
        # a run that does not record its references (a branched line's): the master's is
        # the line's speed reference itself
        values[reference] = np.interp(result.time, *breakpoints(truth.spec.speed))
    columns = {"time [s]": result.time + offset}
    for s in chosen:
        y = values[s.name]
        if s.kind in levels:
            y = y + rng.normal(0.0, levels[s.kind], len(y))
        from webline.units import SI_UNITS

        columns[f"{s.name} [{SI_UNITS[s.unit_kind]}]"] = y
    import pandas as pd

    path = Path(path)
    pd.DataFrame(columns).to_csv(path, index=False, float_format="%.9g")
    return path


def logged_signals(line: Line | BranchedLine,
                   signals: tuple[str, ...] = ("tension", "speed", "torque")) -> list[Signal]:
    """What a logger on ``line`` (single-path or branched) records of the ``signals`` kinds:
    the loadcell tensions, every roller's speed, every drive's torque; and the master's speed
    reference and the loadcells' tension references (a PLC logs them)."""
    view = layout(line)
    loadcells = {point.span for point in view.set_points}
    master = view.master
    return [s for s in line_signals(line).values()
            if (s.kind in signals and (s.kind != "tension" or s.element in loadcells))
            or s.name == f"speed_ref[{master}]"
            or (s.kind == "tension_ref" and s.element in loadcells)]
