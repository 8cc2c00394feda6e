"""Closed-loop modes across the roll (docs/winder.md, "Modes across the roll"): the line
linearized at a modest number of points from the rolls as loaded until the unwind is empty,
along a scenario's course, or along a run's recorded roll radii, with the controllers as the
run has them (gains designed once, at the start; an inertia-adaptive speed loop follows J/r).

The course: every metre of web unwound is wound on the rewind, so with thickness δ the
radii follow d(R²)/dt = ∓δ v/π (6.6): after a length s of web

    R_u² = R_u0² - δ s / π,    R_r² = R_r0² + δ s / π                              (A1)

From empty to full, s runs from 0 to π (R_u0² - R_c²)/δ at the analysis speed; along a
scenario, s(t) = ∫ |v_ref| dt and each point is linearized at the references of its time.
A loop's mode (one that driven rollers' speeds, torques, transmissions, dancers or controller
integrals take at least ``LOOP_SHARE`` of) damped less than the threshold somewhere is a
``low_damping`` warning naming the diameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from webline.errors import WeblineError
from webline.line import Line
from webline.model.operating_point import analysis_time
from webline.profiles import breakpoints
from webline.sim.linear.linearize import linear_model
from webline.verdict import Finding

#: default number of points along the roll (the linearization costs ~10 ms a point)
POINTS = 20
#: a loop's mode damped less than this somewhere along the roll is a warning
DAMPING_THRESHOLD = 0.1
#: share of a mode's participation in the loop states that makes it a loop's mode; a mode of
#: idle rollers ringing on their spans, which no controller acts on, is not one
LOOP_SHARE = 0.2
#: a run whose unwind lost (or rewind gained) this share of its wound radius is a roll run:
#: its verdict and report take the modes along its recorded radii
ROLL_RUN = 0.1
LOOP_SUFFIXES = ("_integral", "_torque", "_motor_omega", "_twist", "_position", "_velocity")


@dataclass(frozen=True)
class RollModes:
    """Closed-loop modes at points along the roll: ``time`` [s], ``unwind_radius`` and
    ``rewind_radius`` [m] per point; per point its ``eigenvalues`` [1/s] (Im >= 0, slowest
    first), the ``dominant`` state of each and whether it is a ``loop`` mode; the damping
    ``threshold``."""

    time: np.ndarray
    unwind_radius: np.ndarray
    rewind_radius: np.ndarray
    eigenvalues: tuple[np.ndarray, ...]
    dominant: tuple[tuple[str, ...], ...]
    loop: tuple[tuple[bool, ...], ...]
    threshold: float

    def least_damped(self) -> list[int | None]:
        """Per point, the index of its oscillatory loop mode with the least damping."""
        out: list[int | None] = []
        for values, flags in zip(self.eigenvalues, self.loop, strict=True):
            found = [j for j, (v, f) in enumerate(zip(values, flags, strict=True))
                     if f and v.imag > 0.0]
            out.append(min(found, key=lambda j: _damping(complex(values[j])), default=None))
        return out

    def least_damping(self) -> np.ndarray:
        """Per point, the least damping of an oscillatory loop mode (NaN if none)."""
        return np.array([math.nan if j is None else _damping(complex(v[j]))
                         for v, j in zip(self.eigenvalues, self.least_damped(), strict=True)])

    def findings(self) -> list[Finding]:
        """A ``warning`` where a loop mode's damping falls below the threshold along the roll:
        the mode and diameters where it is least damped, and where the stretch begins."""
        least = self.least_damped()
        damping = self.least_damping()
        low = [p for p in range(len(least)) if damping[p] < self.threshold]
        if not low:
            return []
        worst = min(low, key=lambda p: damping[p])
        j = least[worst]
        assert j is not None
        value, name = self.eigenvalues[worst][j], self.dominant[worst][j]
        rewind = 2.0 * self.rewind_radius[low]
        message = (f"a closed-loop mode ({name}, {abs(value):.3g} rad/s) is damped only ζ = "
                   f"{damping[worst]:.3g} (< {self.threshold:g}) with the rewind at "
                   f"{2 * self.rewind_radius[worst]:.3g} m and the unwind at "
                   f"{2 * self.unwind_radius[worst]:.3g} m diameter; below the threshold at "
                   f"{len(low)} of {len(least)} points along the roll, rewind diameters "
                   f"{rewind.min():.3g}-{rewind.max():.3g} m")
        return [Finding("warning", "low_damping", name, message, float(self.time[worst]), {
            "damping_ratio": damping[worst], "natural_frequency_rad_s": abs(value),
            "rewind_diameter_m": 2 * float(self.rewind_radius[worst]),
            "unwind_diameter_m": 2 * float(self.unwind_radius[worst]),
            "threshold": self.threshold})]


def roll_course(line: Line, points: int = POINTS,
                duration: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time [s], unwind radius [m], rewind radius [m]) at ``points`` points (A1): from the
    rolls as loaded until the unwind is at its core, or along ``duration`` [s] of the line's
    speed reference."""
    u0, r0 = line.unwind.radius, line.rewind.radius
    core = line.unwind.core_radius
    per_length = line.spec.web.thickness / math.pi  # d(R²)/ds [m]
    if duration is None:
        length = np.linspace(0.0, (u0**2 - core**2) / per_length, points)
        time = np.full(points, analysis_time(line))
    else:
        times, values = breakpoints(line.spec.speed)
        fine = np.union1d(np.linspace(0.0, duration, 20 * points), times[times <= duration])
        speed = np.abs(np.interp(fine, times, values))  # pwl_value, vectorized
        wound = np.r_[0.0, np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(fine))]
        time = np.linspace(0.0, duration, points)
        length = np.interp(time, fine, wound)
    unwind = np.sqrt(np.maximum(u0**2 - per_length * length, core**2))
    rewind = np.sqrt(r0**2 + (u0**2 - unwind**2))
    return time, unwind, rewind


