"""The timing and logging of an identification test's steps, from the line's linearized
closed loop (``sim.linear.linearize`` for a chain, ``sim.branches.linear`` for a branched
line: both give a ``LinearModel`` whose states include each drive's ``NAME_torque``).

A reference step applied as a ramp of duration T_r is the step response y(t) averaged over a
window T_r (linearity): r(t) = (Y(t) - Y(t - T_r)) / T_r with Y the step response's integral.
So one step response, computed once, gives for every candidate ramp

* the drives' torques: the shortest ramp whose torques stay within ``TORQUE_SHARE`` of each
  drive's limit, from the operating point's torque, going up and coming back;
* the settling time: the last time any logged signal (tensions, speeds, torques) is outside
  ``SETTLE_BAND`` of its steady change (of ``SETTLE_BAND`` of its largest excursion where
  it has almost none);
* the logging rate: ``SAMPLES_PER_PERIOD`` samples per period of the fastest closed-loop mode
  that moves a logged signal by more than its sensor noise (``twin.traces.synthetic.NOISE``:
  a mode below the noise cannot be resolved, one above it must be, or the record aliases
  it); a mode of rate λ contributes its step residue times |e^{λ T_r} - 1| / |λ T_r| after
  the ramp (a slow ramp hides the fast modes), and as many samples across the ramp itself.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from webline.sim.linear.linearize import LinearModel
from webline.twin.traces.synthetic import NOISE

#: a step's ramp keeps every drive's torque within this share of its limit (the rest is
#: margin for what the linear model leaves out: roll radii, friction's sign, the sampling)
TORQUE_SHARE = 0.8
#: settled: every logged signal within this share of its largest excursion of its final value
SETTLE_BAND = 0.01
#: samples per period of the fastest mode a test must resolve (and across a ramp)
SAMPLES_PER_PERIOD = 10.0
#: ramps are multiples of this [s] (times an engineer types)
RAMP_GRID = 0.05
#: the step response is computed over this many slowest time constants, and at most
HORIZON_DECAYS, HORIZON_MAX = 10.0, 300.0


@dataclass(frozen=True)
class StepDesign:
    """A reference step laid out as a ramp: its duration ``ramp`` [s], the time from the
    ramp's start until every logged signal has settled [s], the largest torque over its
    limit during the ramp up and back (``peak_share``, and the drive), the logging rate it
    needs [Hz] and the fastest mode that sets it (its rate [rad/s] and dominant state)."""

    ramp: float
    settle: float
    peak_share: float
    peak_drive: str
    rate: float
    fastest: float
    fastest_state: str

    def words(self) -> str:
        """One line for the derivation."""
        short = (f" (above the {100 * TORQUE_SHARE:.0f} % aimed at: the operating point "
                 "leaves too little)" if self.peak_share > TORQUE_SHARE else "")
        return (f"ramp {self.ramp:g} s (torques at most {100 * self.peak_share:.0f} % of "
                f"the limit, {self.peak_drive}{short}), settled {self.settle:.3g} s after "
                f"its start (linearized closed loop)")


def nice_rate(rate: float) -> float:
    """``rate`` [Hz] rounded up to 1, 2 or 5 times a power of ten (what loggers offer)."""
    decade = 10.0 ** math.floor(math.log10(rate))
    return next(m * decade for m in (1.0, 2.0, 5.0, 10.0) if m * decade >= rate * (1 - 1e-9))


def logged_rows(model: LinearModel, drives: Sequence[str]
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rows mapping the state to the logged signals: the model's outputs, then each drive's
    torque; the torque rows' indices among them; each signal's noise level [SI])."""
    picks = np.zeros((len(drives), len(model.states)))
    for d, name in enumerate(drives):
        picks[d, model.states.index(f"{name}_torque")] = 1.0
    rows = np.vstack([model.c, picks])
    kinds = ["tension" if o.endswith("_tension") else "speed" for o in model.outputs]
    noise = np.array([NOISE[k] for k in kinds + ["torque"] * len(drives)])
    return rows, np.arange(model.c.shape[0], rows.shape[0]), noise


