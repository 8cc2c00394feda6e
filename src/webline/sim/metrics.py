"""Per-run metrics of a study: one number per span, drive or node, as a sweep stores them.

The definitions are those of a single run's summary and verdict: tension error against the
loadcell reference (``Result.tension_ref``, NaN on spans without a loadcell), event times
from ``Result.events`` (``webline.sim.events``: intervals of records) and the verdict status
(``Result.verdict``). ``run_metrics`` computes them from a run's records; the batched kernel
(``webline.sim.batch``) reduces the same records to the same numbers inside compiled code.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

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


def run_metrics(time: np.ndarray, tension: np.ndarray, tension_ref: np.ndarray,
                event_totals: Mapping[tuple[str, str], float],
                names: Mapping[str, list[str]]) -> dict[str, np.ndarray]:
    """The metrics (``METRICS``) of one run from its records: time [s], span tension and its
    reference [N] (records x spans; a reference NaN throughout: no loadcell, NaN errors),
    the total time [s] of each (event kind, element name), and the element names per
    dimension ("span", "drive", "node")."""
    error = tension - tension_ref
    loadcell = np.all(np.isfinite(tension_ref), axis=0)
    n_s = tension.shape[1]
    rms, peak, settle = (np.full(n_s, math.nan) for _ in range(3))
    for k in np.flatnonzero(loadcell):
        rms[k] = np.sqrt(np.mean(error[:, k] ** 2))
        peak[k] = np.abs(error[:, k]).max()
        outside = np.flatnonzero(np.abs(error[:, k]) > SETTLE_BAND * np.abs(tension_ref[:, k]))
        settle[k] = (0.0 if outside.size == 0 else
                     math.inf if outside[-1] == len(time) - 1 else float(time[outside[-1]]))

    def event_time(kind: str, dim: str) -> np.ndarray:
        return np.array([event_totals.get((kind, name), 0.0) for name in names[dim]])

    return {"tension_rms_error": rms, "tension_peak_error": peak,
            "tension_min": tension.min(axis=0), "tension_max": tension.max(axis=0),
            "settling_time": settle, "slack_time": event_time("slack", "span"),
            "torque_limit_time": event_time("torque_limit", "drive"),
            "slip_time": event_time("slip", "node")}


def by_element(values: Mapping[str, np.ndarray],
               names: Mapping[str, list[str]]) -> dict[str, dict[str, float]]:
    """Each metric of ``values`` as {element name: value}, names per dimension as in
    ``run_metrics``."""
    return {name: dict(zip(names[dim], map(float, values[name]), strict=True))
            for name, (dim, _, _) in METRICS.items()}
