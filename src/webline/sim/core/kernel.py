"""The compiled simulation loop: plant and sampled controllers in one numba loop.

Between controller ticks the torque commands are held (zero-order hold) and the plant is
integrated with fixed-step RK4 sub-steps; at each tick every controller samples the state
and issues a saturated torque command (``webline.sim.drives.controllers``).

The loop is compiled once per line *structure* (``compiled_loop``): the integer tables of
``webline.sim.elements.layout`` are frozen into it as constants, so its loops over nodes and drives
unroll and the branches on node kind, transmission, controller family and features fold
away. Parameters stay run-time arrays, so changing a value never recompiles.

State vector layout (block starts in ``plan.offsets``, names in ``plan.state_names``): span
stretch forces [N], node angular speeds [rad/s], unwind and rewind radii [m], motor torques
[N·m], eccentric-roller angles [rad], motor speed [rad/s] and twist [rad] of each compliant
transmission, and two web-length integrals [m] (unstrained web unwound and rewound).
"""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.physics import roll, roller, slip, span, web_law
from webline.sim.core.plan import StructureKey, structure_arrays
from webline.sim.drives.controllers import control_tick
from webline.sim.drives.dancer_taper import load_factor
from webline.sim.drives.user_loop import STATUS_USER_NONFINITE, user_nonfinite
from webline.sim.elements import layout as L
from webline.sim.elements.break_hold import brake_band, brake_drag
from webline.sim.elements.dancer_loop import dancer_rate, span_motion
from webline.sim.elements.envelope import envelope, node_arm
from webline.sim.elements.friction_loop import STICK_SPEED, breakaway, stick, table_torque
from webline.sim.elements.signals import jit, loop_njit, njit, profile_at
from webline.sim.elements.splice import apply_splices
from webline.sim.elements.transmission_loop import compliant_torque
from webline.sim.elements.web_state import (
    record_width,
    update_slip,
    wound_in,
)

if TYPE_CHECKING:
    from webline.sim.core.plan import Plan

_tension: Any = jit(span.tension)
_kv_tension: Any = jit(span.kelvin_voigt_tension)
_exact_rate: Any = jit(span.exact_stretch_rate)
_length_change: Any = jit(span.length_change_rate)
_unstrained_flow: Any = jit(span.unstrained_flow)
_law_tension: Any = jit(web_law.law_tension)
_law_stretch: Any = jit(web_law.law_stretch)
_roll_inertia: Any = jit(roll.roll_inertia)
_radius_rate: Any = jit(roll.radius_rate)
_friction: Any = jit(roller.friction_torque)
_slip_velocity: Any = njit(slip.slip_velocity)  # called only while a web slips


