"""The Chapter 4 unwind section as a linear model: A_T, B_V, B_T of (4.3)-(4.6), the braking
input of (4.12) and the backlash direction D.

States (thesis order) x = (θm, ωm, θL, ωL, T1, x1, x2, x3, τm): motor and load (unwind roll)
angles [rad] and speeds [rad/s], span-1 tension [N], the cascaded PI's states x2 = ∫(Tr - T1)
[N·s], x1 = ∫x2 [N·s²] and x3 = ∫(V_ff - V_meas) [m], and the motor torque [N·m]. Inputs: the
master's web speed V_r [m/s] (B_V), the tension reference T_r [N] (B_T) and a brake torque on
the unwind shaft τ_b [N·m] (B_b, 4.12). Re-derived from the equations, not the printed
matrices (docs/errata.md E-4.1, E-4.2):

* belt (4.3) with k = Kb R2² [N·m/rad] the load-side stiffness, n = R2/R1 the motor/load
  speed ratio: Kb R1² = k/n², Kb R1 R2 = k/n (a geared drive: k of the mesh, the same form);
* tension (4.4a) linearised at the operating point, span-1 entries as webline's (6.8);
* the cascaded PI as webline runs it (4.1i-j with the trim sign of E-4.1, speed error in m/s
  from the motor or load encoder, E-4.2): u = d1 (Tr - T1) + d2 x2 + d3 x1 + d4 (V_ff - V_meas)
  + d5 x3 with d1 = σ g Kps Kpt, d2 = σ g (Kps Kit + Kis Kpt), d3 = σ g Kis Kit, d4 = g Kps,
  d5 = g Kis (σ = -1 for the unwind, g the inertia gain scaling at the operating point),
  τmc dτm/dt = -τm + u (4.4e, Km = 1); V_ff = V_r (EA - T_m)/(EA - T0) (the draw; T_m the
  reference of the master's upstream zone, so B_T has a feedforward part too).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import webline
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as L
from webline.sim.linear.linear_plant import load_inertia

STATES = ("theta_m", "omega_m", "theta_L", "omega_L", "T1", "x1", "x2", "x3", "tau_m")


@dataclass(frozen=True)
class UnwindModel:
    """dx/dt = A_T x + B_V V_r + B_T T_r + B_b τ_b + β D φ (4.5a), y = L_p x = (V0, T1) (4.5b);
    ``plant`` marks the rows/columns of the open-loop plant (no PI states)."""

    a_t: np.ndarray
    b_v: np.ndarray
    b_t: np.ndarray
    b_brake: np.ndarray
    d: np.ndarray
    l_p: np.ndarray
    ratio: float
    stiffness: float

    def open_loop(self) -> np.ndarray:
        """A_T with the controller's torque command cut (d1..d5 = 0): the plant alone."""
        a = self.a_t.copy()
        a[8, :8] = 0.0
        return a


