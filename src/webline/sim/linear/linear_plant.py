"""The plant's linear model at an operating point: its states, and its matrices (A, B, E, C)
from the same equations as the kernel (``webline.sim.linear.linearize`` closes the loop on them).

The roll radii are frozen at the operating point, eccentricity is left out and the web sticks
on traction rollers and nips (see ``webline.sim.linear.linearize``). A nip's pressure roller is in
its roller's J and b (docs/winder.md N1).
"""

from __future__ import annotations

import numpy as np

from webline.line import Line, is_roll
from webline.model.operating_point import OperatingPoint
from webline.physics.roll import web_inertia
from webline.physics.roller import COULOMB_SMOOTHING, table_friction
from webline.physics.web_law import law_slope
from webline.sim.core import viscoelastic
from webline.sim.core.plan import Plan, compile_plan
from webline.sim.elements import layout as L
from webline.sim.linear import dancer_linear as dancers


def state_names(line: Line) -> list[str]:
    """Names of the linear model's states: span tensions (their stretches EA·ε where the
    rollers feel more: a damper, a nonlinear law), node speeds, motor torques, and the
    motor speed and twist of each compliant transmission."""
    return plan_state_names(compile_plan(line))


def plan_state_names(plan: Plan) -> list[str]:
    """``state_names`` of the line of ``plan`` (built once per plan; a new list each call)."""
    if "state_names" not in plan.memo:
        line = plan.line
        compliant = [i for d, i in enumerate(line.drives) if plan.drives[d, L.D_TSTATE] >= 0]
        plan.memo["state_names"] = tuple(
            [f"{line.span_name(k)}_tension" for k in range(line.n_spans)]
            + [f"{line.node_name(i)}_omega" for i in range(line.n_nodes)]
            + [f"{line.node_name(i)}_torque" for i in line.drives]
            + [f"{line.node_name(i)}_{part}" for i in compliant
               for part in ("motor_omega", "twist")] + dancers.linear_states(plan))
    return list(plan.memo["state_names"])  # type: ignore[call-overload]


def plant_matrices(line: Line, op: OperatingPoint) -> tuple[np.ndarray, ...]:
    """(A, B, E, C) of the plant at ``op``: dx = A x + B u + E t0, y = C x.

    x = (span tensions [N], node speeds [rad/s], motor torques [N·m], then motor speed
    [rad/s] and twist [rad] of each compliant transmission); u = motor torque commands [N·m];
    t0 = wound-in tension [N]; y = (span tensions, web speeds [m/s]).
    """
    return plan_plant(compile_plan(line), op)


def plan_plant(plan: Plan, op: OperatingPoint) -> tuple[np.ndarray, ...]:
    """``plant_matrices`` of the line of ``plan`` (its tables, its controllers' designs)."""
    line = plan.line
    n_s, n_n, n_d = line.n_spans, line.n_nodes, len(line.drives)
    ws, wn = 0, n_s  # offsets of the blocks
    wt = n_s + n_n
    n_c = int(np.sum(plan.drives[:, L.D_TSTATE] >= 0))
    n_dn = len(dancers.dancer_nodes(line))
    n = wt + n_d + 2 * n_c + 2 * n_dn
    ea = line.ea
    r, v, t = op.radius, op.speed, op.tension
    t_up = np.concatenate(([line.unwind.wound_in_tension], t))
    s, s_up = t, t_up  # the stretch EA·ε mass flow moves: the tension, for a linear web
    if line.nonlinear:  # docs/nonlinear-web.md (N2)
        s_up = np.array([line.stretch_of(x) for x in t_up])
        s = s_up[1:]
    a = np.zeros((n, n))
    b = np.zeros((n, n_d))
    e = np.zeros((n, 1))
    for k in range(n_s):  # L ds_k/dt = EA (v_{k+1} - v_k) + s_{k-1} v_k - s_k v_{k+1}
        length = plan.spans[k, L.S_LENGTH]
        d_s, d_up, d_out, d_in = _span_slopes(ea, s[k], s_up[k], v[k], v[k + 1], line.exact)
        a[ws + k, ws + k] = d_s / length
        if k > 0:
            a[ws + k, ws + k - 1] = d_up / length
        a[ws + k, wn + k + 1] = d_out * r[k + 1] / length
        a[ws + k, wn + k] = d_in * r[k] / length
    e[ws, 0] = _span_slopes(ea, s[0], s_up[0], v[0], v[1], line.exact)[1] / plan.spans[
        0, L.S_LENGTH]
    if line.nonlinear:  # the wound-in tension enters as its stretch: ds0/dT0 = 1 / F'(s0)
        e[ws, 0] /= law_slope(s_up[0], line.law)
    for i in range(n_n):  # J dω/dt = r (T_out - T_in) + shaft torque - b ω - c tanh(ω/ωc)
        inertia = load_inertia(plan, op, i)
        if i < n_s:
            a[wn + i, ws + i] = r[i] / inertia
        if i > 0:
            a[wn + i, ws + i - 1] = -r[i] / inertia
        viscous, coulomb = plan.nodes[i, L.N_VISCOUS], plan.nodes[i, L.N_COULOMB]
        if plan.nodes[i, L.N_DRAG] >= 0:  # a brake or drag acts like Coulomb friction
            coulomb += plan.profile_value(int(plan.nodes[i, L.N_DRAG]), op.time)
        slope = coulomb / COULOMB_SMOOTHING * (1.0 - np.tanh(op.omega[i] / COULOMB_SMOOTHING) ** 2)
        points = int(plan.nodes[i, L.N_FRICN])
        if points > 0:  # a measured friction table (docs/winder.md F1)
            slope += table_friction(float(op.omega[i]),
                                    plan.nodes[i, L.N_FRICW:L.N_FRICW + points],
                                    plan.nodes[i, L.N_FRICT:L.N_FRICT + points])[1]
        a[wn + i, wn + i] = -(viscous + slope) / inertia
    for d in range(n_d):  # lag dτ/dt = (u - τ)/lag
        lag = plan.drives[d, L.D_LAG]
        a[wt + d, wt + d] = -1.0 / lag
        b[wt + d, d] = 1.0 / lag
    _drive_block(a, plan, op, wn, wt, wt + n_d)
    dancers.plant_rows(a, e, plan, s, wt + n_d + 2 * n_c)
    c = np.zeros((n_s + n_n, n))
    slopes = np.array([law_slope(x, line.law) for x in s]) if line.nonlinear else None
    c[:n_s] = viscoelastic.felt_rows(plan, a, e, slopes)  # T = F(s) (+ τ ds/dt, Kelvin-Voigt)
    c[n_s:, wn:wn + n_n] = np.diag(r)
    return a, b, e, c