@jit
def rhs(t0: float, x: np.ndarray, cmd: np.ndarray, drag: np.ndarray, slipping: np.ndarray,
        ns: np.ndarray, ds: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
        spans: np.ndarray, drives: np.ndarray, web: np.ndarray, dx: np.ndarray,
        work: np.ndarray) -> None:
    """Plant derivative dx/dt into ``dx`` with held torque commands ``cmd`` [N·m], held drag
    torques ``drag`` [N·m] (brakes, failing bearings: per node), held stick/slip states
    ``slipping`` (per node; ``drag[nodes + i]``: the load [N] on a dancer on node i, or the
    holding brake [N·m] set on driven node i after a web break (``sim.elements.break_hold``),
    ``drag[2 nodes + k]`` 1 while span k is broken) and the
    unwind's wound-in tension ``t0`` [N] at that instant (see
    ``wound_in``); nothing else depends on time. ``ns``, ``ds``, ``offsets`` are the line's
    structure, the other tables its parameters (``webline.sim.elements.layout``).

    Where the web slips over a roller (Ch. 5, E-5.3) the spans on both sides see the web
    speed r ω - s, s from ``physics.slip.slip_velocity`` (with a traction nip's force); the
    roller feels r (T_out - T_in), transmitted whether the web sticks or slips (winder.md N2).

    Physics as in ``webline.physics`` (span 6.8 with slack, rollers 6.9/6.11, rolls 6.1-6.6
    with J dω/dt = torque, motor lag 4.1k), written out with precomputed reciprocals because
    this function is the simulation's inner loop. ``work`` is scratch of 3 x nodes.
    """
    n_nodes = ns.shape[0]
    n_spans = n_nodes - 1
    last = n_nodes - 1
    off_w, off_r = offsets[L.O_OMEGA], offsets[L.O_RADIUS]
    off_tq, off_q = offsets[L.O_TORQUE], offsets[L.O_WEB]
    ea = web[L.W_EA]
    # work = [arm of each node | web speed of each node | tension of each span]
    sp, te = n_nodes, 2 * n_nodes
    for k in range(n_spans):
        work[te + k] = _tension(x[k])
        if offsets[L.O_BREAK] and drag[2 * n_nodes + k] != 0.0:  # broken: no tension
            work[te + k] = 0.0
    for i in range(n_nodes):
        work[i] = node_arm(i, x, ns, offsets, nodes)
        work[sp + i] = work[i] * x[off_w + i]
        if ns[i, L.NS_TRACTION] != 0 and slipping[i] != 0:
            surface = work[sp + i]
            t_c = web[L.W_RHOA] * surface * surface
            t_a, t_b = work[te + i - 1], work[te + i]
            if offsets[L.O_LAW]:  # the arc's tensions, not the stretches
                t_a, t_b = _law_tension(t_a, web[L.W_COLS:]), _law_tension(t_b, web[L.W_COLS:])
            work[sp + i] -= _slip_velocity(t_a, t_b, nodes[i, L.N_WRAP],
                                           nodes[i, L.N_MU], nodes[i, L.N_MUK], nodes[i, L.N_SLIPB],
                                           t_c, slipping[i], nodes[i, L.N_NIPK])  # nip: Coulomb

    s0 = _law_stretch(t0, web[L.W_COLS:]) if offsets[L.O_LAW] else t0  # wound-in strain x EA
    t_in = s0
    exact = offsets[L.O_EXACT] != 0  # exact mass conservation, else thesis 6.8 (E-6.6)
    for k in range(n_spans):
        v_in, v_out, t_out = work[sp + k], work[sp + k + 1], work[te + k]
        if offsets[L.O_BREAK] and drag[2 * n_nodes + k] != 0.0:
            dx[k] = 0.0
        elif exact:
            moving = ns[k, L.NS_DANCER] >= 0 or ns[k + 1, L.NS_DANCER] >= 0
            length, rate = spans[k, L.S_LENGTH], 0.0
            if moving:
                length, rate = span_motion(k, x, ns, nodes, spans)
            dx[k] = _exact_rate(length, ea, v_in, v_out, t_in, t_out, x[k])
            if moving:  # docs/winder.md (D1)
                dx[k] += _length_change(ea, x[k], rate, length, True)
        else:
            flow = ea * (v_out - v_in) + t_in * v_in - t_out * v_out
            if ns[k, L.NS_DANCER] >= 0 or ns[k + 1, L.NS_DANCER] >= 0:
                length, rate = span_motion(k, x, ns, nodes, spans)
                dx[k] = (flow + (ea - x[k]) * rate) / length  # docs/winder.md (D1)
            else:
                dx[k] = flow * spans[k, L.S_INVLENGTH]
        t_in = t_out
    t_last = work[te + n_spans - 1]  # the strain the rewind winds in, damper or not
    for k in range(n_spans if offsets[L.O_KV] else 0):  # the rollers feel T = F(s) + τ ds/dt
        felt = _law_tension(x[k], web[L.W_COLS:]) if offsets[L.O_LAW] else x[k]
        work[te + k] = _kv_tension(felt, dx[k], spans[k, L.S_TAU])  # (docs/winder.md)

    width = web[L.W_WIDTH]
    for i in range(n_nodes):
        omega = x[off_w + i]
        t_out = work[te + i] if i < n_spans else 0.0
        t_up = work[te + i - 1] if i > 0 else 0.0
        torque = work[i] * (t_out - t_up) - nodes[i, L.N_VISCOUS] * omega
        coulomb = nodes[i, L.N_COULOMB]
        if ns[i, L.NS_DRAG] >= 0:  # a brake (4.12) or drag acts like Coulomb friction
            coulomb += drag[i]
        dry = 0.0  # dry friction: Coulomb, brake, drag and a friction table (F1)
        if coulomb != 0.0:
            dry = _friction(omega, 0.0, coulomb)
            torque -= dry
        if offsets[L.O_FRICTION] and nodes[i, L.N_FRICN] > 0.0:
            table = table_torque(i, omega, nodes)
            dry += table
            torque -= table
        d = ns[i, L.NS_DRIVE]
        if d >= 0:
            n = drives[d, L.D_RATIO]
            if ds[d, L.DS_TSTATE] < 0:  # rigid: n τ less the reflected motor friction
                torque += n * (x[off_tq + d] - n * drives[d, L.D_BMOTOR] * omega)
            else:
                torque += compliant_torque(d, x, ds, offsets, drives, dx)
        inertia = 0.0
        if i == 0 or i == last:  # J(R) of the mean radius, also for an out-of-round roll
            radius = work[i]
            if ns[i, L.NS_ECCSTATE] >= 0:  # out of round: the mean radius (E1)
                radius = x[off_r] if i == 0 else x[off_r + 1]
            inertia = _roll_inertia(nodes[i, L.N_JCONST], radius, nodes[i, L.N_CORE], width,
                                    nodes[i, L.N_RHO])  # the web's or the totals' (J1)
        set_brake = drag[n_nodes + i] if offsets[L.O_BREAK] and d >= 0 else 0.0  # (W8)
        holding = set_brake + (drag[i] if ns[i, L.NS_DRAG] >= 0 else 0.0)  # and a drag (4.12)
        stuck = False
        if holding != 0.0 and abs(omega) < brake_band(
                holding, 1.0 / inertia if inertia > 0.0 else nodes[i, L.N_INVJ]):
            limit = set_brake + coulomb  # at rest a brake is static friction (W8, F2)
            if offsets[L.O_FRICTION]:
                limit += nodes[i, L.N_BREAKAWAY]
            stuck, torque = stick(torque + dry, limit)
        elif set_brake != 0.0:  # turning: Coulomb friction of the set brake
            torque -= set_brake if omega > 0.0 else -set_brake
        elif (offsets[L.O_FRICTION] and nodes[i, L.N_BREAKAWAY] > 0.0
                and abs(omega) < STICK_SPEED):  # at rest: static friction (F2)
            stuck, torque = breakaway(i, omega, torque + dry, nodes)
        if stuck:  # held at rest: ω decays to 0 in a control period
            dx[off_w + i] = -omega / nodes[i, L.N_STICKTAU]
            ecc_state = ns[i, L.NS_ECCSTATE]
            if ecc_state >= 0:
                dx[ecc_state] = omega
            continue
        if i == 0 or i == last:
            dx[off_w + i] = torque / inertia
        else:
            dx[off_w + i] = torque * nodes[i, L.N_INVJ]
        ecc_state = ns[i, L.NS_ECCSTATE]
        if ecc_state >= 0:
            dx[ecc_state] = omega

    v_unwind, v_rewind = work[sp], work[sp + last]  # surface speeds (E1: eccentric too)
    dx[off_r] = _radius_rate(v_unwind, x[off_r], web[L.W_THICK], -1.0)
    dx[off_r + 1] = _radius_rate(v_rewind, x[off_r + 1], web[L.W_THICK], 1.0)

    for d in range(ds.shape[0]):
        dx[off_tq + d] = (cmd[d] - x[off_tq + d]) * drives[d, L.D_INVLAG]
    for i in range(1, last):
        if ns[i, L.NS_DANCER] >= 0:
            if ns[i, L.NS_DGEOM]:  # strands or angles: g_in T_in + g_out T_out (D0-D2)
                pull = nodes[i, L.N_DGIN] * work[te + i - 1] + nodes[i, L.N_DGOUT] * work[te + i]
            else:
                pull = work[te + i - 1] + work[te + i]
            dancer_rate(i, x, ns, nodes, pull, drag[n_nodes + i], dx)

    if exact:  # unstrained web in and out: v/(1 + ε)
        dx[off_q] = _unstrained_flow(v_unwind, ea, s0, True)
        dx[off_q + 1] = _unstrained_flow(v_rewind, ea, t_last, True)
    else:  # v (1 - ε), written as before so that first-order runs keep their last bits
        inv_ea = 1.0 / ea
        dx[off_q] = v_unwind * (1.0 - s0 * inv_ea)
        dx[off_q + 1] = v_rewind * (1.0 - t_last * inv_ea)


