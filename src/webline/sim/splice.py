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
from webline.sim import layout as L
from webline.sim.dancer_loop import span_motion
from webline.sim.signals import jit
from webline.spec.splice import FlyingSplice


def splices(line: Line) -> list[FlyingSplice]:
    """The flying splices of ``line``'s run, in the order of its disturbances."""
    return [d for d in line.spec.disturbances if isinstance(d, FlyingSplice)]


def splice_tick(at: float, dt: float) -> int:
    """The first controller tick at or after ``at`` [s] (period ``dt`` [s]): the splice's
    instant, as the kernel applies it (1e-9 of a tick absorbs rounding of ``at/dt``)."""
    return math.ceil(at / dt - 1e-9)


def splice_columns(nodes: np.ndarray, line: Line, dt: float) -> bool:
    """Fill the splice columns of the roll nodes (none: tick -1); True if a roll is spliced."""
    nodes[:, L.N_SPLICE_TICK] = -1.0
    names = [r.name for r in line.spec.rollers]
    for item in splices(line):
        row = nodes[names.index(item.roll)]
        row[L.N_SPLICE_TICK] = splice_tick(item.at, dt)
        row[L.N_SPLICE_R] = item.new_diameter / 2.0
        row[L.N_SPLICE_GAIN] = 1.0 + item.speed_mismatch
        row[L.N_SPLICE_SLACK] = item.slack
    return bool(splices(line))


@jit
def apply_splices(tick: int, x: np.ndarray, istate: np.ndarray, ns: np.ndarray,
                  offsets: np.ndarray, nodes: np.ndarray, spans: np.ndarray,
                  drives: np.ndarray, web: np.ndarray) -> None:
    """At its tick, splice each roll that has a splice (S1), in place on the plant state ``x``
    and the controller memory ``istate``; called once per tick before the controllers."""
    n_n = ns.shape[0]
    for end in range(2):
        i = 0 if end == 0 else n_n - 1
        if tick != int(nodes[i, L.N_SPLICE_TICK]):
            continue
        radius_state = offsets[L.O_RADIUS] + end
        omega_state = offsets[L.O_OMEGA] + i
        r_old, r_new = x[radius_state], nodes[i, L.N_SPLICE_R]
        omega_old = x[omega_state]
        # the new roll runs at the web's speed at the old roll, times (1 + mismatch)
        x[omega_state] = nodes[i, L.N_SPLICE_GAIN] * r_old * omega_old / r_new
        x[radius_state] = r_new
        k = 0 if end == 0 else n_n - 2  # the span next to the roll
        carried = x[k] if x[k] > 0.0 else 0.0  # the tension the old roll carried
        length = span_motion(k, x, ns, nodes, spans)[0]
        slack = nodes[i, L.N_SPLICE_SLACK]
        x[k] -= web[L.W_EA] * slack / length  # u = L (1 - s/EA) grows by the slack
        x[offsets[L.O_WEB] + end] += slack if end == 0 else -slack
        d = ns[i, L.NS_DRIVE]
        n = drives[d, L.D_RATIO]
        direction = -1.0 if end == 0 else 1.0  # the motor brakes an unwind, pulls a rewind
        omega = x[omega_state]
        viscous = nodes[i, L.N_VISCOUS] / n + n * drives[d, L.D_BMOTOR]  # [N·m·s] at the motor
        istate[d, L.I_SPEED] += (direction * carried * (r_new - r_old) / n
                                 + viscous * (omega - omega_old))  # tension and friction
        # the new roll's motor carried only its friction until now (S1): (rigid drives only)
        coulomb = nodes[i, L.N_COULOMB] * (1.0 if omega > 0.0 else -1.0 if omega < 0.0 else 0.0)
        x[offsets[L.O_TORQUE] + d] = viscous * omega + coulomb / n
        istate[d, L.I_RADIUS] = r_new  # diameter preset: the drive knows the new roll
        istate[d, L.I_REXTREME] = 0.0  # the break monitor's extreme starts again
        istate[d, L.I_WHAT] = x[omega_state]  # a section observer's speed estimate
