"""Synthetic measurements for tests, benchmarks and the docs: a simulated run of a line with
changed parameters, written as a logger would record it (sensor noise, a time offset, its
own sample rate) to a CSV file."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np

from webline.line import Line, load_line
from webline.sim.simulate import simulate
from webline.twin.traces.signals import Signal, line_signals, simulated

#: white sensor noise (standard deviation) by signal kind [SI]: a loadcell amplifier's
#: ~0.25 % of a 200 N reading, an encoder-derived surface speed, a drive's torque estimate
NOISE = {"tension": 0.5, "speed": 2e-3, "torque": 0.02}


def synthetic_csv(path: str | Path, line: Line | str, *, changes: Mapping[str, object],
                  duration: float, scenario: str | None = None, rate: float = 200.0,
                  offset: float = 0.0, seed: int = 0,
                  noise: Mapping[str, float] | None = None,
                  signals: tuple[str, ...] = ("tension", "speed", "torque")) -> Path:
    """Simulate ``line`` with ``changes`` for ``duration`` [s] and write what a logger at
    ``rate`` [Hz] would record: the loadcell tensions, every roller's speed and every
    drive's torque with white noise (``NOISE``, or ``noise`` by kind [SI]), the master's
    speed reference and the tension references exactly (a PLC logs them), time stamps
    shifted by ``offset`` [s]."""
    base = load_line(line)
    if scenario is not None:
        base = base.with_scenario(scenario)
    truth = base.replace(dict(changes)) if changes else base
    result = simulate(truth, duration, record_interval=1.0 / rate)
    rng = np.random.default_rng(seed)
    levels = {**NOISE, **(noise or {})}
    chosen = logged_signals(truth, signals)
    values = simulated(result, chosen)
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


def logged_signals(line: Line, signals: tuple[str, ...] = ("tension", "speed", "torque")
                   ) -> list[Signal]:
    """What a logger on ``line`` records of the ``signals`` kinds: the loadcell tensions,
    every roller's speed, every drive's torque; and the master's speed reference and the
    loadcells' tension references (a PLC logs them)."""
    loadcells = {line.span_name(z.loadcell) for z in line.zones}
    master = line.node_name(line.master)
    return [s for s in line_signals(line).values()
            if (s.kind in signals and (s.kind != "tension" or s.element in loadcells))
            or s.name == f"speed_ref[{master}]"
            or (s.kind == "tension_ref" and s.element in loadcells)]
