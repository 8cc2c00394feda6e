"""Flying splices in the compiled plan and loop (docs/winder.md, S1-S3): at its tick the web
passes from the old roll to a new one, which takes the roll's place in the line.

The roll's radius and speed are states of the line; the splice sets them to the new roll's
(radius R_new, surface speed (1 + mismatch) times the web's at the old roll), puts the
splice's slack into the span next to the roll (its stretch drops by EA·slack/L, the web-length
integral of the roll takes the slack, so the web balance holds exactly), presets the roll
drive's diameter to the new one and its speed integrator to the new roll's tension torque.
"""

from __future__ import annotations

import math

import numpy as np

from webline.line import Line
from webline.sim.elements import layout as L
from webline.sim.elements.dancer_loop import span_motion
from webline.sim.elements.signals import jit
from webline.spec.splice import FlyingSplice


def splices(line: Line) -> list[FlyingSplice]:
    """The flying splices of ``line``'s run, in the order of its disturbances."""
    return [d for d in line.spec.disturbances if isinstance(d, FlyingSplice)]


def splice_tick(at: float, dt: float) -> int:
    """The first controller tick at or after ``at`` [s] (period ``dt`` [s]): the splice's
    instant, as the kernel applies it (1e-9 of a tick absorbs rounding of ``at/dt``)."""
    return math.ceil(at / dt - 1e-9)


def splice_profiles(line: Line) -> list[tuple[np.ndarray, np.ndarray]]:
    """Three profiles per spliced roll (unwind first), over the times of its splices: new
    radius [m], surface-speed ratio 1 + mismatch [-], slack [m] (``L.N_SPLICE``)."""
    out = []
    for roll in (line.node_name(0), line.node_name(line.n_nodes - 1)):
        items = sorted((s for s in splices(line) if s.roll == roll), key=lambda s: s.at)
        if not items:
            continue
        times = np.array([s.at for s in items])
        out += [(times, np.array([s.new_diameter / 2.0 for s in items])),
                (times, np.array([1.0 + s.speed_mismatch for s in items])),
                (times, np.array([s.slack for s in items]))]
    return out


def splice_columns(nodes: np.ndarray, line: Line, first_profile: int) -> bool:
    """Point each spliced roll's node at its profiles (``splice_profiles``, the first at
    index ``first_profile``; none: -1); True if a roll is spliced."""
    nodes[:, L.N_SPLICE] = -1.0
    p = first_profile
    for i, roll in ((0, line.node_name(0)), (line.n_nodes - 1, line.node_name(line.n_nodes - 1))):
        if any(s.roll == roll for s in splices(line)):
            nodes[i, L.N_SPLICE] = p
            p += 3
    return bool(splices(line))


@jit
def apply_splices(tick: int, dt: float, x: np.ndarray, istate: np.ndarray, ns: np.ndarray,
                  offsets: np.ndarray, nodes: np.ndarray, spans: np.ndarray,
                  drives: np.ndarray, web: np.ndarray, prof_t: np.ndarray,
                  prof_v: np.ndarray, prof_off: np.ndarray) -> None:
    """Splice each roll that has a splice at this tick (S1), in place on the plant state
    ``x`` and the controller memory ``istate``; called once per tick (period ``dt`` [s])
    before the controllers."""
    n_n = ns.shape[0]
    for end in range(2):
        i = 0 if end == 0 else n_n - 1
        p = int(nodes[i, L.N_SPLICE])
        if p < 0:
            continue
        count = prof_off[p + 1] - prof_off[p]
        for b in range(prof_off[p], prof_off[p + 1]):
            if tick == math.ceil(prof_t[b] / dt - 1e-9):  # as ``splice_tick``
                splice(end, i, prof_v[b], prof_v[b + count], prof_v[b + 2 * count], x, istate,
                       ns, offsets, nodes, spans, drives, web)


@jit
def splice(end: int, i: int, r_new: float, gain: float, slack: float, x: np.ndarray,
           istate: np.ndarray, ns: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
           spans: np.ndarray, drives: np.ndarray, web: np.ndarray) -> None:
    """One splice (S1) of the roll on node ``i`` (``end`` 0: unwind, 1: rewind) onto a new
    roll of radius ``r_new`` [m] running at ``gain`` times the web's speed [-], putting
    ``slack`` [m] of web into the span next to it."""
    n_n = ns.shape[0]
    radius_state = offsets[L.O_RADIUS] + end
    omega_state = offsets[L.O_OMEGA] + i
    r_old = x[radius_state]
    omega_old = x[omega_state]
    # the new roll runs at the web's speed at the old roll, times (1 + mismatch)
    x[omega_state] = gain * r_old * omega_old / r_new
    x[radius_state] = r_new
    k = 0 if end == 0 else n_n - 2  # the span next to the roll
    carried = x[k] if x[k] > 0.0 else 0.0  # the tension the old roll carried
    length = span_motion(k, x, ns, nodes, spans)[0]
    ea = web[L.W_EA]
    if offsets[L.O_EXACT]:  # u = L/(1 + s/EA) grows by the slack (E-6.6)
        x[k] = length * ea / (length * ea / (ea + x[k]) + slack) - ea
    else:
        x[k] -= ea * slack / length  # u = L (1 - s/EA) grows by the slack
    x[offsets[L.O_WEB] + end] += slack if end == 0 else -slack
    d = ns[i, L.NS_DRIVE]
    n = drives[d, L.D_RATIO]
    direction = -1.0 if end == 0 else 1.0  # the motor brakes an unwind, pulls a rewind
    omega = x[omega_state]
    viscous = nodes[i, L.N_VISCOUS] / n + n * drives[d, L.D_BMOTOR]  # [N·m·s] at the motor
    istate[d, L.I_SPEED] += (direction * carried * (r_new - r_old) / n
                             + viscous * (omega - omega_old))  # tension and friction
    # the new roll's motor carried only its friction until now (rigid drives only)
    coulomb = nodes[i, L.N_COULOMB] * (1.0 if omega > 0.0 else -1.0 if omega < 0.0 else 0.0)
    x[offsets[L.O_TORQUE] + d] = viscous * omega + coulomb / n
    istate[d, L.I_RADIUS] = r_new  # diameter preset: the drive knows the new roll
    istate[d, L.I_REXTREME] = 0.0  # the break monitor's extreme starts again
    istate[d, L.I_WHAT] = omega  # a section observer's speed estimate
