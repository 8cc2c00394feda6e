"""``webline.twin.load_measurements``: a measurement file read against a line and resampled
onto the line's controller ticks, with a record of everything that was done to it."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.line import Line
from webline.model.lines import load_line
from webline.twin.traces.read import MeasurementError, RawColumn, read_columns
from webline.twin.traces.signals import Signal, is_ignored, line_signals, suggestions

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine

#: a spacing longer than this many median sample periods is a gap: ticks inside it have no
#: measurement (NaN) rather than an interpolation across it
GAP_FACTOR = 3.0
#: fewest valid samples of a signal before it counts as measured
MIN_SAMPLES = 20
#: a record must last this many time constants of the line's slowest control loop
MIN_TIME_CONSTANTS = 5.0


@dataclass(frozen=True)
class Measurements:
    """Measured signals of one line on its controller ticks.

    ``time`` [s] are the ticks from 0 (the file's first time stamp, ``offset`` [s], is
    removed); ``signals`` the SI values at each tick (NaN where the file has a gap or no
    data); ``sample_period`` [s] the file's median spacing (a fit compares every
    ``stride``-th tick, so that its residuals stay as independent as the file's samples);
    ``notes`` what the loading did (resampling, gaps, NaNs dropped, columns not compared)."""

    source: str
    line: Line | BranchedLine
    time: np.ndarray
    signals: dict[str, np.ndarray]
    units: dict[str, str]
    sample_period: float
    offset: float
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def dt(self) -> float:
        """Controller period [s]."""
        return float(self.time[1] - self.time[0]) if len(self.time) > 1 else 0.0

    @property
    def duration(self) -> float:
        """Length of the record [s]."""
        return float(self.time[-1])

    @property
    def stride(self) -> int:
        """Ticks between compared points: the file's sample period in ticks (at least 1)."""
        return max(1, round(self.sample_period / self.dt)) if self.dt else 1

    @property
    def names(self) -> list[str]:
        """The measured signals compared with a simulation (references excluded)."""
        return [n for n in self.signals if not n.partition("[")[0].endswith("_ref")]

    def report(self) -> str:
        """What was read and done, one item per line."""
        head = (f"{self.source}: {len(self.signals)} signals, {self.duration:.4g} s on "
                f"{1 / self.dt:.4g} Hz ticks of line {self.line.name!r}")
        return "\n".join([head, *(f"- {n}" for n in self.notes)])

    def to_dataframe(self) -> Any:
        """The signals as a ``pandas.DataFrame`` indexed by tick time [s], SI."""
        import pandas as pd

        frame = pd.DataFrame(self.signals, index=pd.Index(self.time, name="time"))
        frame.attrs["units"] = dict(self.units)
        return frame

    def __repr__(self) -> str:
        shown = ", ".join(list(self.signals)[:4]) + (" ..." if len(self.signals) > 4 else "")
        return (f"<webline Measurements {Path(self.source).name}: {len(self.signals)} signals "
                f"over {self.duration:.4g} s ({len(self.notes)} notes)>\n  {shown}")


