"""The benchmark's metrics, each defined once here (name, unit, definition) and printed in
the report as written here. Integrals are trapezoids over the run's records (every controller
tick). Lower is better for every metric.

The tension band of the settling time is ``sim.results.metrics.SETTLE_BAND`` (2 %), the one
a run's own summary uses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from webline.sim.results.metrics import SETTLE_BAND

if TYPE_CHECKING:
    from webline.sim.results.result import Result


@dataclass(frozen=True)
class Metric:
    """A metric's ``name``, ``unit`` and ``definition`` (its formula in words); ``ranked``:
    whether it enters the ranking."""

    name: str
    unit: str
    definition: str
    ranked: bool = True


#: the metrics of one run, in the report's order
RUN_METRICS: tuple[Metric, ...] = (
    Metric("tension_iae", "N·s", "Σ over loadcell spans k of ∫ |T_k − T_ref,k| dt over the "
           "run (T: the true span tension, T_ref: its reference)", ranked=False),
    Metric("tension_iae_rel", "%·s", "Σ over loadcell spans k of ∫ |T_k − T_ref,k| / "
           "|T_ref,k| dt x 100: the tension IAE of each zone normalised by its reference"),
    Metric("tension_peak", "N", "max over loadcell spans and time of |T_k − T_ref,k|",
           ranked=False),
    Metric("tension_peak_pct", "%", "max over loadcell spans and time of |T_k − T_ref,k| / "
           "|T_ref,k| x 100"),
    Metric("settling_time", "s", f"the last recorded time at or after the case's onset t₀ at "
           f"which any loadcell span's |T_k − T_ref,k| exceeds {SETTLE_BAND:.0%} of "
           f"|T_ref,k|, less t₀ (0 if never; inf if still outside at the end)"),
    Metric("speed_iae", "m", "∫ |v − v_ref| dt of the master drive: its web speed against "
           "the line-speed reference"),
    Metric("torque_rms", "N·m", "√(mean over drives d and time of (τ_d(t) − τ_d(0))²): "
           "the motor torques' RMS deviation from the equilibrium command the run starts at "
           "(the torque that holds the line is the same for every controller)"),
    Metric("energy", "J", "Σ over drives d of ∫ |τ_d ω_d| dt: the motors' absolute "
           "mechanical work (τ motor torque, ω motor speed)"),
)

#: the metrics of a Monte Carlo case, over its samples, per contender
ROBUSTNESS_METRICS: tuple[Metric, ...] = (
    Metric("tension_iae_rel_mean", "%·s", "mean over the samples of tension_iae_rel",
           ranked=False),
    Metric("tension_iae_rel_worst", "%·s", "largest tension_iae_rel over the samples "
           "(worst case)"),
    Metric("tension_iae_rel_spread", "%·s", "standard deviation of tension_iae_rel over "
           "the samples (ddof = 1)"),
    Metric("tension_peak_pct_worst", "%", "largest tension_peak_pct over the samples"),
    Metric("failures", "1", "samples whose run failed (a failed sample is left out of the "
           "other robustness metrics)"),
)

METRICS: dict[str, Metric] = {m.name: m for m in RUN_METRICS + ROBUSTNESS_METRICS}


def integral(time: np.ndarray, values: np.ndarray) -> float:
    """∫ values dt by the trapezoid rule over ``time`` [s] (values 1-D)."""
    return float(np.trapezoid(values, time)) if len(time) > 1 else 0.0


def tension_scores(time: np.ndarray, tension: np.ndarray, tension_ref: np.ndarray,
                   onset: float = 0.0) -> dict[str, float]:
    """``tension_iae`` [N·s], ``tension_iae_rel`` [%·s], ``tension_peak`` [N],
    ``tension_peak_pct`` [%] and ``settling_time`` [s] (from ``onset`` [s]) of records at
    ``time`` [s] of span tensions and references [N] (records x spans; spans whose reference
    is NaN have no loadcell and are left out)."""
    loadcell = np.flatnonzero(np.all(np.isfinite(tension_ref), axis=0))
    error = np.abs(tension[:, loadcell] - tension_ref[:, loadcell])
    relative = error / np.abs(tension_ref[:, loadcell])
    outside = np.flatnonzero(np.any(relative > SETTLE_BAND, axis=1) & (time >= onset))
    settle = (0.0 if outside.size == 0 else math.inf if outside[-1] == len(time) - 1
              else float(time[outside[-1]]) - onset)
    return {"tension_iae": sum(integral(time, e) for e in error.T),
            "tension_iae_rel": 100.0 * sum(integral(time, r) for r in relative.T),
            "tension_peak": float(error.max(initial=0.0)),
            "tension_peak_pct": 100.0 * float(relative.max(initial=0.0)),
            "settling_time": settle}


def effort_scores(time: np.ndarray, torque: np.ndarray,
                  motor_speed: np.ndarray) -> dict[str, float]:
    """``torque_rms`` [N·m] and ``energy`` [J] of records at ``time`` [s] of motor torques
    [N·m] and motor speeds [rad/s] (records x drives)."""
    deviation = torque - torque[0]
    return {"torque_rms": float(np.sqrt(np.mean(deviation**2))),
            "energy": sum(integral(time, p) for p in np.abs(torque * motor_speed).T)}


def speed_scores(time: np.ndarray, speed: np.ndarray, speed_ref: np.ndarray) -> dict[str, float]:
    """``speed_iae`` [m] of the master drive's web speed and its reference [m/s] at ``time``."""
    return {"speed_iae": integral(time, np.abs(speed - speed_ref))}


def run_scores(result: Result, onset: float) -> dict[str, float]:
    """Every metric of ``RUN_METRICS`` of a run, settling measured from ``onset`` [s]."""
    time = result.time
    master = result.line.drives.index(result.line.master)
    return {**tension_scores(time, result.tension, result.tension_ref, onset),
            **speed_scores(time, result.drive_speed[:, master],
                           result.speed_feedforward[:, master]),
            **effort_scores(time, result.torque, result.motor_speed)}


def robustness_scores(samples: list[dict[str, float] | None]) -> dict[str, float]:
    """The ``ROBUSTNESS_METRICS`` of a Monte Carlo case's runs (None: a failed sample)."""
    done = [s for s in samples if s is not None]
    iae = np.array([s["tension_iae_rel"] for s in done])
    peak = np.array([s["tension_peak_pct"] for s in done])
    nan = math.nan
    return {"tension_iae_rel_mean": float(iae.mean()) if iae.size else nan,
            "tension_iae_rel_worst": float(iae.max()) if iae.size else nan,
            "tension_iae_rel_spread": float(iae.std(ddof=1)) if iae.size > 1 else nan,
            "tension_peak_pct_worst": float(peak.max()) if peak.size else nan,
            "failures": float(len(samples) - len(done))}
