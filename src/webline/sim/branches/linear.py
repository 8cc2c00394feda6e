"""Linear models of a branched line at its operating point (docs/branching.md, "Linear models").

The plant is the compiled right-hand side ``sim.branches.loop.plant.rhs`` itself, differentiated
by central finite differences at the operating point (``sim.branches.equilibrium``), so the
model follows the kernel wherever it changes; a test checks it against the Jacobian derived
by hand from (B1)-(B4). States kept: span stretches [N] (= tensions on a taut span), node
speeds ω [rad/s], motor torques [N·m], a laminate's layers' strain offsets [N]
(``loop.laminate``). The roll radii are frozen at the operating point (they
change over minutes, the dynamics over seconds, as on a chain: thesis Sec. 4.1's set of
radii), and the web-length counters are outputs, not dynamics: both are left out.

The closed loop adds every drive's controller (``kernel.control_tick``) in continuous time,
as the chain's does (PI: speed and tension integrators; saturation off at the point), and
the section observers' states (``sim.branches.drives.observer``)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

import numpy as np

from webline.model.web_graph import BranchedLine, load_branched
from webline.sim.branches.dancer_views import linear_states as dancer_linear_states
from webline.sim.branches.dancer_views import load_column, reading_row
from webline.sim.branches.drives.decentral import ensure_prepared, linear_rows
from webline.sim.branches.drives.draw import draw_coefficients
from webline.sim.branches.drives.drive_trains import train_states
from webline.sim.branches.drives.observer import observer_names, observer_rows
from webline.sim.branches.equilibrium import BranchPoint, operating_point
from webline.sim.branches.equilibrium import analysis_time as analysis_time  # (its home was here)
from webline.sim.branches.findings.web_findings import felt_rows, felt_wound_rows
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import node_inertia, rhs
from webline.sim.branches.loop.transmission import reflected_motor
from webline.sim.branches.plan import BranchPlan, compile_branches
from webline.sim.branches.traction import slip_rate_bound
from webline.sim.branches.winder import linear_winder_rows
from webline.sim.linear.linearize import LinearModel
from webline.sim.linear.stability import SHARE, UnstableMode, tolerance, unstable_modes
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.sim.linear.linear_system import LinearSystem

#: central-difference step, relative to each state's scale (``_scales``). The right-hand
#: side is affine or bilinear (T·v) in the kept states at a taut operating point, so the
#: central difference has no truncation error there but the tanh of Coulomb friction's; the
#: step only trades rounding (eps·|f|/h): 1e-5 of the scale leaves ~1e-9 relative error.
FD_STEP = 1e-5


def kept_states(plan: BranchPlan, radii: bool = False) -> np.ndarray:
    """Indices into the kernel's state of the linear model's states: stretches, ω, (with
    ``radii`` the roll radii,) torques, the core speeds of a differential shaft's lanes."""
    off_r, off_tq, off_q = (plan.offsets[B.O_RADIUS], plan.offsets[B.O_TORQUE],
                            plan.offsets[B.O_WEB])
    return np.concatenate([np.arange(off_tq if radii else off_r),
                           np.arange(off_tq, off_q),
                           np.arange(plan.offsets[B.O_CORE], plan.offsets[B.O_ANGLE]),
                           [s for s, _ in train_states(plan.line, plan.di)],  # motor ω, twist
                           dancer_linear_states(plan)[0],
                           _layer_states(plan)]).astype(np.int64)


def state_names(plan: BranchPlan, radii: bool = False) -> list[str]:
    """Names of the plant's states, as the chain's (``span_tension``, ``node_omega``,
    ``node_torque``; with ``radii`` also ``node/web_radius``)."""
    line = plan.line
    rolls = ([f"{line.spec.rollers[r.node].name}/{line.spec.webs[r.web].name}_radius"
              for r in line.rolls] if radii else [])
    cores = [f"{line.spec.rollers[line.rolls[j].node].name}/"
             f"{line.spec.webs[line.rolls[j].web].name}_core_omega" for j in plan.cores[:, 0]]
    return ([f"{s.name}_tension" for s in line.spans]
            + [f"{r.name}_omega" for r in line.spec.rollers] + rolls
            + [f"{line.spec.rollers[i].name}_torque" for i in line.drives] + cores
            + [name for _, name in train_states(plan.line, plan.di)]
            + dancer_linear_states(plan)[1]
            + [f"{line.spans[int(plan.lawi[t, B.LI_SPAN])].name}/"
               f"{line.spec.webs[int(plan.lawi[t, B.LI_WEB])].name}_offset"
               for t in np.nonzero(plan.lawi[:, B.LI_STATE] >= 0)[0]])


