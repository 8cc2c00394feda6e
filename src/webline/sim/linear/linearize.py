"""Linear models of a line at its operating point, as named python-control state-space systems.

The roll radii are frozen at the operating point (they change over minutes, the dynamics over
seconds), as in thesis Sec. 4.1's set U of radii and Ch. 6's section models. Eccentricity is
left out (it makes the model periodic), and the web sticks on traction rollers and nips. A
nip's pressure roller is in its roller's J and b (docs/winder.md N1). The Jacobian is analytic,
from the same equations as the kernel; a finite-difference check of it is part of the tests.
The plant's matrices come from ``sim.linear.linear_plant``; this module adds the controllers (the
closed loop), caches the models on the plan and bounds their fastest mode.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from webline.errors import LineFileError
from webline.line import Line, load_line
from webline.model.operating_point import OperatingPoint, operating_point
from webline.sim.core import viscoelastic, winder
from webline.sim.core.plan import Plan, compile_plan
from webline.sim.elements import layout as L
from webline.sim.linear import dancer_linear as dancers
from webline.sim.linear.fastest import spectral_radius_bound
from webline.sim.linear.linear_plant import plan_plant, plan_state_names

if TYPE_CHECKING:
    import control


def _speed_state(plan: Plan, d: int, i: int) -> int:
    """State whose speed drive ``d`` measures: its motor's across a compliant transmission
    with motor-side feedback, else its roller's."""
    motor = plan.linear_motor_state(d)
    if motor is not None and plan.drives[d, L.D_FEEDBACK] > 0:
        return motor
    return plan.line.n_spans + i


def _tension_sensor(plan: Plan, d: int) -> tuple[int, float]:
    """(linear state, d(measured tension)/d(state)) of drive ``d``'s tension measurement: its
    zone's loadcell span (its gain, ``spec.sensors``), or a dancer
    (``sim.core.dancer.measurement_row``)."""
    line = plan.line
    n_c = int(np.sum(plan.drives[:, L.D_TSTATE] >= 0))
    first = line.n_spans + line.n_nodes + len(line.drives) + 2 * n_c
    found = dancers.measurement_row(plan, d, first)
    if found is not None:
        return found
    return int(plan.drives[d, L.D_LOADCELL]), float(plan.drives[d, L.D_TGAIN])


def _speed_scale(plan: Plan, d: int) -> float:
    """The measured speed's state per measured roller speed: n for a motor encoder, over
    the encoder's scale (``spec.sensors``)."""
    scale = float(plan.drives[d, L.D_VSCALE])
    if plan.linear_motor_state(d) is not None and plan.drives[d, L.D_FEEDBACK] > 0:
        return float(plan.drives[d, L.D_RATIO]) / scale
    return 1.0 / scale


