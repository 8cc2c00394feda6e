"""Why a run stopped early: the kernel's status turned into a named failure with its time and
place (``Failure``), never one failure reported as another."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from webline.physics.web_law import law_tension
from webline.sim import layout as L
from webline.sim.plan import RUNAWAY_SPEED_FACTOR, RUNAWAY_SPEED_FLOOR, Plan


@dataclass(frozen=True)
class Failure:
    """A run that stopped early.

    ``kind``: ``diverged`` (the state left the line's physical envelope: a runaway),
    ``nonfinite``, ``unwind_empty``, ``strength_exceeded`` or ``interrupted``; ``where``: the
    span, roller, drive or state concerned; ``time`` [s]; ``message``: one sentence from the
    numbers; ``details``: those numbers (SI).
    """

    kind: str
    where: str
    time: float
    message: str
    details: dict[str, object] = field(default_factory=dict, compare=False, hash=False)


def kernel_failure(plan: Plan, status: int, t_fail: float, where: int,
                   x: np.ndarray) -> Failure | None:
    """The failure the kernel reported (``layout.STATUS_*``, the index ``where`` of the span,
    node or drive, the state ``x`` at which it stopped), or None for a run that finished."""
    line = plan.line
    at = f"at t = {t_fail:.4g} s"
    if status == L.STATUS_OK:
        return None
    if status == L.STATUS_NONFINITE:
        bad = np.flatnonzero(~np.isfinite(x))
        name = plan.state_names[int(bad[0])] if bad.size else "state"
        return Failure("nonfinite", name, t_fail,
                       f"the state stopped being finite ({name} first) {at}",
                       {"state": name})
    if status == L.STATUS_UNWIND_EMPTY:
        name = line.node_name(0)
        return Failure("unwind_empty", name, t_fail,
                       f"the unwind roll ran out of web (reached its core) {at}",
                       {"radius_m": float(x[plan.offsets[L.O_RADIUS]])})
    ea = plan.web[L.W_EA]
    if status == L.STATUS_STRENGTH:
        name, tension = line.span_name(where), float(x[where])
        strength = float(plan.web[L.W_STRENGTH])
        if line.nonlinear:  # the kernel compared stretches: say it in tensions
            tension = law_tension(tension, line.law)
            strength = float(line.spec.web.strength or math.inf)
        return Failure("strength_exceeded", name, t_fail,
                       f"the web broke in {name}: tension {tension:.4g} N exceeded its strength "
                       f"{strength:.4g} N {at}",
                       {"tension_N": tension, "strength_N": strength})
    if status == L.STATUS_RUNAWAY_STRETCH:
        name, stretch = line.span_name(where), float(x[where])
        limit = float(plan.web[L.W_STRETCH_MAX] / ea)
        beyond = (f"beyond {limit:g} x EA, a strain no web survives" if stretch > 0 else
                  f"slack by more than {limit:.0%} of its length: the web piles up")
        return Failure("diverged", name, t_fail,
                       f"the run diverged: {name} stretch reached {stretch / ea:.3g} x EA "
                       f"({beyond}) {at}",
                       {"stretch_N": stretch, "ea_N": float(ea), "signal": "stretch"})
    speed_max = float(plan.web[L.W_SPEED_MAX])
    if status == L.STATUS_RUNAWAY_SPEED:
        name = line.node_name(where)
        omega = float(x[plan.offsets[L.O_OMEGA] + where])
        speed = omega * _arm(plan, where, x)
        signal = "surface speed"
    elif status == L.STATUS_RUNAWAY_MOTOR:
        node = line.drives[where]
        name = line.node_name(node)
        ratio = float(plan.drives[where, L.D_RATIO])
        speed = float(x[int(plan.drives[where, L.D_TSTATE])]) / ratio * _arm(plan, node, x)
        signal = "motor speed (as roller surface speed)"
    else:
        return Failure("diverged", "line", t_fail, f"the run stopped (status {status}) {at}")
    return Failure("diverged", name, t_fail,
                   f"the run diverged: {name} {signal} reached {speed:.3g} m/s (beyond "
                   f"{speed_max:.3g} m/s = {RUNAWAY_SPEED_FACTOR:g} x the fastest speed reference "
                   f"+ {RUNAWAY_SPEED_FLOOR:g} m/s) {at}",
                   {"speed_m_s": speed, "speed_max_m_s": speed_max, "signal": signal})


def _arm(plan: Plan, i: int, x: np.ndarray) -> float:
    """Radius [m] of node ``i`` in state ``x`` (roll radius state, else nominal + eccentric)."""
    off_r = int(plan.offsets[L.O_RADIUS])
    radius = float(plan.nodes[i, L.N_RADIUS])
    if i == 0:
        radius = float(x[off_r])
    if i == plan.nodes.shape[0] - 1:
        radius = float(x[off_r + 1])
    ecc_state = int(plan.nodes[i, L.N_ECCSTATE])
    if ecc_state >= 0:
        radius += float(plan.nodes[i, L.N_ECC]) * math.cos(float(x[ecc_state]))
    return radius