def unwind_model(line: webline.Line, t: float = 0.0) -> UnwindModel:
    """The model of ``line``'s unwind section at its operating point at time ``t`` [s] (roll
    radius frozen, as in the thesis's set U of radii). The unwind must be driven through a belt
    or shaft (compliant) transmission with a cascaded PI (4.1); its downstream node is taken as
    the master speed V_r."""
    plan = compile_plan(line)
    op = webline.operating_point(line, t)
    if not line.drives or line.drives[0] != 0:
        raise ValueError(f"{line.source}: the unwind is not driven")
    row = plan.drives[0]
    if row[L.D_TSTATE] < 0:
        raise ValueError(f"{line.source}: the unwind drive has no belt or shaft (rigid)")
    if row[L.D_FAMILY] != L.FAMILY_PI:
        raise ValueError(f"{line.source}: the unwind is not under cascaded PI (Fig. 4.3)")
    n, k, c = row[L.D_RATIO], row[L.D_KTRANS], row[L.D_CTRANS]
    jm, bm, lag = row[L.D_JMOTOR], row[L.D_BMOTOR], row[L.D_LAG]
    jl, bl = load_inertia(plan, op, 0), plan.nodes[0, L.N_VISCOUS]
    r_un, length, ea = op.radius[0], plan.spans[0, L.S_LENGTH], line.ea
    t1, t0, v1 = op.tension[0], line.unwind.wound_in_tension, op.speed[1]
    g = op.inertia[0] / (n * r_un) / row[L.D_GAINNORM]
    gains = plan.gains[0]
    sigma = row[L.D_SIGMA]
    d1 = sigma * g * gains.speed_kp * gains.tension_kp
    d2 = sigma * g * (gains.speed_kp * gains.tension_ki + gains.speed_ki * gains.tension_kp)
    d3 = sigma * g * gains.speed_ki * gains.tension_ki
    d4, d5 = g * gains.speed_kp, g * gains.speed_ki
    # feedforward V_ff = V_line (EA - T_master_up)/(EA - T0), as the kernel's ``pi_command``
    master_up = int(plan.offsets[L.O_MASTER_UP])
    t_master = plan.profile_value(master_up, t)
    draw = (ea - t_master) / (ea - t0)
    draw_t = -op.line_speed / (ea - t0) if master_up == int(row[L.D_REF]) else 0.0
    motor_feedback = row[L.D_FEEDBACK] > 0
    a = np.zeros((9, 9))
    a[0, 1] = 1.0
    # motor (4.3b): Jm ω̇m = τm - bm ωm - (k/n)(θm/n - θL) - (c/n)(ωm/n - ωL)
    a[1, 0], a[1, 2] = -k / (n * n * jm), k / (n * jm)
    a[1, 1], a[1, 3], a[1, 8] = -(bm + c / n**2) / jm, c / (n * jm), 1.0 / jm
    a[2, 3] = 1.0
    # load (4.3d): JL ω̇L = k(θm/n - θL) + c(ωm/n - ωL) - bL ωL + r T1
    a[3, 0], a[3, 2] = k / (n * jl), -k / jl
    a[3, 1], a[3, 3], a[3, 4] = c / (n * jl), -(bl + c) / jl, r_un / jl
    # tension (4.4a): L1 Ṫ1 = EA (V1 - r ωL) + r ωL T0 - V1 T1
    a[4, 3], a[4, 4] = -(ea - t0) * r_un / length, -v1 / length
    a[5, 6] = 1.0  # x1 = ∫x2
    a[6, 4] = -1.0  # x2 = ∫(Tr - T1)
    speed_row = np.zeros(9)  # V_meas
    speed_row[1 if motor_feedback else 3] = r_un / n if motor_feedback else r_un
    a[7] = -speed_row  # x3 = ∫(V_ff - V_meas)
    u = -d1 * np.eye(9)[4] + d2 * np.eye(9)[6] + d3 * np.eye(9)[5] - d4 * speed_row \
        + d5 * np.eye(9)[7]
    a[8] = u / lag
    a[8, 8] -= 1.0 / lag
    b_v = np.zeros(9)
    b_v[4] = (ea - t1) / length
    b_v[7] = draw
    b_v[8] = d4 * draw / lag
    b_t = np.zeros(9)
    b_t[6] = 1.0
    b_t[7] = draw_t  # the draw follows the tension reference of the master's upstream zone
    b_t[8] = (d1 + d4 * draw_t) / lag
    b_brake = np.zeros(9)
    b_brake[3] = 1.0 / jl  # (4.12): τ_b acts on the load shaft
    d = np.zeros(9)  # backlash term φ as a load-side torque: -1/(n Jm) motor, +1/JL load
    d[1], d[3] = -1.0 / (n * jm), 1.0 / jl
    l_p = np.zeros((2, 9))
    l_p[0, 3], l_p[1, 4] = r_un, 1.0
    return UnwindModel(a, b_v, b_t, b_brake, d, l_p, float(n), float(k))