def controller_matrices(plan: Plan, op: OperatingPoint) -> tuple[np.ndarray, ...]:
    """Every drive's controller in continuous time, linear at ``op``.

    u = Kx x + Ki xi + Kr ref, dxi/dt = Gx x + Gi xi + Gr ref, with xi = (speed integrator
    [N·m], tension integrator [m/s]) per drive (used by cascaded PI only) and ref = (line
    speed, zone tension references). Decentralized drives: u = u_eq + f - K x, with adaptive
    estimates frozen at their design values; the dependence of their speed references on the
    tension references (the draw, of order T/EA) is left out of Kr.
    """
    line = plan.line
    for user in np.flatnonzero(plan.drives[:, L.D_FAMILY] == L.FAMILY_USER):
        raise LineFileError(line.source, f"rollers[{line.drives[int(user)]}].controller",
                            "a python controller has no linear model in webline: analyses "
                            "and studies (sweeps, Monte Carlo) need a built-in controller; "
                            "run it with simulate or Session")
    n_d = len(line.drives)
    n = len(plan_state_names(plan))
    n_ref = 1 + len(line.zones)
    kx, ki, kr = np.zeros((n_d, n)), np.zeros((n_d, 2 * n_d)), np.zeros((n_d, n_ref))
    gx, gi, gr = np.zeros((2 * n_d, n)), np.zeros((2 * n_d, 2 * n_d)), np.zeros((2 * n_d, n_ref))
    ea = line.ea
    refs = np.array([op.line_speed] + [op.tension[z.loadcell] for z in line.zones])
    master_up = int(plan.offsets[6])  # profile index = reference index
    for d, i in enumerate(line.drives):
        row = plan.drives[d]
        direction = {0: -1.0, line.n_nodes - 1: 1.0}.get(i, 0.0)
        if winder.linear_rows(row, direction, op.radius[i], line.n_spans + i,
                              int(row[L.D_REF]), kx[d], kr[d]):
            continue  # open-loop tension control: no feedback but the compensation's
        if row[L.D_FAMILY] != L.FAMILY_PI:
            rows = _decentralized_rows(plan, op, d, i, refs, n)
            kx[d] += rows[0]
            kr[d] += rows[1]
            continue
        up = int(row[L.D_UPREF])
        t_up = line.unwind.wound_in_tension if up < 0 else refs[up]
        t_m = refs[master_up]
        # e_v = ff(refs) + σ(kp_t (T_ref - T_lc) + I_t) - r ω   (linear part)
        ev_x, ev_i, ev_r = np.zeros(n), np.zeros(2 * n_d), np.zeros(n_ref)
        if line.exact:  # ff = V (EA + T_up)/(EA + T_m) (``physics.span.draw_ratio``)
            ev_r[0] = (ea + t_up) / (ea + t_m)
            ev_r[master_up] += -op.line_speed * (ea + t_up) / (ea + t_m) ** 2
            if up >= 0:
                ev_r[up] += op.line_speed / (ea + t_m)
        else:  # ff = V (EA - T_m)/(EA - T_up) (thesis 6.22)
            ev_r[0] = (ea - t_m) / (ea - t_up)
            ev_r[master_up] += -op.line_speed / (ea - t_up)
            if up >= 0:
                ev_r[up] += op.line_speed * (ea - t_m) / (ea - t_up) ** 2
        radius = op.radius[i]
        ev_x[_speed_state(plan, d, i)] = -radius / _speed_scale(plan, d)
        gain = 1.0
        if row[L.D_ADAPTIVE] > 0:
            gain = op.inertia[i] / (plan.nodes[i, L.N_RATIO] * radius) / row[L.D_GAINNORM]
        if row[L.D_ROLE] == L.ROLE_TENSION:
            sigma, ref = row[L.D_SIGMA], int(row[L.D_REF])
            sensor, slope = _tension_sensor(plan, d)
            ev_x[sensor] += -sigma * row[L.D_KPT] * slope
            ev_r[ref] += sigma * row[L.D_KPT]
            ev_i[2 * d + 1] = sigma
            gx[2 * d + 1, sensor] = -row[L.D_KIT] * slope
            gr[2 * d + 1, ref] = row[L.D_KIT]
        kps, kis = row[L.D_KPS] * gain, row[L.D_KIS] * gain
        kx[d] += kps * ev_x
        ki[d] = kps * ev_i
        kr[d] += kps * ev_r
        ki[d, 2 * d] += 1.0
        gx[2 * d], gi[2 * d], gr[2 * d] = kis * ev_x, kis * ev_i, kis * ev_r
    return kx, ki, kr, gx, gi, gr


def _decentralized_rows(plan: Plan, op: OperatingPoint, d: int, i: int, refs: np.ndarray,
                        n: int) -> tuple[np.ndarray, np.ndarray]:
    """(Kx, Kr) rows of a state-feedback or adaptive drive (see ``controller_matrices``) over
    the ``n`` plant states."""
    line, row = plan.line, plan.drives[d]
    n_s = line.n_spans
    kx = np.zeros(n)
    kr = np.zeros(len(refs))
    radius, ratio = op.radius[i], plan.nodes[i, L.N_RATIO]
    gain = 1.0
    if row[L.D_ADAPTIVE] > 0:
        gain = op.inertia[i] / (ratio * radius) / row[L.D_GAINNORM]
    kx[_speed_state(plan, d, i)] = -gain * row[L.D_KV] * radius / _speed_scale(plan, d)
    # the node's reference speed per line reference: the draw (the op's speeds are the web's,
    # slower than the reference by the master encoder's scale, spec.sensors)
    master_scale = plan.drives[line.drives.index(line.master), L.D_VSCALE]
    speed_per_line = master_scale * op.speed[i] / op.line_speed if op.line_speed else 1.0
    kr[0] = gain * row[L.D_KV] * speed_per_line
    if row[L.D_FAMILY] == L.FAMILY_ADAPTIVE:  # b̂ (ω - ω_ref)/n with b̂ frozen at its guess
        kx[_speed_state(plan, d, i)] += row[L.D_BMODEL] / (ratio * _speed_scale(plan, d))
    else:  # u_eq's friction term b_model ω_ref/n
        kr[0] += row[L.D_BMODEL] * speed_per_line / (radius * ratio)
    if row[L.D_ROLE] == L.ROLE_TENSION:
        sensor, slope = _tension_sensor(plan, d)
        kx[sensor] = -gain * row[L.D_KT] * slope
        kr[int(row[L.D_REF])] += gain * row[L.D_KT]
    for k, sign in ((i, -1.0), (i - 1, 1.0)):  # u_eq: -r (T_out - T_in) / n
        if 0 <= k < n_s:
            kr[1 + line.zone_of_span(k)] += sign * radius / ratio
    return kx, kr


