"""When does the backlash gap of a roll's drive open? (thesis Sec. 4.3, (4.8)-(4.12)).

The teeth of a backlashed drive part when the spring torque through the transmission reaches
zero. On the load shaft of a rewind (torque balance of (4.11d) and (4.12))

    τ(t) = R T(t) + b_L ω_L(t) + J_L dω_L/dt + τ_b,     mean  τ̄ = R T_r + b_L V/R + τ_b,

so the gap stays closed while the disturbance part of τ stays above -τ̄. While the teeth touch
the backlash model *is* the linear model (the gap only shifts the twist), so the linear
closed-loop model decides exactly when the gap first opens:

* a sinusoidal disturbance of amplitude a [m/s] and frequency f: opens iff
  a > a*(f) = τ̄ / |G_τ(j2πf)|, G_τ the closed-loop response of the spring torque [N·m per m/s];
  the web goes slack iff a > a_s(f) = T_r / |G_T(j2πf)| (tension response): whichever threshold
  is lower is crossed first;
* a deceleration d [m/s²] of the line (a slow-down ramp): opens iff d > d* = τ̄ / σ, σ [N·m per
  m/s²] the peak drop of the spring torque per unit deceleration (the linear ramp response).
  Quasi-statically (roll following the web, tension held) σ = J_L/R, i.e. d* = R τ̄/J_L; the
  loop's overshoot makes σ larger.
* both: the gap stays closed while τ̄ - σ d - a |G_τ| > 0 (sufficient, peaks aligned).

``tension_deviation`` is the term Lp2 g(t) of (4.8): the tension a backlash adds to the linear
run, from the deviation torque φ(t) a simulation recorded, for the prediction (4.9)-(4.10).
``tension_bound`` bounds it for *any* motion in the gap (the L1 bound of E-3.3 with |φ| <= kΔ),
hence bounds the mean shift and the change of the standard deviation (E-4.3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.analysis.drivetrain.backlash_bounds import BacklashLoop, l1_bound, printed_bound_peak
from webline.analysis.drivetrain.sampled import zoh
from webline.line import Line
from webline.physics.backlash import transmitted_torque
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as L
from webline.sim.linear.linear_plant import load_inertia
from webline.sim.linear.linearize import LinearModel, linear_model, plan_linear_model


@dataclass(frozen=True)
class GapMargin:
    """The rewind drive's margin against the gap opening at the line's operating point.

    ``mean_torque`` τ̄ [N·m], ``radius`` R [m], ``load_inertia`` J_L [kg·m²], ``stiffness`` k
    [N·m/rad] of the transmission, ``torque_per_decel`` σ [N·m per m/s²] (peak of the linear
    ramp response), ``tension`` T_r [N]."""

    mean_torque: float
    radius: float
    load_inertia: float
    stiffness: float
    torque_per_decel: float
    tension: float

    @property
    def decel_threshold(self) -> float:
        """d* = τ̄/σ [m/s²]: the gap opens in a slow-down ramp steeper than this."""
        return self.mean_torque / self.torque_per_decel

    @property
    def quasi_static_decel(self) -> float:
        """R τ̄/J_L [m/s²]: d* of a roll that follows the web with the tension held."""
        return self.radius * self.mean_torque / self.load_inertia


def _rewind(line: Line) -> tuple[int, int]:
    """(node, drive index) of the line's last roll, which must be a driven rewind."""
    node = line.n_nodes - 1
    return node, list(line.drives).index(node)


def _state(model: LinearModel, name: str) -> int:
    return model.states.index(name)


def _lsim(a: np.ndarray, b: np.ndarray, u: np.ndarray, dt: float,
          x0: np.ndarray | None = None) -> np.ndarray:
    """States [n_t, n] of dx/dt = A x + b u(t), u held over each step ``dt`` [s] (ZOH)."""
    n = a.shape[0]
    ad, bd = zoh(a, b, dt)
    x = np.zeros((len(u), n))
    x[0] = 0.0 if x0 is None else x0
    for k in range(len(u) - 1):
        x[k + 1] = ad @ x[k] + bd * u[k]
    return x


def rewind_gap_margin(line: Line, *, brake: float = 0.0, horizon: float = 8.0,
                      dt: float = 2e-3) -> GapMargin:
    """The margin of the rewind drive of ``line`` (no backlash needed) with a ``brake`` [N·m]
    on its shaft; σ from the closed-loop ramp response over ``horizon`` [s] at step ``dt`` [s]."""
    plan = compile_plan(line)
    node, d = _rewind(line)
    op = plan.op
    model = plan_linear_model(plan, loop="closed")
    k = float(plan.drives[d, L.D_KTRANS])
    radius = float(op.radius[node])
    tension = float(op.tension[line.n_spans - 1])
    viscous = float(plan.nodes[node, L.N_VISCOUS])
    mean = radius * tension + viscous * float(op.speed[node]) / radius + brake
    t = np.arange(0.0, horizon, dt)
    x = _lsim(model.a, model.b[:, model.inputs.index("line_speed_ref")], -t, dt)
    drop = -k * x[:, _state(model, f"{line.node_name(node)}_twist")]
    return GapMargin(mean, radius, load_inertia(plan, op, node), k, float(drop.max()), tension)