def _layer_states(plan: BranchPlan) -> np.ndarray:
    """The bonded layers' offset states (``loop.laminate``: advected with the web; their
    lengths in and out are counters, left out as the webs' are)."""
    return plan.lawi[plan.lawi[:, B.LI_STATE] >= 0, B.LI_STATE]


def wound_webs(plan: BranchPlan) -> list[int]:
    """Webs that start at an unwind (their wound-in tension is an input)."""
    return [w for w in range(plan.webs.shape[0])
            if plan.si[plan.webs[w, B.WB_FIRST], B.S_SRC] == B.SRC_WOUND]


def _scales(point: BranchPoint, keep: np.ndarray) -> np.ndarray:
    """Scale of each kept state for the difference step: |value|, at least 1 N (stretch),
    1 rad/s (ω), 1 m (radius) or 1 N·m (torque)."""
    return np.maximum(np.abs(point.x[keep]), 1.0)


def plant_matrices(plan: BranchPlan, point: BranchPoint,
                   radii: bool = False) -> tuple[np.ndarray, ...]:
    """(A, B, E) of the plant at ``point``: dx = A x + B u + E w, x the kept states
    (``state_names``), u the motor torque commands [N·m], w the wound-in tensions [N] of
    ``wound_webs``; central differences of ``kernel.rhs`` (``FD_STEP``)."""
    keep = kept_states(plan, radii)
    dx, work = np.zeros(plan.n_x), plan.scratch()
    tables = plan.tables()

    def f(x: np.ndarray, cmd: np.ndarray, wound: np.ndarray) -> np.ndarray:
        rhs(x, cmd, wound, *tables, dx, work)
        return dx[keep].copy()

    def column(which: int, m: int, h: float) -> np.ndarray:
        args = [point.x.copy(), point.torque.copy(), plan.wound.copy()]
        args[which][m] += h
        up = f(*args)
        args[which][m] -= 2 * h
        return (up - f(*args)) / (2 * h)

    scales = _scales(point, keep)
    a = np.column_stack([column(0, int(m), FD_STEP * s)
                         for m, s in zip(keep, scales, strict=True)])
    # torque commands and wound-in tensions enter linearly: any step is exact
    b = np.column_stack([column(1, d, 1.0) for d in range(plan.di.shape[0])])
    webs = wound_webs(plan)
    e = (np.column_stack([column(2, w, 1.0) for w in webs]) if webs
         else np.zeros((len(keep), 0)))
    return a, b, e


def felt_tension_rows(plan: BranchPlan, point: BranchPoint, radii: bool = False) -> np.ndarray:
    """Rows [N per state unit] of the span tensions the rollers and loadcells feel over the
    kept states (``sim.branches.web_laws.felt_rows``; [I 0] for linear elastic webs)."""
    keep = kept_states(plan, radii)
    return felt_rows(plan, point.x, keep, FD_STEP * _scales(point, keep))


def speed_arm(plan: BranchPlan, point: BranchPoint, i: int) -> float:
    """Radius [m] converting node ``i``'s ω to the surface speed its drive measures (its roll's
    at the operating point), or the roller's radius."""
    d = int(plan.nodes[i, B.N_DRIVE])
    j = plan.di[d, B.DI_ROLL] if d >= 0 else -1
    return float(point.x[plan.offsets[B.O_RADIUS] + j]) if j >= 0 else float(
        plan.nodes[i, B.N_RADIUS])