def roll_modes(line: Line, time: np.ndarray, unwind: np.ndarray, rewind: np.ndarray,
               threshold: float = DAMPING_THRESHOLD) -> RollModes:
    """The closed-loop modes of ``line`` at each (time [s], unwind radius, rewind radius [m])."""
    driven = {f"{line.node_name(i)}_omega" for i in line.drives}
    eigenvalues, dominant, loops = [], [], []
    for t, ru, rr in zip(time, unwind, rewind, strict=True):
        model = linear_model(line, float(t), loop="closed", unwind_radius=float(ru),
                             rewind_radius=float(rr))
        values, names, in_loop = classified_modes(model, driven)
        eigenvalues.append(values)
        dominant.append(names)
        loops.append(in_loop)
    return RollModes(np.asarray(time, dtype=float), np.asarray(unwind, dtype=float),
                     np.asarray(rewind, dtype=float), tuple(eigenvalues), tuple(dominant),
                     tuple(loops), threshold)


def is_roll_run(line: Line, unwind: np.ndarray, rewind: np.ndarray) -> bool:
    """Whether a run's recorded radii [m] changed by ``ROLL_RUN`` of the unwind's wound
    radius (R_u0 - R_c) or more: a run across (part of) a roll."""
    if len(unwind) < 2:
        return False
    wound = max(line.unwind.radius - line.unwind.core_radius, 1e-9)
    change = max(abs(unwind[-1] - unwind[0]), abs(rewind[-1] - rewind[0]))
    return bool(change >= ROLL_RUN * wound)


def run_roll_modes(line: Line, time: np.ndarray, unwind: np.ndarray,
                   rewind: np.ndarray, points: int = POINTS) -> RollModes | None:
    """The modes along a run's recorded course (record times [s], roll radii [m]) at
    ``points`` times, or None for a run that is no roll run (``is_roll_run``) or whose line
    has no operating point somewhere along it."""
    if not is_roll_run(line, unwind, rewind):
        return None
    at = np.linspace(float(time[0]), float(time[-1]), points)
    try:
        return roll_modes(line, at, np.interp(at, time, unwind), np.interp(at, time, rewind))
    except (WeblineError, ValueError, ArithmeticError, np.linalg.LinAlgError):
        return None


def _damping(value: complex) -> float:
    return -value.real / abs(value) if value else math.nan


def classified_modes(model: Any, driven: set[str]
                     ) -> tuple[np.ndarray, tuple[str, ...], tuple[bool, ...]]:
    """The modes of linear ``model`` (its ``a`` and ``states``) with Im >= 0, slowest first:
    their eigenvalues [1/s], each one's dominant state, and whether it belongs to the drives'
    loops (a share of at least ``LOOP_SHARE`` of its participation in the ``driven`` rollers'
    speeds and the controllers' states)."""
    loop = [k for k, name in enumerate(model.states)
            if name in driven or name.endswith(LOOP_SUFFIXES)]
    values, right = np.linalg.eig(np.asarray(model.a, dtype=float))
    participation = np.abs(right * np.linalg.inv(right).T)  # [state, mode]
    share = participation[loop].sum(axis=0) / participation.sum(axis=0)
    kept = sorted((j for j in range(len(values)) if values[j].imag >= 0.0),
                  key=lambda j: (abs(values[j]), values[j].imag))
    return (values[kept], tuple(model.states[int(np.argmax(participation[:, j]))] for j in kept),
            tuple(bool(share[j] >= LOOP_SHARE) for j in kept))