@jit
def felt_tensions(t0: float, x: np.ndarray, cmd: np.ndarray, drag: np.ndarray,
                  slipping: np.ndarray, ns: np.ndarray, ds: np.ndarray, offsets: np.ndarray,
                  nodes: np.ndarray, spans: np.ndarray, drives: np.ndarray, web: np.ndarray,
                  dx: np.ndarray, work: np.ndarray, saved: np.ndarray) -> None:
    """Put the tension each span's rollers feel (Kelvin-Voigt: s + τ ds/dt, ``rhs``) in
    place of its stretch in ``x`` for a controller tick, the stretches kept in ``saved``
    (scratch ``dx`` and ``work`` as ``rhs`` takes them)."""
    rhs(t0, x, cmd, drag, slipping, ns, ds, offsets, nodes, spans, drives, web, dx, work)
    for k in range(ns.shape[0] - 1):
        saved[k], x[k] = x[k], work[2 * ns.shape[0] + k]


def initial_slip(plan: Plan, x: np.ndarray) -> np.ndarray:
    """Stick/slip state of every node (0 stuck, 1 slipping) for the state ``x`` of ``plan``."""
    slip = np.zeros(plan.line.n_nodes, dtype=np.int64)
    update_slip(x, slip, plan.node_structure, plan.offsets, plan.nodes, plan.web)
    return slip