def controller_matrices(plan: BranchPlan, point: BranchPoint,
                        radii: bool = False) -> tuple[np.ndarray, ...]:
    """Every drive's cascaded PI (``kernel.control_tick``) in continuous time, linear at
    ``point``: u = Kx x + Ki q + Kr r, dq/dt = Gx x + Gi q + Gr r; q = (speed integrator
    [N·m] of every drive, then tension integrator [m/s] of every drive with a zone), r = (line
    speed [m/s], then each loadcell's reference [N] in ``plan.cells`` order). With
    ``radii`` the measured speed r ω also varies with the roll's radius."""
    ensure_prepared(plan)
    n_x, n_d = len(kept_states(plan, radii)), plan.di.shape[0]
    zoned = _zoned(plan)
    n_q, n_r = n_d + len(zoned), 1 + plan.cells.shape[0]
    kx, ki, kr = np.zeros((n_d, n_x)), np.zeros((n_d, n_q)), np.zeros((n_d, n_r))
    gx, gi, gr = np.zeros((n_q, n_x)), np.zeros((n_q, n_q)), np.zeros((n_q, n_r))
    off_w = plan.offsets[B.O_OMEGA]
    felt = felt_tension_rows(plan, point, radii)
    kept = kept_states(plan, radii)
    draw = draw_coefficients(plan)  # the feedforward's draw follows the references
    for d in range(n_d):
        i, row = int(plan.di[d, B.DI_NODE]), plan.df[d]
        if plan.di[d, B.DI_FAMILY] != B.FAMILY_PI:  # state feedback, adaptive
            kx[d], ki[d], kr[d], gx[d], gi[d], gr[d] = linear_rows(plan, point, d, n_x, n_q,
                                                                   kept)
            continue
        # e_v = v_line ff + σ (kp_t e_t + q_t) - r ω,  e_t = Σ (ref_c - T_c)
        ev_x, ev_q, ev_r = np.zeros(n_x), np.zeros(n_q), np.zeros(n_r)
        ev_r[0] = point.ratio[d]
        ev_r[1:] += point.line_speed * point.ratio[d] * draw[d]  # (loop.draw, errata E-B4)
        motor = int(plan.di[d, B.DI_TSTATE])
        if motor >= 0 and row[B.D_FEEDBACK] > 0:  # the motor's encoder: ω_m / n
            kept = kept_states(plan, radii)
            ev_x[int(np.flatnonzero(kept == motor)[0])] = -speed_arm(plan, point, i) / row[
                B.D_RATIO] * row[B.D_VSCALE]  # (its encoder's scale, spec.sensors)
        else:
            ev_x[off_w + i] = -speed_arm(plan, point, i) * row[B.D_VSCALE]
        if radii and plan.di[d, B.DI_ROLL] >= 0:
            ev_x[plan.offsets[B.O_RADIUS] + plan.di[d, B.DI_ROLL]] = -point.x[off_w + i] * row[
                B.D_VSCALE]
        if d in zoned:
            q_t = n_d + zoned.index(d)
            ev_q[q_t] = row[B.D_SIGMA]
            first = int(plan.di[d, B.DI_CELLS])
            for c in range(first, first + int(plan.di[d, B.DI_NCELLS])):
                k = int(plan.cells[c, 0])
                reading = reading_row(plan, c, kept)  # a dancer's position or tension
                on_x, on_ref = (-plan.sf[k, B.SF_TGAIN] * felt[k], 1.0) if reading is None else (
                    reading)  # (a loadcell: its gain, spec.sensors)
                ev_x += row[B.D_SIGMA] * row[B.D_KPT] * on_x
                ev_r[1 + c] += row[B.D_SIGMA] * row[B.D_KPT] * on_ref
                gx[q_t] += row[B.D_KIT] * on_x
                gr[q_t, 1 + c] = row[B.D_KIT] * on_ref
        gain = 1.0
        if row[B.D_ADAPTIVE] > 0.0:  # the speed gains follow the roll's inertia
            inertia = node_inertia(i, point.x, plan.const.offsets, plan.nodes, plan.rolls) + (
                reflected_motor(d, plan.const.di, plan.df))
            gain = inertia / (row[B.D_RATIO] * speed_arm(plan, point, i)) / row[B.D_GAINNORM]
        kps, kis = row[B.D_KPS] * gain, row[B.D_KIS] * gain
        kx[d], ki[d], kr[d] = kps * ev_x, kps * ev_q, kps * ev_r
        ki[d, d] += 1.0
        gx[d], gi[d], gr[d] = kis * ev_x, kis * ev_q, kis * ev_r
        if plan.di[d, B.DI_WINDER] != B.WINDER_NONE:  # a centre winder (docs/winder.md W3-W4)
            linear_winder_rows(plan, d, speed_arm(plan, point, i),
                               n_d + zoned.index(d) if d in zoned else None, kx, ki, kr, gx,
                               gi, gr)
    keep = _integrators(plan)  # a state-feedback drive has none; then the observers' states
    return observer_rows(plan, point, kept, (kx, ki[:, keep], kr, gx[keep],
                                             gi[np.ix_(keep, keep)], gr[keep]))