def _step_response(a: np.ndarray, b: np.ndarray, horizon: float, steps: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(time [s], state) of dx/dt = a x + b for a unit step from rest (exact zero-order hold
    discretisation: the step is constant)."""
    n = a.shape[0]
    dt = horizon / steps
    aug = np.zeros((n + 1, n + 1))
    aug[:n, :n], aug[:n, n] = a, b
    phi = scipy.linalg.expm(aug * dt)
    x = np.zeros((steps + 1, n))
    for k in range(steps):
        x[k + 1] = phi[:n, :n] @ x[k] + phi[:n, n]
    return np.arange(steps + 1) * dt, x


def design_step(model: LinearModel, steps: Mapping[str, float], drives: Sequence[str],
                torque: np.ndarray, limit: np.ndarray, ramp: float | None = None) -> StepDesign:
    """Steps of the closed loop ``model``'s inputs (``steps``: name -> size [input units]),
    together, applied as a ramp: the shortest multiple of ``RAMP_GRID`` [s] that keeps each
    drive's torque (``drives``' names; ``torque`` [N·m] at the operating point, ``limit``
    [N·m]) within ``TORQUE_SHARE`` of its limit on the way up and back, or the given
    ``ramp`` [s]; its settling time and logging rate (module docstring)."""
    u = np.zeros(len(model.inputs))
    for name, size in steps.items():
        u[model.inputs.index(name)] = size
    values, right = np.linalg.eig(model.a)
    rates = np.abs(values.real)
    slowest = float(np.min(rates[rates > 1e-9 * rates.max()]))
    horizon = min(HORIZON_DECAYS / slowest, HORIZON_MAX)
    ticks = int(min(max(20.0 * horizon * float(np.abs(values).max()), 2000), 40000))
    t, x = _step_response(model.a, model.b @ u, horizon, ticks)
    rows, torque_rows, noise = logged_rows(model, drives)
    y = x @ rows.T  # [time, signal]
    dt = t[1]
    integral = np.vstack([np.zeros(y.shape[1]), np.cumsum((y[1:] + y[:-1]) * dt / 2, axis=0)])
    final = y[-1]

    def ramped(width: float) -> tuple[np.ndarray, np.ndarray]:
        """(time, response) to the ramp of ``width`` [s], on past its end by the horizon."""
        lag = max(1, round(width / dt))
        tail = integral[-1] + final * dt * np.arange(1, lag + 1)[:, None]
        whole = np.vstack([integral, tail])
        behind = np.vstack([np.zeros((lag, y.shape[1])), whole[:len(whole) - lag]])
        return np.arange(len(whole)) * dt, (whole - behind) / width

    def peak(response: np.ndarray) -> tuple[float, int]:
        tq = response[:, torque_rows]
        up = np.abs(torque + tq) / limit  # the ramp up from the operating point
        down = np.abs(torque + final[torque_rows] - tq) / limit  # and back
        share = np.maximum(up.max(axis=0), down.max(axis=0))
        return float(share.max()), int(np.argmax(share))

    candidates = [ramp] if ramp is not None else list(
        RAMP_GRID * np.arange(1, int(horizon / RAMP_GRID) + 1))
    for width in candidates:
        time, response = ramped(width)
        share, worst = peak(response)
        if share <= TORQUE_SHARE:
            break
    settle = _settled(time, response)
    fastest, state = _fastest_seen(model, values, right, u, rows, noise, width)
    rate = nice_rate(SAMPLES_PER_PERIOD * max(fastest / (2 * math.pi), 1.0 / width))
    return StepDesign(float(width), settle, share, drives[worst], rate, fastest, state)


def _settled(time: np.ndarray, response: np.ndarray) -> float:
    """The last time [s] any signal of ``response`` [time, signal] is outside
    ``SETTLE_BAND`` of its steady change (a draw's speed change is ~T/EA of the speed's
    transient: a hold read for it must wait for that), or of ``SETTLE_BAND`` of its largest
    excursion where it comes back (nearly) to where it was."""
    away = np.abs(response - response[-1])
    size = away.max(axis=0)
    moving = size > 1e-12 * max(float(np.abs(response).max()), 1e-300)
    band = SETTLE_BAND * np.maximum(np.abs(response[-1]), SETTLE_BAND * size)
    outside = np.any(away[:, moving] > band[moving], axis=1)
    return float(time[np.flatnonzero(outside)[-1] + 1]) if outside.any() else 0.0


def _fastest_seen(model: LinearModel, values: np.ndarray, right: np.ndarray, u: np.ndarray,
                  rows: np.ndarray, noise: np.ndarray, width: float) -> tuple[float, str]:
    """(|λ| [rad/s], dominant state) of the fastest mode whose contribution to some logged
    signal exceeds that signal's ``noise`` after a ramp of ``width`` [s] (0, "" if none)."""
    left = np.linalg.inv(right)
    best, state = 0.0, ""
    for j, value in enumerate(values):
        residue = (rows @ right[:, j]) * (left[j] @ model.b @ u) / value
        ramp = abs((np.exp(value * width) - 1.0) / (value * width)) if width > 0 else 1.0
        # a complex pair's two terms add to twice one's modulus
        amplitude = np.abs(residue) * ramp * (2.0 if value.imag != 0 else 1.0)
        if np.any(amplitude > noise) and abs(value) > best:
            best = float(abs(value))
            state = model.states[int(np.argmax(np.abs(right[:, j] * left[j])))]
    return best, state


def mode_rate(model: LinearModel) -> tuple[float, str]:
    """The logging rate [Hz] that resolves every mode of the closed loop ``model`` (for a
    test whose input is not one of its inputs), and why."""
    values = np.linalg.eigvals(model.a)
    fastest = float(np.abs(values).max())
    return (nice_rate(SAMPLES_PER_PERIOD * fastest / (2 * math.pi)),
            f"10 samples per period of the line's fastest closed-loop mode "
            f"({fastest / (2 * math.pi):.3g} Hz)")