def run(plan: Plan, x0: np.ndarray, istate0: np.ndarray, slip0: np.ndarray, tick0: int,
        n_ticks: int, substeps: int, record_every: int,
        include_end: bool, rec: np.ndarray | None = None,
        ) -> tuple[np.ndarray, int, int, float, int, np.ndarray, np.ndarray, np.ndarray]:
    """Simulate ``n_ticks`` controller periods of ``plan.dt`` [s] from tick ``tick0``.

    A tick is recorded when its global index is a multiple of ``record_every``; with
    ``include_end`` the state after the last period is recorded too (a chunked run leaves it
    to the next chunk). Returns (records, number of records, status, time of failure, where it
    failed (``envelope``), final state, final controller memory, final stick/slip states).
    Each record row is [t, x..., cmd..., vref..., trim..., u_eq..., friction estimate...,
    controller radius... (one value per drive in each group), slip state per node...]. The
    run stops early, keeping what it computed, if the state stops being finite, the unwind
    roll runs out of web, a tension exceeds the web's strength or the state leaves the
    physical envelope (``envelope``).

    This wrapper allocates every array; the compiled loop allocates none (``loop_njit``).
    ``rec``, if given, receives the records instead (a C-contiguous block of enough rows, e.g.
    the rest of a whole run's buffer, so that a chunked run needs no concatenation).
    """
    n_x, n_d, n_n = x0.shape[0], plan.drives.shape[0], plan.nodes.shape[0]
    x, istate, slipping = x0.copy(), istate0.copy(), slip0.copy()
    if rec is None:
        rec = np.empty((n_ticks // record_every + 2, record_width(n_x, n_d, n_n)))
    out = np.zeros((4, n_d))
    stages = np.empty((5, n_x))  # RK4 slopes k1..k4 and the stage state
    refs = np.empty((4, max(plan.prof_off.shape[0] - 1, n_n)))  # profiles|spans|v_ref|a_ref
    work = np.zeros((2, 3 * n_n))  # rhs scratch | held drag, dancer load, span broken flag
    n_rec, status, t_fail, where = compiled_loop(plan)(
        x, istate, slipping, rec, out, stages, refs, work, tick0, n_ticks, plan.dt, substeps,
        record_every, include_end, *plan.params())
    return rec, n_rec, status, t_fail, where, x, istate, slipping


def compiled_loop(plan: Plan) -> Any:
    """The simulation loop compiled for ``plan``'s structure (module docstring)."""
    return _compiled(plan.structure_key())


@functools.cache
def _compiled(key: StructureKey) -> Any:
    ns, ds, offsets = structure_arrays(key)  # frozen in: one cached loop per structure

    @loop_njit
    def loop(x: np.ndarray, istate: np.ndarray, slipping: np.ndarray, rec: np.ndarray,
             out: np.ndarray, stages: np.ndarray, refs: np.ndarray, work: np.ndarray,
             tick0: int, n_ticks: int, dt: float, substeps: int, record_every: int,
             include_end: bool, nodes: np.ndarray, spans: np.ndarray, drives: np.ndarray,
             web: np.ndarray, wound_ripple: np.ndarray, speed_ripple: np.ndarray,
             prof_t: np.ndarray, prof_v: np.ndarray,
             prof_off: np.ndarray) -> tuple[int, int, float, int]:
        return advance(x, istate, slipping, rec, out, stages, refs, work, tick0, n_ticks, dt,
                       substeps, record_every, include_end, ns, ds, offsets, nodes, spans,
                       drives, web, wound_ripple, speed_ripple, prof_t, prof_v, prof_off,
                       None, None)

    return loop


@jit
def advance(x: np.ndarray, istate: np.ndarray, slipping: np.ndarray, rec: np.ndarray,
            out: np.ndarray, stages: np.ndarray, refs: np.ndarray, work: np.ndarray,
            tick0: int, n_ticks: int, dt: float, substeps: int, record_every: int,
            include_end: bool, ns: np.ndarray, ds: np.ndarray, offsets: np.ndarray,
            nodes: np.ndarray, spans: np.ndarray, drives: np.ndarray, web: np.ndarray,
            wound_ripple: np.ndarray, speed_ripple: np.ndarray, prof_t: np.ndarray,
            prof_v: np.ndarray, prof_off: np.ndarray, law: Any,
            law_buf: Any) -> tuple[int, int, float, int]:
    """The loop of ``run``: advances ``x``, ``istate`` and ``slipping`` in place, writes
    ``rec`` and returns (records written, status, time of failure, where: ``envelope``); the
    other arrays are scratch of the shapes ``run`` gives them. ``law``, ``law_buf``: None, or
    the compiled user laws (``sim.core.law_kernel``), whose non-finite command stops the run
    before its tick is recorded (``STATUS_USER_NONFINITE``, ``where``: the drive)."""
    n_x = offsets[L.O_WEB] + 2
    n_d = ds.shape[0]
    n_n = ns.shape[0]
    cmd = out[0]
    tmp = stages[4]
    prof, span_ref = refs[0, :prof_off.shape[0] - 1], refs[1, :n_n - 1]
    v_ref, a_ref = refs[2, :n_n], refs[3, :n_n]
    scratch, drag = work[0], work[1]
    h = dt / substeps
    n_rec = 0
    status = L.STATUS_OK
    t_fail = math.nan
    where = -1
    off_r = offsets[L.O_RADIUS]
    core = nodes[0, L.N_CORE]
    for j in range(n_ticks + 1):
        tick = tick0 + j
        t = tick * dt
        if j == n_ticks and not include_end:
            break
        for k in range(n_n - 1 if offsets[L.O_BREAK] else 0):  # a broken span: no tension
            if t >= spans[k, L.S_BREAK] and drag[2 * n_n + k] == 0.0:
                drag[2 * n_n + k], x[k] = 1.0, 0.0
        if offsets[L.O_SPLICE]:  # a new roll takes over the web (docs/winder.md S1)
            apply_splices(tick, dt, x, istate, ns, offsets, nodes, spans, drives, web, prof_t,
                          prof_v, prof_off)
        if offsets[L.O_KV]:  # the controllers measure what the rollers feel
            felt_tensions(wound_in(t, web, wound_ripple), x, cmd, drag, slipping, ns, ds,
                          offsets, nodes, spans, drives, web, stages[0], scratch, tmp)
        control_tick(tick, dt, x, istate, ns, ds, offsets, nodes, drives, web, prof_t, prof_v,
                     prof_off, speed_ripple, out, prof, span_ref, v_ref, a_ref, law, law_buf)
        for k in range(n_n - 1 if offsets[L.O_KV] else 0):
            x[k] = tmp[k]  # the stretch states back
        if law is not None:
            where = user_nonfinite(ds, out)
            if where >= 0:
                status, t_fail = STATUS_USER_NONFINITE, t
                break
        update_slip(x, slipping, ns, offsets, nodes, web)
        if tick % record_every == 0 or j == n_ticks:
            rec[n_rec, 0] = t
            for m in range(n_x):
                rec[n_rec, 1 + m] = x[m]
            col = 1 + n_x
            for q in range(4):
                for d in range(n_d):
                    rec[n_rec, col] = out[q, d]
                    col += 1
            for q in range(2 * n_d):  # friction estimate, controller radius
                rec[n_rec, col + q] = istate[q % n_d, L.I_FRICTION if q < n_d else L.I_RADIUS]
            col += 2 * n_d
            for i in range(n_n):
                rec[n_rec, col] = slipping[i]
                col += 1
            for d in range(n_d):  # the MRAC's adapted gains k̂ (tension, speed) and bias ĉ
                rec[n_rec, col] = istate[d, L.I_KT]
                rec[n_rec, col + 1] = istate[d, L.I_KV]
                rec[n_rec, col + 2] = istate[d, L.I_BIAS]
                col += 3
            n_rec += 1
        if j == n_ticks:
            break
        for i in range(n_n):  # drag torques are held over the tick, like the commands
            p = ns[i, L.NS_DRAG]
            if p >= 0:
                drag[i] = profile_at(p, t, prof_t, prof_v, prof_off)
            if ns[i, L.NS_DANCER] >= 0:
                drag[n_n + i] = profile_at(int(nodes[i, L.N_DLOAD]), t, prof_t, prof_v,
                                           prof_off) * load_factor(i, istate, ds, drives,
                                                                   prof_t, prof_v, prof_off)
            if offsets[L.O_BREAK] and ns[i, L.NS_DRIVE] >= 0:  # a driven node is no dancer
                drag[n_n + i] = brake_drag(i, t, istate, ns, drives, web)
        t0_start = wound_in(t, web, wound_ripple)
        for s in range(substeps):
            ts = t + s * h
            t0_mid = wound_in(ts + 0.5 * h, web, wound_ripple)
            t0_end = wound_in(ts + h, web, wound_ripple)
            for stage in range(4):  # one call site: the rhs is compiled once, not four times
                state, t0 = (x, t0_start) if stage == 0 else (
                    tmp, t0_end if stage == 3 else t0_mid)
                rhs(t0, state, cmd, drag, slipping, ns, ds, offsets, nodes, spans, drives, web,
                    stages[stage], scratch)
                if stage < 3:
                    c = h if stage == 2 else 0.5 * h
                    for m in range(n_x):
                        tmp[m] = x[m] + c * stages[stage, m]
            for m in range(n_x):
                x[m] += h / 6.0 * (stages[0, m] + 2.0 * stages[1, m] + 2.0 * stages[2, m]
                                   + stages[3, m])
            t0_start = t0_end
        finite = True
        for m in range(n_x):
            if not math.isfinite(x[m]):
                finite = False
        if not finite:
            status = L.STATUS_NONFINITE
            t_fail = t + dt
            break
        if x[off_r] <= core:
            status = L.STATUS_UNWIND_EMPTY
            t_fail = t + dt
            break
        status, where = envelope(x, ns, ds, offsets, nodes, drives, web)
        if status != L.STATUS_OK:
            t_fail = t + dt
            break
    return n_rec, status, t_fail, where
