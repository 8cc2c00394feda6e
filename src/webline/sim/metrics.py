"""Per-run metrics of a study: one number per span, drive or node, as a sweep stores them.

The definitions are those of a single run's summary and verdict: tension error against the
loadcell reference (``Result.tension_ref``, NaN on spans without a loadcell), event times
from ``Result.events`` (``webline.sim.events``: intervals of records) and the verdict status
(``Result.verdict``). ``result_metrics`` computes them from a ``Result``; the batched kernel
(``webline.sim.batch``) reduces the same records to the same numbers inside compiled code.
"""

from __future__ import annotations

import math

import numpy as np

from webline.sim.result import Result

#: A tension is settled within this fraction of its reference [1]; ``settling_time`` is the
#: last recorded time [s] it was outside (0 if never; inf if still outside at the end).
SETTLE_BAND = 0.02

#: metric name -> (element dimension, units, description)
METRICS: dict[str, tuple[str, str, str]] = {
    "tension_rms_error": ("span", "N", "RMS of tension minus loadcell reference"),
    "tension_peak_error": ("span", "N", "largest |tension - loadcell reference|"),
    "tension_min": ("span", "N", "smallest tension"),
    "tension_max": ("span", "N", "largest tension"),
    "settling_time": ("span", "s",
                      f"last time |tension error| > {SETTLE_BAND:.0%} of the reference"),
    "slack_time": ("span", "s", "time the span was slack"),
    "torque_limit_time": ("drive", "s", "time the torque command sat at its limit"),
    "slip_time": ("node", "s", "time the web slipped over the roller"),
}


def result_metrics(result: Result) -> dict[str, np.ndarray]:
    """The metrics (``METRICS``) of one run, plus ``status`` (the verdict's) [SI]."""
    tension, ref, time = result.tension, result.tension_ref, result.time
    error = tension - ref
    loadcell = np.all(np.isfinite(ref), axis=0)
    n_s = tension.shape[1]
    rms = np.full(n_s, math.nan)
    peak = np.full(n_s, math.nan)
    settle = np.full(n_s, math.nan)
    for k in np.flatnonzero(loadcell):
        rms[k] = np.sqrt(np.mean(error[:, k] ** 2))
        peak[k] = np.abs(error[:, k]).max()
        outside = np.flatnonzero(np.abs(error[:, k]) > SETTLE_BAND * np.abs(ref[:, k]))
        settle[k] = (0.0 if outside.size == 0 else
                     math.inf if outside[-1] == len(time) - 1 else float(time[outside[-1]]))
    totals = {(e.kind, e.where): e.total for e in result.events}

    def event_time(kind: str, names: list[str]) -> np.ndarray:
        return np.array([totals.get((kind, name), 0.0) for name in names])

    return {"tension_rms_error": rms, "tension_peak_error": peak,
            "tension_min": tension.min(axis=0), "tension_max": tension.max(axis=0),
            "settling_time": settle,
            "slack_time": event_time("slack", result.span_names),
            "torque_limit_time": event_time("torque_limit", result.drive_names),
            "slip_time": event_time("slip", result.node_names),
            "status": np.array(result.status)}
