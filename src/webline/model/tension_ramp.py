"""The tension ramp at start and stop (docs/winder.md, R1): every zone's set tension runs
from a standstill fraction up to the running value when the line starts, and back when it
stops, at a fixed rate, as winder programs ramp their tension set point.

The line stands while its speed reference |v_ref(t)| <= ``below``; the factor f(t) on every
zone's reference moves towards 1 while the line runs and towards ``standstill`` while it
stands, at the rate (1 - standstill)/``time``, and starts where it would rest (f = 1 for a
line that starts running, ``standstill`` for one at rest). The speed reference is piecewise
linear, so its crossings of ±below are exact and f is piecewise linear too: a profile the
compiled loop reads like any other.
"""

from __future__ import annotations

import numpy as np

from webline.profiles import breakpoints, pwl_value


def _switches(times: np.ndarray, values: np.ndarray, below: float) -> list[tuple[float, bool]]:
    """(time [s], running after it) of every change of |v| > ``below`` along the PWL speed
    profile (``times``, ``values``), in time order."""
    out: list[tuple[float, bool]] = []
    running = abs(values[0]) > below
    for k in range(len(times) - 1):
        t0, t1, v0, v1 = times[k], times[k + 1], values[k], values[k + 1]
        if t1 <= t0 or v0 == v1:
            continue
        crossings = sorted(t0 + (level - v0) / (v1 - v0) * (t1 - t0) for level in (below, -below)
                           if min(v0, v1) <= level <= max(v0, v1))
        for t in crossings:
            after = abs(v0 + (v1 - v0) * min((t - t0) / (t1 - t0) + 1e-12, 1.0)) > below
            if after != running:
                out.append((float(t), after))
                running = after
    return out


def ramp_profile(speed: object, ramp: object) -> tuple[np.ndarray, np.ndarray]:
    """(times [s], factors [-]) of the tension ramp ``ramp`` (``spec.winder.StartStopTension``)
    along the line-speed ``speed`` profile (R1)."""
    times, values = breakpoints(speed)
    low, duration, below = ramp.standstill, ramp.time, ramp.below  # type: ignore[attr-defined]
    rate = (1.0 - low) / duration
    target = 1.0 if abs(values[0]) > below else low
    now, level = 0.0, target
    points = [(now, level)]
    for when, running in [*_switches(times, values, below), (np.inf, None)]:
        if level != target:  # move towards the target until it is reached or it changes
            reach = now + abs(target - level) / rate
            if reach <= when:
                points.append((reach, target))
                now, level = reach, target
        if running is None:
            break
        if level != target:  # still moving: where it is at the switch
            level += (when - now) * rate * (1.0 if target > level else -1.0)
            points.append((when, level))
        elif when > now:
            points.append((when, level))
        now, target = when, (1.0 if running else low)
    return np.array([p[0] for p in points]), np.array([p[1] for p in points])


def ramp_factor(line: object, t: float | np.ndarray) -> float | np.ndarray:
    """The ramp's factor on every zone's tension reference at ``t`` [s] (1 without one)."""
    spec = line.spec  # type: ignore[attr-defined]
    ramp = spec.control.tension_ramp
    if ramp is None:
        return 1.0 if np.isscalar(t) else np.ones_like(t)
    times, values = ramp_profile(spec.speed, ramp)
    if np.isscalar(t):
        return float(pwl_value(times, values, float(t)))  # type: ignore[arg-type]
    return np.interp(t, times, values)