@dataclass(frozen=True)
class LinearModel:
    """Matrices of a linear model (dx = A x + B u, y = C x) with the names of its signals."""

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    states: list[str]
    inputs: list[str]
    outputs: list[str]

    def __repr__(self) -> str:
        """Its size and a few names (the dataclass's repr printed every matrix)."""
        def few(names: list[str]) -> str:
            return ", ".join(names[:4]) + (", ..." if len(names) > 4 else "")

        return (f"<webline LinearModel: {len(self.states)} states, {len(self.inputs)} inputs "
                f"({few(self.inputs)}), {len(self.outputs)} outputs ({few(self.outputs)})>")


def linear_model(line: Line, t: float = 0.0, *, loop: Literal["open", "closed"] = "closed",
                 unwind_radius: float | None = None,
                 rewind_radius: float | None = None) -> LinearModel:
    """The matrices behind ``linearize`` (numpy only; see its docstring). At t = 0 with the
    initial radii it is the default plan's ``plan_linear_model``, built once per line."""
    plan = compile_plan(line)
    if t == 0.0 and unwind_radius is None and rewind_radius is None:
        return plan_linear_model(plan, loop=loop)
    op = operating_point(line, t, unwind_radius=unwind_radius, rewind_radius=rewind_radius)
    return _linear_model(plan, op, loop)


def plan_linear_model(plan: Plan, *, loop: Literal["open", "closed"] = "closed",
                      t: float = 0.0) -> LinearModel:
    """Linear model of ``plan`` (its controllers, at its sample rate's gains) at the plan's
    operating point ``plan.op`` (``t`` = 0), or at the equilibrium of its references at time
    ``t`` [s] with the initial roll radii; built once per plan, loop and ``t``, its arrays
    read-only."""
    key = ("linear_model", loop, t)
    if key not in plan.memo:
        plant = None
        if loop == "closed":  # the closed loop is built on the (cached) plant
            open_ = plan_linear_model(plan, loop="open", t=t)
            plant = (open_.a, open_.b[:, :-1], open_.b[:, -1:], open_.c)
        model = _linear_model(plan, _plan_op(plan, t), loop, plant)
        for array in (model.a, model.b, model.c):
            array.setflags(write=False)
        plan.memo[key] = model
    return plan.memo[key]  # type: ignore[return-value]


def _plan_op(plan: Plan, t: float) -> OperatingPoint:
    """The plan's operating point at time ``t`` [s] (``plan.op`` at 0), once per plan and t."""
    if t == 0.0:
        return plan.op
    if ("op", t) not in plan.memo:
        plan.memo[("op", t)] = operating_point(plan.line, t)
    return plan.memo[("op", t)]  # type: ignore[return-value]


def plan_eigenvalues(plan: Plan, *, loop: Literal["open", "closed"] = "closed",
                     t: float = 0.0) -> np.ndarray:
    """Eigenvalues [1/s] of ``plan_linear_model(plan, loop=loop, t=t).a``, computed once per
    plan, loop and ``t`` (read-only): the modes a stability check at that instant needs."""
    key = ("eigenvalues", loop, t)
    if key not in plan.memo:
        eig = np.linalg.eigvals(plan_linear_model(plan, loop=loop, t=t).a)
        eig.setflags(write=False)
        plan.memo[key] = eig
    return plan.memo[key]  # type: ignore[return-value]


def fastest_mode(plan: Plan) -> float:
    """Largest |eigenvalue| [1/s] of the plan's open- and closed-loop linear models at its
    operating point (what the fixed integration step must resolve), once per plan: exact for
    small lines, a rigorous upper bound within ~10 % for long ones
    (``webline.sim.linear.fastest.spectral_radius_bound``)."""
    if "fastest_mode" not in plan.memo:
        plan.memo["fastest_mode"] = max(spectral_radius_bound(plan_linear_model(plan, loop=loop).a)
                                        for loop in ("open", "closed"))
    return plan.memo["fastest_mode"]  # type: ignore[return-value]


