"""The constraints a tuned line must meet, each computed from the line itself.

* stability margins at several points of the roll (``tune_space.roll_radii``; the speed gains
  of the rolls scheduled there as the drives schedule them): every closed-loop mode stable;
  the modes in which the controllers' integrators take at least ``controller_share`` of the
  participation damped by at least ``min_damping`` (the light idlers ringing on their spans,
  which no drive can reach, are left to the plant); each drive's loop-at-a-time gain margin,
  gain-reduction margin and phase margin (``loop_margins``); and, where every drive runs a
  decentralized controller, the certificate of thesis Theorem 6.2.1
  (``analysis.certificate``) at the initial radii;
* torque limits: in every scenario no drive's torque command sits at its limit for more than
  ``saturation_share`` of the run, and no run fails or goes unstable (its verdict);
* robustness (``tune_robust``): the same, in at least ``robust_share`` of Monte Carlo draws of
  the uncertain parameters.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from webline.line import Line
from webline.sim.core.plan import compile_plan
from webline.sim.linear.linearize import plan_linear_model
from webline.spec.schema import CascadedPISpec
from webline.twin.tuning.loop_margins import LoopMargin, loop_margins
from webline.twin.tuning.tune_space import line_at_roll, roll_radii

#: the constraint on the closed loop's modes
UNSTABLE = "largest real part of a closed-loop mode [1/s]"


@dataclass(frozen=True)
class Limits:
    """Limits of ``webline.tune``: margins [dB, deg], damping [1] of the modes the controllers
    take part in (those whose integrators hold ≥ ``controller_share`` of the participation),
    the share of a run a torque may sit at its limit [1], the share of Monte Carlo draws that
    must stay stable and within limits [1], and the points across the roll checked."""

    gain_margin_db: float = 6.0
    reduction_margin_db: float = 6.0
    phase_margin_deg: float = 40.0
    min_damping: float = 0.3
    controller_share: float = 0.05
    saturation_share: float = 0.01
    robust_share: float = 0.9
    roll_points: int = 3

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


@dataclass(frozen=True)
class Constraint:
    """One checked constraint: ``value`` against ``limit`` in ``sense`` (">=" or "<=")."""

    name: str
    value: float
    limit: float
    sense: str
    where: str = ""

    @property
    def holds(self) -> bool:
        if math.isnan(self.value):
            return False
        return self.value >= self.limit if self.sense == ">=" else self.value <= self.limit

    @property
    def violation(self) -> float:
        """How far it misses, relative to the limit's scale (0 if it holds) [1]."""
        if self.holds:
            return 0.0
        if math.isnan(self.value):
            return 1.0
        scale = max(abs(self.limit), 1e-3)
        return min(abs(self.value - self.limit) / scale, 10.0)

    def as_dict(self) -> dict[str, object]:
        return {"name": self.name, "value": _finite(self.value), "limit": self.limit,
                "sense": self.sense, "where": self.where, "holds": self.holds}


def _finite(value: float) -> float | str:
    return value if math.isfinite(value) else str(value)


def controller_modes(line: Line) -> tuple[np.ndarray, np.ndarray]:
    """(eigenvalues [1/s], share of their participation held by controller integrator
    states [1]) of ``line``'s closed loop at its operating point."""
    model = plan_linear_model(compile_plan(line), loop="closed")
    values, right = np.linalg.eig(np.asarray(model.a, dtype=float))
    participation = np.abs(right * np.linalg.inv(right).T)
    participation /= participation.sum(axis=0, keepdims=True)
    ctrl = [j for j, name in enumerate(model.states) if name.endswith("_integral")]
    return values, participation[ctrl].sum(axis=0)


def stability_constraints(line: Line, limits: Limits) -> list[Constraint]:
    """Margins and damping of ``line`` (its gains explicit, ``tune_space.frozen_gains``) at
    ``limits.roll_points`` points across the roll; the worst of each over the points."""
    worst: Worst = {}
    for ru, rw in roll_radii(line, limits.roll_points):
        at = line_at_roll(line, ru, rw)
        spot = f"unwind r = {ru:.3g} m, rewind r = {rw:.3g} m"
        values, share = controller_modes(at)
        record_point(worst, values, share, loop_margins(compile_plan(at)), spot, limits)
    out = worst_constraints(worst, limits)
    if all(not isinstance(getattr(line.spec.rollers[i], "controller", None), CascadedPISpec)
           for i in line.drives):
        from webline.analysis.certificate import certificate

        cert = certificate(line)
        out.append(Constraint("decentralized certificate: min δ/(√N ξ) [1]",
                              cert.worst_ratio, 1.0, ">=", "initial radii"))
    return out


#: the worst value of each stability measure so far and where: {name: (value, where)}
Worst = dict[str, tuple[float, str]]


def record_point(worst: Worst, values: np.ndarray, share: np.ndarray,
                 margins: list[LoopMargin], spot: str, limits: Limits) -> None:
    """Keep in ``worst`` the stability measures of one operating point (``spot``): its
    closed-loop eigenvalues ``values`` [1/s], their controller ``share`` [1] and each drive's
    loop ``margins``."""
    def keep(name: str, value: float, where: str, lower_is_worse: bool = True) -> None:
        old = worst.get(name)
        if old is None or (value < old[0] if lower_is_worse else value > old[0]):
            worst[name] = (value, where)

    keep(UNSTABLE, float(values.real.max()), spot, lower_is_worse=False)
    mask = share >= limits.controller_share
    zeta = -values.real / np.maximum(np.abs(values), 1e-300)
    keep("damping of the controlled modes [1]",
         float(zeta[mask].min()) if mask.any() else 1.0, spot)
    for m in margins:
        here = f"{m.drive}, {spot}"
        keep("gain margin [dB]", m.gain_margin_db, here)
        keep("gain-reduction margin [dB]", m.reduction_margin_db, here)
        keep("phase margin [deg]", m.phase_margin, here)


def worst_constraints(worst: Worst, limits: Limits) -> list[Constraint]:
    """The stability constraints of the worst values ``record_point`` kept."""
    out = [Constraint(UNSTABLE, worst[UNSTABLE][0], 0.0, "<=", worst[UNSTABLE][1])]
    for name, limit in (("damping of the controlled modes [1]", limits.min_damping),
                        ("gain margin [dB]", limits.gain_margin_db),
                        ("gain-reduction margin [dB]", limits.reduction_margin_db),
                        ("phase margin [deg]", limits.phase_margin_deg)):
        value, where = worst[name]
        out.append(Constraint(name, value, limit, ">=", where))
    return out


def run_constraints(scenario: str, status: str, saturation: np.ndarray, drives: list[str],
                    duration: float, limits: Limits) -> list[Constraint]:
    """Torque-limit and verdict constraints of one run: ``saturation`` [s] each drive's
    torque command sat at its limit, ``status`` the run's verdict status."""
    share = saturation / duration
    d = int(np.argmax(share))
    return [Constraint("time at a torque limit [share of the run]", float(share[d]),
                       limits.saturation_share, "<=", f"{drives[d]}, {scenario}"),
            Constraint("run neither failed nor unstable [1 = yes]",
                       0.0 if status in ("failed", "unstable") else 1.0, 1.0, ">=", scenario)]
