"""The line as the measurements drove it: its speed reference, tension set points and initial
roll radii replaced by what the file logged, so a simulation sees the run the data saw."""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from webline.errors import LineFileError
from webline.line import Line
from webline.twin.traces.layout import layout
from webline.twin.traces.measurements import Measurements
from webline.twin.traces.read import MeasurementError

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine

#: most points of a reference table built from a logged reference
MAX_TABLE = 2000
#: a corner of a logged reference: its second difference over the ticks (the change of slope
#: times the tick) above this share of its largest value; below it is the log's rounding (a
#: 9-digit CSV: 2e-9, float32: 2e-7), not a corner (a ramp of 0.1 % of the scale per second
#: starting on 1 ms ticks is 1e-6)
BEND = 1e-6
#: a logged tension set point replaces the line's only where it differs by more than this
#: share of the line's (a logged copy of the line's own set point changes nothing)
SET_POINT_CHANGE = 0.005


@dataclass(frozen=True)
class Driven:
    """The line driven by the data and, one per line, what was taken from the data."""

    line: Line | BranchedLine
    notes: tuple[str, ...]


def reference_table(time: np.ndarray, values: np.ndarray) -> dict[str, object]:
    """A ``table`` profile (SI) following a logged reference: its corners where it is
    piecewise linear (a ramp logged exactly, or ``twin.traces.ramps``'s reconstruction),
    else bin means of at most ``MAX_TABLE`` points (a noisy or curved log); one point past
    the end continues the last slope (a ramp cut by the end of the record still has its
    rate there, as the inertia compensation needs)."""
    ok = np.isfinite(values)
    t, v = time[ok], values[ok]
    scale = max(float(np.max(np.abs(v))), 1e-12)
    bends = np.flatnonzero(np.abs(np.diff(v, 2)) > BEND * scale) + 1
    knots = np.unique(np.concatenate([[0], bends - 1, bends, bends + 1, [len(t) - 1]]))
    knots = knots[(knots >= 0) & (knots < len(t))]
    bins = MAX_TABLE
    if len(knots) <= MAX_TABLE:
        tt, vv = t[knots], v[knots]
    else:
        edges = np.linspace(0, len(t), bins + 1).astype(int)
        tt = np.array([t[a:b].mean() for a, b in itertools.pairwise(edges)])
        vv = np.array([v[a:b].mean() for a, b in itertools.pairwise(edges)])
        tt[0], tt[-1] = t[0], t[-1]
    if len(tt) >= 2:  # one more point on the last slope: the last tick sees the same rate
        slope = (vv[-1] - vv[-2]) / (tt[-1] - tt[-2])
        step = max(tt[-1] - tt[-2], 1e-3)
        last = vv[-1] + slope * step
        tt, vv = np.append(tt, tt[-1] + step), np.append(vv, last)
    vv = np.maximum(vv, 0.0)  # speed and tension references are >= 0 (a noisy zero is not)
    return {"type": "table", "time": [float(x) for x in tt], "value": [float(x) for x in vv]}


def driven_line(data: Measurements, line: Line | BranchedLine | None = None) -> Driven:
    """``line`` (default: the data's; single-path or branched) with the logged references of
    ``data`` swapped in: line speed from ``speed_ref[MASTER]`` (else reconstructed from the
    master roller's measured ``speed``), each loadcell span's tension set point from
    ``tension_ref[SPAN]`` where it differs from the line's (zones with a taper keep the
    line's: the logged reference includes the taper), the rolls' radii from ``radius[...]``
    at t = 0 (``twin.traces.layout`` names them and their paths)."""
    line = data.line if line is None else line
    view = layout(line)
    changes: dict[str, object] = {}
    notes = []
    reference, measured = f"speed_ref[{view.master}]", f"speed[{view.master}]"
    if reference in data.signals and np.isfinite(data.signals[reference]).any():
        changes["speed"] = reference_table(data.time, data.signals[reference])
        notes.append(f"line speed from {reference} (logged speed reference)")
    elif measured in data.signals:
        from webline.twin.traces.ramps import reconstructed
        from webline.twin.traces.weights import noise_level

        # at the file's own samples: the ticks between them are interpolated, not measured
        values, times = data.signals[measured][::data.stride], data.time[::data.stride]
        t, v, how = reconstructed(times, values, noise_level(values))
        changes["speed"] = reference_table(t, v)
        notes.append(f"line speed: no speed reference logged; reconstructed from {measured}, "
                     f"the master roller's measured speed: {how}")
    else:
        notes.append("line speed: the line's own reference (no speed_ref or master speed "
                     "logged)")
    for point in view.set_points:
        name = f"tension_ref[{point.span}]"
        if name not in data.signals or not isinstance(point.value, int | float):
            continue
        logged = data.signals[name]
        if np.nanmax(np.abs(logged - point.value)) > SET_POINT_CHANGE * abs(point.value):
            if point.tapered:
                notes.append(f"{name}: a tapered zone keeps the line's set point and taper")
                continue
            changes[point.path] = reference_table(data.time, logged)
            notes.append(f"tension set point of {point.span} from {name}")
    for roll in view.rolls:
        if roll.signal not in data.signals or not np.isfinite(data.signals[roll.signal][0]):
            continue
        radius = float(data.signals[roll.signal][0])
        if abs(radius - roll.radius) <= 1e-4:
            continue
        if roll.path:
            changes[roll.path] = radius
            notes.append(f"initial radius from {roll.signal}: {radius:.4g} m")
        else:
            notes.append(f"{roll.signal}: a lane on a shaft of several keeps the line's "
                         f"radius ({roll.radius:.4g} m; logged {radius:.4g} m)")
    try:
        driven = line.replace(changes) if changes else line
    except LineFileError as exc:  # a logged reference the line file cannot take
        raise MeasurementError(data.source, exc.key, f"the logged references cannot drive "
                               f"line {line.name!r}: {exc.problem}") from None
    return Driven(driven, tuple(notes))
