"""Linear stability of a line with its controllers, as ``unstable`` findings of a verdict.

The closed-loop linear model of the plan (``sim.linearize.plan_linear_model``, cached on the
plan) at ``analysis_time`` is checked with plain eigenvalues first (cached too); only when a
mode has Re λ above the tolerance are eigenvectors computed, to name the states the mode lives
in (participation factors) and its likely cause.

Tolerance: the closed-loop model has exact zero eigenvalues (the unwind and rewind speeds of a
line at rest, integrators that only see each other), which LAPACK returns as |Re λ| of order
eps·‖A‖ (a defective double zero as sqrt(eps·‖A‖)). A mode counts as unstable when
Re λ > ``RTOL`` · max|λ| + ``ATOL``: with max|λ| ~ 1e4-1e6 1/s that is 1e-4-1e-2 1/s, a time
constant of minutes or longer, far above round-off and far below any instability that matters
on a run's time scale.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from webline.errors import WeblineError
from webline.limits import MAX_EIGEN_STATES
from webline.line import Line
from webline.model.operating_point import analysis_time
from webline.sim.linearize import plan_eigenvalues, plan_linear_model
from webline.sim.plan import Plan, compile_plan
from webline.verdict import Finding

RTOL = 1e-8
ATOL = 1e-6  # [1/s]
#: states sharing at least this much of an unstable mode's participation are named
SHARE = 0.1


@dataclass(frozen=True)
class UnstableMode:
    """An eigenvalue λ [1/s] with Re λ > 0 and the states it lives in (share of the
    participation, largest first)."""

    eigenvalue: complex
    states: tuple[tuple[str, float], ...]

    @property
    def frequency_hz(self) -> float:
        """Oscillation frequency |Im λ| / 2π [Hz] (0 for a real pole)."""
        return abs(self.eigenvalue.imag) / (2.0 * math.pi)

    @property
    def damping(self) -> float:
        """ζ = -Re λ / |λ| (negative: growing)."""
        return -self.eigenvalue.real / abs(self.eigenvalue)


def tolerance(values: np.ndarray) -> float:
    """Largest Re λ [1/s] still taken as zero (module docstring)."""
    return RTOL * float(np.max(np.abs(values), initial=0.0)) + ATOL


def unstable_modes(a: np.ndarray, names: list[str],
                   values: np.ndarray | None = None) -> list[UnstableMode]:
    """The modes of ``a`` with Re λ above ``tolerance``, fastest-growing first (one per
    complex pair); ``values``: the eigenvalues of ``a`` if already known."""
    values = np.linalg.eigvals(a) if values is None else values
    tol = tolerance(values)
    if not np.any(values.real > tol):
        return []
    values, right = np.linalg.eig(a)
    left = np.linalg.inv(right)  # rows are the left eigenvectors
    participation = np.abs(right * left.T)  # [state, mode]
    out = []
    for j in np.argsort(-values.real):
        value = complex(values[j])
        if value.real <= tol or value.imag < 0.0:
            continue
        share = participation[:, j] / participation[:, j].sum()
        order = [int(s) for s in np.argsort(-share) if share[s] >= SHARE][:4]
        out.append(UnstableMode(value, tuple((names[s], float(share[s])) for s in order)))
    return out


def is_stable(line: Line, t: float) -> tuple[bool, float]:
    """Whether the closed-loop linear model of ``line`` at time ``t`` [s] has no mode above
    ``tolerance``, and its largest Re λ [1/s]."""
    values = plan_eigenvalues(compile_plan(line), loop="closed", t=t)
    worst = float(np.max(values.real))
    return worst <= tolerance(values), worst


def stability_findings(line: Line, t: float | None = None, *,
                       plan: Plan | None = None) -> list[Finding]:
    """An ``unstable`` finding per unstable closed-loop mode of ``line`` at ``t`` [s]
    (default ``analysis_time``); none for a stable line or one without an operating point
    (the run or analysis reports that itself); a ``warning`` (``stability_unchecked``) for a
    model beyond ``limits.MAX_EIGEN_STATES`` states. ``plan``: the compiled plan of ``line``
    whose cached linear model to use (default: the line's own plan)."""
    t = analysis_time(line) if t is None else t
    plan = compile_plan(line) if plan is None else plan
    try:
        model = plan_linear_model(plan, loop="closed", t=t)
    except (WeblineError, ValueError, ArithmeticError, np.linalg.LinAlgError):
        return []
    if len(model.states) > MAX_EIGEN_STATES:  # said, never silently skipped
        return [Finding("warning", "stability_unchecked", "", (
            f"stability not checked: the closed-loop model has {len(model.states)} states, "
            f"more than the {MAX_EIGEN_STATES} whose eigenvalues webline computes for a run "
            "(limits.MAX_EIGEN_STATES)"), None,
            {"states": len(model.states), "limit": MAX_EIGEN_STATES})]
    values = plan_eigenvalues(plan, loop="closed", t=t)
    out = []
    for mode in unstable_modes(model.a, model.states, values):
        states = ", ".join(f"{name} {share:.0%}" for name, share in mode.states)
        cause = likely_cause(line, t, mode)
        message = (f"closed-loop mode λ = {mode.eigenvalue.real:.3g} ± "
                   f"{abs(mode.eigenvalue.imag):.3g}j 1/s grows ({mode.frequency_hz:.3g} Hz, "
                   f"ζ = {mode.damping:.3g}) at t = {t:g} s, in {states}")
        if cause:
            message += f"; {cause}"
        out.append(Finding("unstable", "unstable_mode", mode.states[0][0] if mode.states else "",
                           message, None, {
                               "eigenvalue_real": mode.eigenvalue.real,
                               "eigenvalue_imag": mode.eigenvalue.imag,
                               "frequency_hz": mode.frequency_hz, "damping_ratio": mode.damping,
                               "analysis_time_s": t, "states": [n for n, _ in mode.states],
                               "participation": [s for _, s in mode.states],
                               "cause": cause}))
    return out


def likely_cause(line: Line, t: float, mode: UnstableMode) -> str:
    """The cause webline can tell, checked on the linear model: a drive that measures its speed
    on the load side of a compliant transmission, whose states the mode lives in, and with
    whose ``feedback = "motor"`` the line is stable. '' if none is found."""
    involved = {name for name, _ in mode.states}
    for i in line.drives:
        roller = line.spec.rollers[i]
        drive = roller.drive  # type: ignore[union-attr]
        if drive.feedback != "load" or drive.transmission.type == "direct":
            continue
        name = line.node_name(i)
        if not any(s.startswith(f"{name}_") for s in involved):
            continue
        stable, worst = is_stable(with_motor_feedback(line, i), t)
        if stable:
            return (f"{name} measures its speed on the load side of its "
                    f"{drive.transmission.type} transmission; with feedback = \"motor\" the "
                    f"line is stable (largest Re λ {worst:.3g} 1/s)")
    return ""


def with_motor_feedback(line: Line, node: int) -> Line:
    """``line`` with the drive of ``node`` measuring its speed on the motor."""
    rollers = [r.model_dump(exclude_none=True) for r in line.spec.rollers]
    rollers[node]["drive"]["feedback"] = "motor"
    return line.replace(rollers=rollers)
