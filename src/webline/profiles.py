"""Reference profiles (constant, ramp, steps, table) as piecewise-linear breakpoint arrays."""

from __future__ import annotations

import numpy as np


def breakpoints(profile: object) -> tuple[np.ndarray, np.ndarray]:
    """(times [s], values [SI]) of a spec profile; a step is two points at the same time."""
    if isinstance(profile, float | int):
        return np.array([0.0]), np.array([float(profile)])
    kind = getattr(profile, "type", None)
    if kind == "ramp":
        t0 = profile.start  # type: ignore[attr-defined]
        return (np.array([t0, t0 + profile.duration]),  # type: ignore[attr-defined]
                np.array([profile.initial, profile.final]))  # type: ignore[attr-defined]
    if kind == "steps":
        times, values = [0.0], [profile.initial]  # type: ignore[attr-defined]
        for step in profile.steps:  # type: ignore[attr-defined]
            times += [step.time, step.time]
            values += [values[-1], step.value]
        return np.array(times), np.array(values)
    if kind == "table":
        return np.asarray(profile.time, float), np.asarray(profile.value, float)  # type: ignore[attr-defined]
    raise TypeError(f"not a profile: {profile!r}")


def pwl_value(times: np.ndarray, values: np.ndarray, t: float) -> float:
    """Value at time ``t`` [s] of the piecewise-linear profile; constant outside its range.

    At a repeated time (a step) the later value holds.
    """
    n = times.shape[0]
    if t < times[0]:
        return values[0]
    if t >= times[n - 1]:
        return values[n - 1]
    j = np.searchsorted(times, t, "right") - 1
    span = times[j + 1] - times[j]
    return values[j] + (values[j + 1] - values[j]) * (t - times[j]) / span


def pwl_slope(times: np.ndarray, values: np.ndarray, t: float) -> float:
    """Rate of change [SI/s] of the profile at ``t`` (0 outside it and on steps)."""
    n = times.shape[0]
    if t < times[0] or t >= times[n - 1]:
        return 0.0
    j = np.searchsorted(times, t, "right") - 1
    span = times[j + 1] - times[j]
    return (values[j + 1] - values[j]) / span if span > 0 else 0.0