def load_measurements(path: str | Path, line: Line | BranchedLine | str | Path,
                      mapping: Mapping[str, str] | None = None) -> Measurements:
    """Read measured traces for ``line`` from a CSV, Parquet or NetCDF file.

    Columns are a time column (``time [s]``) and any of the signals webline writes, with the
    same names (``tension[process_span] [N]``, ``speed[rewind] [m/s]``,
    ``torque[unwind] [N*m]``; a run's own ``results.csv``/``results.nc`` load as they are)
    and units in the header (any pint unit of the right kind: ``[lbf]``, ``[ft/min]``; no
    unit: SI). ``mapping`` renames foreign columns ({"LC2_N": "tension[process_span]"}; a
    name mapped to "" is skipped). Uneven sampling, a different rate, gaps and NaNs are
    resampled onto the controller ticks (linear interpolation between valid samples, gaps
    longer than ``GAP_FACTOR`` sample periods left empty) and the first time stamp is taken
    as t = 0; ``Measurements.notes`` say what was done. Raises ``MeasurementError`` (one line:
    file, column, problem) for an empty file, an unknown column, a unit of the wrong kind,
    time that does not increase, or a record too short to identify anything.
    """
    line = load_line(line)
    label = str(path)
    columns = read_columns(Path(path))
    columns = _renamed(columns, dict(mapping or {}), label)
    time_column = next((c for c in columns if c.name.lower() in ("time", "t")), None)
    if time_column is None:
        raise MeasurementError(label, "time", "no time column (name one 'time [s]' or map "
                               "yours to 'time')")
    known = line_signals(line)
    notes: list[str] = []
    chosen: list[tuple[RawColumn, Signal]] = []
    ignored = []
    for column in columns:
        if column is time_column:
            continue
        signal = known.get(column.name)
        if signal is None:
            if is_ignored(line, column.name):
                ignored.append(column.name)
                continue
            raise MeasurementError(label, column.header, "matches no signal of line "
                                   f"{line.name!r}" + suggestions(column.name, list(known))
                                   + " (map it with mapping= / --map NAME=SIGNAL)")
        chosen.append((column, signal))
    if ignored:
        notes.append(f"{len(ignored)} columns webline writes but does not compare were "
                     f"skipped ({', '.join(sorted({n.partition('[')[0] for n in ignored}))})")
    t = _seconds(time_column, label)
    if not np.all(np.isfinite(t)):
        keep = np.isfinite(t)
        notes.append(f"{int((~keep).sum())} rows without a time stamp dropped")
    else:
        keep = np.ones(len(t), dtype=bool)
    t_ok = t[keep]
    step = np.diff(t_ok)
    if np.any(step <= 0):
        i = int(np.argmax(step <= 0))
        raise MeasurementError(label, time_column.header, f"time does not increase at data row "
                               f"{int(np.flatnonzero(keep)[i + 1]) + 1} ({t_ok[i]:.6g} s then "
                               f"{t_ok[i + 1]:.6g} s)")
    if len(t_ok) < 2:
        raise MeasurementError(label, time_column.header, "fewer than two time stamps")
    offset = float(t_ok[0])
    period = float(np.median(step))
    dt = line_dt(line)
    n_ticks = int(np.floor((t_ok[-1] - offset) / dt + 1e-9)) + 1
    ticks = np.arange(n_ticks) * dt
    if offset != 0.0:
        notes.append(f"time offset {offset:.6g} s removed (the file's first time stamp is t = 0)")
    spread = (float(step.min()), float(step.max()))
    uneven = spread[1] > 1.01 * spread[0]
    notes.append(f"sampled every {period * 1e3:.4g} ms" +
                 (f" (uneven: {spread[0] * 1e3:.3g}-{spread[1] * 1e3:.3g} ms)" if uneven else "")
                 + f", resampled onto the {dt * 1e3:.4g} ms controller ticks by linear "
                 "interpolation" + (" (the file is faster than the ticks: no averaging)"
                                    if period < dt * 0.99 else ""))
    signals, units = {}, {}
    for column, signal in chosen:
        values = column.values[keep] * _si_factor(column, signal, label)
        valid = np.isfinite(values)
        if valid.sum() < MIN_SAMPLES:
            notes.append(f"{signal.name}: " + (f"only {int(valid.sum())} valid samples"
                                                 if valid.any() else "no data (all NaN)")
                         + ": skipped")
            continue
        if (~valid).any():
            notes.append(f"{signal.name}: {int((~valid).sum())} NaN samples dropped")
        tv, yv = t_ok[valid] - offset, values[valid]
        y = np.interp(ticks, tv, yv)
        gaps = np.flatnonzero(np.diff(tv) > GAP_FACTOR * period)
        for g in gaps:
            y[(ticks > tv[g]) & (ticks < tv[g + 1])] = np.nan
        if len(gaps):
            longest = float(np.max(np.diff(tv)[gaps]))
            notes.append(f"{signal.name}: {len(gaps)} gaps (longest {longest:.3g} s, first at "
                         f"{tv[gaps[0]]:.4g} s) left without data")
        signals[signal.name] = y
        units[signal.name] = column.unit or ""
    if not signals:
        raise MeasurementError(label, "", f"no signal of line {line.name!r} with data in the "
                               "file")
    _check_length(line, label, float(ticks[-1]), len(t_ok))
    return Measurements(label, line, ticks, signals, units, period, offset, tuple(notes))


def line_dt(line: Line | BranchedLine) -> float:
    """The line's controller period [s]."""
    return 1.0 / float(line.spec.control.sample_rate)


def slowest_loop(line: Line | BranchedLine) -> float:
    """Time constant [s] of the line's slowest controller loop (1 / the lowest bandwidth of
    any controller), 1 s where no controller states one."""
    rates = []
    for roller in line.spec.rollers:
        controller = getattr(roller, "controller", None)
        for key in ("speed_bandwidth", "tension_bandwidth"):
            value = getattr(controller, key, None)
            if isinstance(value, int | float) and value > 0:
                rates.append(float(value))
    return 1.0 / min(rates) if rates else 1.0


def _check_length(line: Line | BranchedLine, label: str, duration: float, samples: int) -> None:
    need = MIN_TIME_CONSTANTS * slowest_loop(line)
    if duration < need or samples < MIN_SAMPLES:
        raise MeasurementError(label, "time", (
            f"{duration:.3g} s of data ({samples} samples) is too short to identify anything: "
            f"inertias, friction, the web's modulus and dancer damping show only over "
            f"{MIN_TIME_CONSTANTS:g} time constants of the slowest control loop "
            f"({need:.3g} s) and at least {MIN_SAMPLES} samples"))


def _renamed(columns: list[RawColumn], mapping: dict[str, str], label: str) -> list[RawColumn]:
    names = {c.name for c in columns} | {c.header for c in columns}
    for foreign in mapping:
        if foreign not in names:
            raise MeasurementError(label, foreign, "mapped, but no such column in the file"
                                   + suggestions(foreign, sorted(names)))
    out = []
    for c in columns:
        target = mapping.get(c.header, mapping.get(c.name))
        if target == "":
            continue
        out.append(c if target is None else RawColumn(c.header, target, c.unit, c.values))
    return out


def _seconds(column: RawColumn, label: str) -> np.ndarray:
    from webline.units import to_si

    unit = column.unit or "s"
    try:
        factor = to_si(f"1 {unit}", "time")
    except ValueError:
        raise MeasurementError(label, column.header, f"unit {unit!r} is not a time unit "
                               "(s, ms, min)") from None
    return column.values * factor


def _si_factor(column: RawColumn, signal: Signal, label: str) -> float:
    from webline.units import SI_UNITS, to_si

    if not column.unit:
        return 1.0
    try:
        return to_si(f"1 {column.unit}", signal.unit_kind)
    except ValueError:
        kind = signal.unit_kind.replace("_", " ")
        raise MeasurementError(label, column.header, (
            f"unit {column.unit!r} is not a {kind}: {signal.kind} is a {kind} "
            f"({SI_UNITS[signal.unit_kind]})")) from None