def ripple_gains(line: Line, roller: str, freqs: list[float],
                 rewind_radius: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(|G_τ|, |G_T|) at ``freqs`` [Hz]: amplitude of the rewind's spring torque [N·m] and of its
    span's tension [N] per m/s of a ``speed_ripple`` in the speed reference of drive ``roller``
    (the linear closed loop at the initial or the given ``rewind_radius`` [m]; the ripple
    enters the drive's PI like its speed reference)."""
    plan = compile_plan(line)
    model = linear_model(line, loop="closed", rewind_radius=rewind_radius)
    open_ = linear_model(line, loop="open", rewind_radius=rewind_radius)
    d = [line.node_name(i) for i in line.drives].index(roller)
    if plan.drives[d, L.D_FAMILY] != L.FAMILY_PI:
        raise ValueError(f"{roller}: ripple gains need a cascaded-PI drive")
    col = np.zeros(model.a.shape[0])
    col[: open_.b.shape[0]] = open_.b[:, d] * plan.drives[d, L.D_KPS]
    col[_state(model, f"{roller}_speed_integral")] = plan.drives[d, L.D_KIS]
    node, dr = _rewind(line)
    k = float(plan.drives[dr, L.D_KTRANS])
    twist = _state(model, f"{line.node_name(node)}_twist")
    tension_row = model.c[line.n_spans - 1]
    g_tau, g_t = [], []
    for f in freqs:
        x = np.linalg.solve(2j * np.pi * f * np.eye(len(col)) - model.a, col)
        g_tau.append(abs(k * x[twist]))
        g_t.append(abs(tension_row @ x))
    return np.array(g_tau), np.array(g_t)


def deviation_torque(twist: np.ndarray, rate: np.ndarray, stiffness: float, damping: float,
                     gap: float) -> np.ndarray:
    """φ(t) [N·m] of (3.65) in rotary form: the linear spring-damper torque minus the backlash
    one, for the recorded ``twist`` [rad] and ``rate`` [rad/s] and a symmetric ``gap`` Δ [rad]."""
    return np.array([stiffness * tw + damping * r
                     - transmitted_torque(tw, r, stiffness, damping, gap, gap)
                     for tw, r in zip(twist, rate, strict=True)])


def tension_deviation(line: Line, phi: np.ndarray, dt: float, twist0: float = 0.0) -> np.ndarray:
    """Lp2 g(t) of (4.8) [N]: the rewind span's tension added to the backlash-free run of
    ``line`` by the deviation torque ``phi`` [N·m] sampled every ``dt`` [s], from an initial
    twist difference ``twist0`` [rad] (the gap the backlash run starts in), through the linear
    closed loop at the line's operating point."""
    plan = compile_plan(line)
    model = plan_linear_model(plan, loop="closed")
    node, d = _rewind(line)
    twist = _state(model, f"{line.node_name(node)}_twist")
    k = float(plan.drives[d, L.D_KTRANS])
    col = -model.a[:, twist] / k  # φ enters where k·twist does, with the opposite sign
    x0 = np.zeros(model.a.shape[0])
    x0[twist] = twist0
    x = _lsim(model.a, col, phi, dt, x0)
    return x @ model.c[line.n_spans - 1]


def tension_bound(line: Line, gap: float, *, from_contact: bool = False) -> float:
    """Bound [N] on |Lp2 g(t)|, the rewind span's tension a symmetric ``gap`` Δ [rad] can add to
    the backlash-free run of ``line`` from the same state whatever the teeth do: kΔ ∫|c e^{Aσ}
    D| dσ over the linear closed loop (``l1_bound``); it also bounds the steady-state mean shift
    and change of std. ``from_contact``: for a backlash run that starts resting on the driving
    flank (twist + Δ, as webline starts one), φ - kΔ drives the difference, so the peak of the
    response to a constant kΔ (``printed_bound_peak``) is added. The damping c·rate that also
    drops out while the teeth are apart is left out (0.13 N·m·s/rad on ``rockwell``: 2 % of kΔ
    at 1 rad/s). The integral runs over 12 time constants of the slowest mode (tail below
    e^-12) on 40 000 points: within 1e-3 of ``l1_bound``'s 40 time constants on its finer
    grid, in a tenth of a second."""
    plan = compile_plan(line)
    model = plan_linear_model(plan, loop="closed")
    node, d = _rewind(line)
    twist = _state(model, f"{line.node_name(node)}_twist")
    k = float(plan.drives[d, L.D_KTRANS])
    row = np.asarray(model.c[line.n_spans - 1])
    loop = BacklashLoop(np.asarray(model.a), np.zeros(0), np.zeros(0),
                        -model.a[:, twist] / k, row, k * gap)
    horizon = 12.0 / float(-np.linalg.eigvals(loop.a).real.max())
    bound = l1_bound(loop, t=horizon, output=row, samples=40_000)
    if from_contact:
        bound += printed_bound_peak(loop, t=horizon, output=row, samples=40_000)
    return bound
