"""Per-run metrics of a study: one number per span, drive or node, as a sweep stores them.

The definitions are those of a single run's summary and verdict: tension error against the
loadcell reference (``Result.tension_ref``, NaN on spans without a loadcell), event times
from ``Result.events`` (``webline.sim.results.events``: intervals of records) and the verdict status
(``Result.verdict``). ``run_metrics`` computes them from a run's records; the batched kernel
(``webline.sim.sweeps.batch``) reduces the same records to the same numbers inside compiled code.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

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


def metrics_table(values: Mapping[str, np.ndarray], names: Mapping[str, list[str]],
                  status: str):
    """The metrics of ``values`` (``run_metrics``) as a tidy ``pandas.DataFrame``: one row per
    element and metric, columns ``element``, ``metric``, ``value``, ``unit`` (``METRICS``'s);
    the verdict ``status`` in ``attrs``."""
    import pandas as pd

    rows = [(element, name, float(value), unit)
            for name, (dim, unit, _) in METRICS.items()
            for element, value in zip(names[dim], values[name], strict=True)]
    table = pd.DataFrame(rows, columns=["element", "metric", "value", "unit"])
    table.attrs["status"] = status
    return table


def run_summary(result: Any) -> dict[str, dict[str, dict[str, float]]]:
    """``Result.summary()`` of ``result`` (which imports this module): per span its tension
    mean, standard deviation and, with a loadcell, mean, largest and RMS error [N]; per drive
    the mean of its speed reference [m/s] (an open-loop drive's: its limiter's), its speed
    error's mean, standard deviation and largest value [m/s] against its reference
    and its largest torque [N·m]."""
    spans = {}
    for k, name in enumerate(result.span_names):
        tension = result.tension[:, k]
        ref = result.tension_ref[:, k]
        entry = {"mean": float(tension.mean()), "std": float(tension.std())}
        if np.all(np.isfinite(ref)):
            error = tension - ref
            entry |= {"mean_error": float(error.mean()),
                      "max_abs_error": float(np.abs(error).max()),
                      "rms_error": float(np.sqrt(np.mean(error**2)))}
        spans[name] = entry
    drives = {}
    for d, name in enumerate(result.drive_names):
        error = result.drive_speed[:, d] - result.speed_ref[:, d]
        drives[name] = {"mean_reference": float(result.speed_ref[:, d].mean()),
                        "mean_error": float(error.mean()), "std_error": float(error.std()),
                        "max_abs_error": float(np.abs(error).max()),
                        "max_abs_torque": float(np.abs(result.torque[:, d]).max())}
    return {"spans": spans, "drives": drives}