def _linear_model(plan: Plan, op: OperatingPoint, loop: Literal["open", "closed"],
                  plant: tuple[np.ndarray, ...] | None = None) -> LinearModel:
    """``linear_model`` of the line of ``plan`` at ``op``, its controllers as in ``plan``;
    ``plant``: its (A, B, E, C) if already built."""
    line = plan.line
    a, b, e, c = plant if plant is not None else plan_plant(plan, op)
    states = plan_state_names(plan)
    outputs = ([f"{line.span_name(k)}_tension" for k in range(line.n_spans)]
               + [f"{line.node_name(i)}_speed" for i in range(line.n_nodes)])
    if loop == "open":
        inputs = [f"{line.node_name(i)}_torque_cmd" for i in line.drives] + ["wound_in_tension"]
        return LinearModel(a, np.hstack([b, e]), c, states, inputs, outputs)
    kx, ki, kr, gx, gi, gr = controller_matrices(plan, op)
    # keep the integrators that exist: PI drives only, and no tension loop on the master
    pi = plan.drives[:, L.D_FAMILY] == L.FAMILY_PI
    tension = plan.drives[:, L.D_ROLE] == L.ROLE_TENSION
    used = [j for j in range(2 * len(line.drives))
            if pi[j // 2] and (j % 2 == 0 or tension[j // 2])]
    ki, gx, gi, gr = ki[:, used], gx[used], gi[np.ix_(used, used)], gr[used]
    (kx, fk), (gx, fg) = (viscoelastic.measured(plan, g, c[:line.n_spans], e) for g in (kx, gx))
    # [[A + B Kx, B Ki], [Gx, Gi]] and [[B Kr, E + B Fk], [Gr, Fg]], filled in place
    # (np.block's checks cost more than the products on these small matrices)
    n, m, n_ref = a.shape[0], gi.shape[0], kr.shape[1]
    a_cl = np.empty((n + m, n + m))
    a_cl[:n, :n] = a + b @ kx
    a_cl[:n, n:] = b @ ki
    a_cl[n:, :n] = gx
    a_cl[n:, n:] = gi
    b_cl = np.empty((n + m, n_ref + 1))
    b_cl[:n, :n_ref] = b @ kr
    b_cl[:n, n_ref:] = e + b @ fk
    b_cl[n:, :n_ref] = gr
    b_cl[n:, n_ref:] = fg
    c_cl = np.zeros((c.shape[0], n + m))
    c_cl[:, :n] = c
    states += [f"{line.node_name(line.drives[j // 2])}_{('speed', 'tension')[j % 2]}_integral"
               for j in used]
    inputs = (["line_speed_ref"] + [f"zone{z + 1}_tension_ref" for z in range(len(line.zones))]
              + ["wound_in_tension"])
    return LinearModel(a_cl, b_cl, c_cl, states, inputs, outputs)


def system_matrix(line: Line, t: float = 0.0, *,
                  loop: Literal["open", "closed"] = "closed") -> np.ndarray:
    """State matrix A [SI] of the open- or closed-loop linear model at time ``t`` [s]."""
    return linear_model(line, t, loop=loop).a


def linearize(line: Line | str, t: float | str = 0.0, *,
              loop: Literal["open", "closed"] = "closed",
              unwind_radius: float | None = None,
              rewind_radius: float | None = None) -> control.StateSpace:
    """Linear model of ``line`` at its operating point at time ``t`` [s], roll radii [m] as
    given (default: initial), as a python-control ``StateSpace`` with named signals.

    ``loop="open"``: the plant; inputs are motor torque commands [N·m] and the wound-in
    tension [N]. ``loop="closed"``: plant with its continuous-time cascaded PI controllers;
    inputs are the line speed reference [m/s], each zone's tension reference [N] and the
    wound-in tension [N]. Outputs (both): span tensions [N] and web speeds [m/s]. Signals are
    named (``span1_tension``, ``master_speed``, ``unwind_torque_cmd``, ...; python-control
    reserves '.'). A ``LinearSystem`` (``webline.sim.linear.linear_system``): a ``StateSpace`` whose
    ``repr`` is a few lines.
    """
    from webline.errors import ArgumentError
    from webline.spec.ranges import argument

    t = argument(t, "time", "t", ">=0")  # "1 s" and pint quantities too, as the CLI takes
    if loop not in ("open", "closed"):
        raise ArgumentError(f"loop: must be 'open' or 'closed', got {loop!r}")
    model = linear_model(load_line(line), t, loop=loop, unwind_radius=unwind_radius,
                         rewind_radius=rewind_radius)
    # python-control reserves '.' in system names (subsystem.signal); a line name is free text
    name = load_line(line).name.replace(".", "_") + ("-plant" if loop == "open" else "-closed-loop")
    from webline.sim.linear.linear_system import LinearSystem

    return LinearSystem(model.a, model.b, model.c, np.zeros((len(model.outputs),
                                                             len(model.inputs))),
                        states=model.states, inputs=model.inputs, outputs=model.outputs,
                        name=name)