def _zoned(plan: BranchPlan) -> list[int]:
    """The PI drives with a tension loop (a tension integrator each)."""
    return [d for d in range(plan.di.shape[0])
            if plan.di[d, B.DI_NCELLS] > 0 and plan.di[d, B.DI_FAMILY] == B.FAMILY_PI]


def _integrators(plan: BranchPlan) -> list[int]:
    """The controller states kept: each drive's speed integrator (an adaptive drive's: its
    friction estimate; an MRAC's: its bias, its gains' changes being second order at the
    operating point; none for state feedback), then the tension integrators."""
    n_d = plan.di.shape[0]
    return ([d for d in range(n_d) if plan.di[d, B.DI_FAMILY] != B.FAMILY_STATE_FEEDBACK]
            + list(range(n_d, n_d + len(_zoned(plan)))))


def integrator_names(plan: BranchPlan) -> list[str]:
    """Names of the closed loop's controller states (``_integrators``)."""
    drives = [plan.line.spec.rollers[i].name for i in plan.line.drives]
    kind = {B.FAMILY_ADAPTIVE: "friction_estimate", B.FAMILY_MRAC: "mrac_bias"}
    names = [f"{n}_{kind.get(int(plan.di[d, B.DI_FAMILY]), 'speed_integral')}"
             for d, n in enumerate(drives)]
    names += [f"{drives[d]}_tension_integral" for d in _zoned(plan)]
    return [names[q] for q in _integrators(plan)] + observer_names(plan)