def _span_slopes(ea: float, s: float, s_in: float, v_in: float, v_out: float,
                 exact: bool) -> tuple[float, float, float, float]:
    """L x the partial derivatives of a taut span's d(stretch)/dt with respect to its stretch
    ``s``, the stretch ``s_in`` carried in, and the speeds out and in [N/s per N, per m/s]:
    thesis 6.8 (-v_out, v_in, EA - s, -(EA - s_in)), or exact mass conservation
    (``physics.span.exact_stretch_rate``, L ds/dt = (EA + s) v_out - (EA + s)² v_in/(EA + s_in),
    whose flows need not balance: a line speeding up)."""
    if not exact:
        return -v_out, v_in, ea - s, -(ea - s_in)
    grow, carried = ea + s, ea + s_in
    return (v_out - 2.0 * grow * v_in / carried, grow * grow * v_in / carried**2, grow,
            -grow * grow / carried)


def load_inertia(plan: Plan, op: OperatingPoint, i: int) -> float:
    """Inertia [kg·m²] at the shaft of node ``i`` at ``op`` as the kernel sees it: with the
    motor reflected for a rigid drive, without it across a compliant transmission."""
    roller = plan.line.spec.rollers[i]
    if not is_roll(roller):
        return float(plan.nodes[i, L.N_JCONST])
    web = plan.line.spec.web
    return float(plan.nodes[i, L.N_JCONST]) + web_inertia(
        op.radius[i], roller.core_radius, web.width,  # type: ignore[union-attr]
        plan.roll_density(i))


def _drive_block(a: np.ndarray, plan: Plan, op: OperatingPoint, wn: int, wt: int,
                 wc: int) -> None:
    """Entries of every drive's shaft torque (see ``kernel.drive_torque``) in ``a``: the
    node's speed row, and the motor-speed and twist rows of compliant transmissions, whose
    states start at column ``wc``. The teeth of a backlash are taken in contact unless the
    equilibrium torque through them is zero."""
    c = 0
    for d, i in enumerate(plan.line.drives):
        row = plan.drives[d]
        inertia = load_inertia(plan, op, i)
        n = row[L.D_RATIO]
        if row[L.D_TSTATE] < 0:
            a[wn + i, wt + d] = n / inertia
            a[wn + i, wn + i] -= n * n * row[L.D_BMOTOR] / inertia
            continue
        wm, tw = wc + 2 * c, wc + 2 * c + 1
        c += 1
        gap = row[L.D_GAPNEG] + row[L.D_GAPPOS]
        contact = gap == 0.0 or op.torque[d] != 0.0
        k, damping = (row[L.D_KTRANS], row[L.D_CTRANS]) if contact else (0.0, 0.0)
        jm = row[L.D_JMOTOR]
        a[wn + i, tw] = k / inertia
        a[wn + i, wm] = damping / (n * inertia)
        a[wn + i, wn + i] -= damping / inertia
        a[wm, wt + d] = 1.0 / jm
        a[wm, tw] = -k / (n * jm)
        a[wm, wm] = -(damping / n**2 + row[L.D_BMOTOR]) / jm
        a[wm, wn + i] = damping / (n * jm)
        a[tw, wm] = 1.0 / n
        a[tw, wn + i] = -1.0