def wound_gains(plan: BranchPlan, point: BranchPoint,
                radii: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(Kw, Gw): what the wound-in tensions of ``wound_webs`` add to the torque commands and
    integrators through the loadcells (u += Kw w, dq/dt += Gw w): a Kelvin-Voigt loadcell
    span feels τ ds/dt, which reads the tension its web carries in (``felt_wound_rows``);
    zero for elastic spans."""
    webs = wound_webs(plan)
    felt = felt_wound_rows(plan, point.x, webs)
    n_d = plan.di.shape[0]
    zoned = [d for d in range(n_d) if plan.di[d, B.DI_NCELLS] > 0]
    kw, gw = np.zeros((n_d, len(webs))), np.zeros((n_d + len(zoned), len(webs)))
    for d in zoned:
        i, row = int(plan.di[d, B.DI_NODE]), plan.df[d]
        first = int(plan.di[d, B.DI_CELLS])
        ev_w = np.zeros(len(webs))
        for c in range(first, first + int(plan.di[d, B.DI_NCELLS])):
            k = int(plan.cells[c, 0])
            if plan.cells[c, B.CELL_DANCER] >= 0:  # a dancer's position: no loadcell
                continue
            ev_w -= row[B.D_SIGMA] * row[B.D_KPT] * plan.sf[k, B.SF_TGAIN] * felt[k]
            gw[n_d + zoned.index(d)] -= row[B.D_KIT] * plan.sf[k, B.SF_TGAIN] * felt[k]
        gain = 1.0
        if row[B.D_ADAPTIVE] > 0.0:  # as controller_matrices
            inertia = node_inertia(i, point.x, plan.const.offsets, plan.nodes, plan.rolls) + (
                reflected_motor(d, plan.const.di, plan.df))
            gain = inertia / (row[B.D_RATIO] * speed_arm(plan, point, i)) / row[B.D_GAINNORM]
        kw[d], gw[d] = row[B.D_KPS] * gain * ev_w, row[B.D_KIS] * gain * ev_w
    return kw, gw


def branch_linear_model(plan: BranchPlan, point: BranchPoint,
                        loop: Literal["open", "closed"] = "closed", *,
                        radii: bool = False) -> LinearModel:
    """Linear model of ``plan`` at ``point``, named signals. Open: inputs the motor torque
    commands [N·m] and wound-in tensions [N]. Closed: inputs the line speed reference [m/s],
    each loadcell's tension reference [N] and the wound-in tensions. Outputs (both): span
    tensions [N] and each node's surface speed [m/s] (its drive's roll radius x ω). With
    ``radii`` the roll radii are states too (slow: they integrate the web wound or unwound)."""
    line = plan.line
    a, b, e = plant_matrices(plan, point, radii)
    names = state_names(plan, radii)
    n_s, n_n, n_x = len(line.spans), plan.nodes.shape[0], a.shape[0]
    c = np.zeros((n_s + n_n, n_x))
    c[:n_s] = felt_tension_rows(plan, point, radii)  # (web laws: F'(s), a damper's τ ds/dt)
    for i in range(n_n):
        c[n_s + i, n_s + i] = speed_arm(plan, point, i)
        d = int(plan.nodes[i, B.N_DRIVE])
        if radii and d >= 0 and plan.di[d, B.DI_ROLL] >= 0:  # v = r ω: r varies too
            c[n_s + i, plan.offsets[B.O_RADIUS] + plan.di[d, B.DI_ROLL]] = point.x[n_s + i]
    outputs = ([f"{s.name}_tension" for s in line.spans]
               + [f"{r.name}_speed" for r in line.spec.rollers])
    wound = [f"{line.spec.webs[w].name}_wound_in_tension" for w in wound_webs(plan)]
    drives = [line.spec.rollers[i].name for i in line.drives]
    if loop == "open":
        return LinearModel(a, np.hstack([b, e]), c, names,
                           [f"{n}_torque_cmd" for n in drives] + wound, outputs)
    kx, ki, kr, gx, gi, gr = controller_matrices(plan, point, radii)
    n_q = gi.shape[0]
    a_cl = np.block([[a + b @ kx, b @ ki], [gx, gi]])
    b_cl = np.block([[b @ kr, e], [gr, np.zeros((n_q, e.shape[1]))]])
    if plan.kv.shape[0] and e.shape[1]:  # a damper's loadcell reads τ ds/dt: the wound-in too
        kw, gw = wound_gains(plan, point, radii)
        b_cl[:n_x, -e.shape[1]:] += b @ kw
        b_cl[n_x:, -e.shape[1]:] = gw
    keep = kept_states(plan, radii)
    for cell in range(plan.cells.shape[0]):  # a dancer's default load follows its reference
        b_cl[:n_x, 1 + cell] += load_column(plan, cell, keep)
    c_cl = np.hstack([c, np.zeros((c.shape[0], n_q))])
    names = names + integrator_names(plan)
    inputs = (["line_speed_ref"]
              + [f"{line.spans[int(k)].name}_tension_ref" for k in plan.cells[:, 0]] + wound)
    return LinearModel(a_cl, b_cl, c_cl, names, inputs, outputs)


def linear_model(line: BranchedLine | str, t: float = 0.0, *,
                 loop: Literal["open", "closed"] = "closed") -> LinearModel:
    """Linear model of branched ``line`` at its operating point at time ``t`` [s] of its
    references (``branch_linear_model``)."""
    plan = compile_branches(load_branched(line))
    return branch_linear_model(plan, operating_point(plan, t), loop)


def fastest_rate(plan: BranchPlan, point: BranchPoint) -> float:
    """Largest |eigenvalue| [1/s] of the open- and closed-loop models at ``point``: what the
    fixed RK4 step must resolve (as the chain's ``sim.linear.linearize.fastest_mode``), and
    the spans round a slipping roller (``traction.slip_rate_bound``)."""
    model = max(float(np.max(np.abs(np.linalg.eigvals(branch_linear_model(plan, point, loop).a))))
                for loop in ("open", "closed"))
    top = float(np.max(np.abs(plan.prof_v[plan.prof_off[0]:plan.prof_off[1]])))
    return max(model, slip_rate_bound(plan.line, plan.nodes, plan.sf, top))  # (stuck model)


def sampled_unstable_modes(plan: BranchPlan, point: BranchPoint) -> list[UnstableMode]:
    """The modes of ``sampled_closed_loop`` with Re λ = Re ln(μ) / dt above
    ``sim.linear.stability.tolerance``, fastest-growing first, with the states they live in
    (participation factors of the sampled loop's eigenvectors)."""
    names = branch_linear_model(plan, point, "closed").states
    mu, right = np.linalg.eig(sampled_closed_loop(plan, point))
    values = np.log(mu.astype(complex)) / plan.dt
    tol = tolerance(values)
    if not np.any(values.real > tol):
        return []
    participation = np.abs(right * np.linalg.inv(right).T)
    out = []
    for j in np.argsort(-values.real):
        if values[j].real <= tol or values[j].imag < 0.0:
            continue
        share = participation[:, j] / participation[:, j].sum()
        order = [int(s) for s in np.argsort(-share) if share[s] >= SHARE][:4]
        out.append(UnstableMode(complex(values[j]),
                                tuple((names[s], float(share[s])) for s in order)))
    return out


def stability_findings(plan: BranchPlan, point: BranchPoint, t: float) -> list[Finding]:
    """An ``unstable`` finding per closed-loop mode of ``plan`` at ``point`` (time ``t`` [s])
    growing faster than ``sim.linear.stability.tolerance``, naming the states it lives in:
    the continuous model's modes, or where none grows there, the sampled loop's
    (``sampled_closed_loop``: the hold's delay can destabilize a fast mode)."""
    model = branch_linear_model(plan, point, "closed")
    modes, what = unstable_modes(model.a, model.states), "closed-loop mode"
    if not modes:
        modes = sampled_unstable_modes(plan, point)
        what = (f"closed-loop mode (controllers sampled at {1.0 / plan.dt:.4g} Hz, torque "
                "held; the continuous model's modes all decay)")
    out = []
    for mode in modes:
        states = ", ".join(f"{name} {share:.0%}" for name, share in mode.states)
        out.append(Finding("unstable", "unstable_mode", mode.states[0][0] if mode.states else "",
                           f"{what} λ = {mode.eigenvalue.real:.3g} ± "
                           f"{abs(mode.eigenvalue.imag):.3g}j 1/s grows "
                           f"({mode.frequency_hz:.3g} Hz, ζ = {mode.damping:.3g}) at t = {t:g} s, "
                           f"in {states}", None, {
                               "eigenvalue_real": mode.eigenvalue.real,
                               "eigenvalue_imag": mode.eigenvalue.imag,
                               "frequency_hz": mode.frequency_hz, "damping_ratio": mode.damping,
                               "analysis_time_s": t, "states": [n for n, _ in mode.states],
                               "participation": [s for _, s in mode.states]}))
    return out


def linearize_branched(line: BranchedLine | str, t: float = 0.0, *,
                       loop: Literal["open", "closed"] = "closed") -> LinearSystem:
    """``linear_model`` of branched ``line`` at time ``t`` [s] as a python-control
    ``StateSpace`` (``LinearSystem``) with named signals, as ``webline.linearize`` returns."""
    from webline.sim.linear.linear_system import LinearSystem  # python-control: on use

    line = load_branched(line)
    model = linear_model(line, t, loop=loop)
    name = line.name.replace(".", "_") + ("-plant" if loop == "open" else "-closed-loop")
    return LinearSystem(model.a, model.b, model.c,
                        np.zeros((len(model.outputs), len(model.inputs))), states=model.states,
                        inputs=model.inputs, outputs=model.outputs, name=name)


def sampled_closed_loop(plan: BranchPlan, point: BranchPoint) -> np.ndarray:
    """The closed loop as the run has it, one controller period ``plan.dt`` [s] per step:
    z_{k+1} = M z_k, z = (plant states, integrators) at a tick. The plant over a period with
    the torque command held, x+ = Φ x + Γ u (Φ = e^{A dt}, Γ = ∫ e^{As} ds B: exact, the
    run's RK4 aside); the controllers as ``kernel.control_tick`` orders them: u from the
    integrators before their update, then q+ = q + dt (Gx x + Gi q). Its eigenvalues μ are
    the sampled loop's modes, λ = ln(μ) / dt [1/s]."""
    from scipy.linalg import expm

    a, b, _ = plant_matrices(plan, point)
    kx, ki, _, gx, gi, _ = controller_matrices(plan, point)
    n, m, dt = a.shape[0], b.shape[1], plan.dt
    augmented = np.zeros((n + m, n + m))
    augmented[:n, :n], augmented[:n, n:] = a, b
    step = expm(augmented * dt)
    phi, gamma = step[:n, :n], step[:n, n:]
    return np.block([[phi + gamma @ kx, gamma @ ki],
                     [dt * gx, np.eye(gi.shape[0]) + dt * gi]])
