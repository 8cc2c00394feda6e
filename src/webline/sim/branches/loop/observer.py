"""The section observer of a decentralized drive on a branched line (docs/branching.md,
"Section observer"), the chain's ``sim.drives.observer`` on a tree: for a drive whose zone is
one span k (from node a to node b, one of them its own), the observer integrates the span
equation (B1) with the *measured* speeds of both ends and its own node's torque balance (B4)
with the motor torque and every other span on the node at its reference tension (a
junction's too), and corrects both with the speed residual ω_meas - ω̂:

    L dT̂/dt = EA (v_b - v_a) + T_in v_a - T̂ v_b + L l_T (ω_meas - ω̂)
    (with exact transport, ``web.transport``, errata E-6.6: the plant's exact (B1),
    (EA + T̂) v_b - (EA + T̂)² v_a/(EA + T_in), in place of the first three terms)
    J dω̂/dt = ± a_k T̂ + Σ_others ± a T_ref + n τ - b ω̂ - c tanh(ω̂/ω_s) + J l_ω (ω_meas - ω̂)

T_in at its reference (the previous span's, a laminate's layers' sum, a lane's share of its
base web, or the wound-in tension), one Euler step per controller tick; l_T, l_ω from the
section model (``sim.branches.drives.observer``) place both error poles at -``observer_bandwidth``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import roller, span
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import arm, node_inertia
from webline.sim.elements.signals import jit

_friction: Any = jit(roller.friction_torque)
_exact_rate: Any = jit(span.exact_stretch_rate)


@jit
def reference_tension(k: int, refs: np.ndarray) -> float:
    """Span ``k``'s reference tension [N] this tick (the design point's plus each loadcell's
    reference change times its sensitivity, ``loop.decentral.reference_changes``)."""
    t_ref = refs[k, 0]
    for c in range(refs.shape[1] - 1):
        t_ref += refs[k, 1 + c] * refs[-1, 1 + c]
    return t_ref


@jit
def observe(d: int, i: int, dt: float, omega_meas: float, x: np.ndarray,
            istate: np.ndarray, offsets: np.ndarray, nodes: np.ndarray, rolls: np.ndarray,
            si: np.ndarray, sf: np.ndarray, layers: np.ndarray, di: np.ndarray,
            fb: np.ndarray, refs: np.ndarray) -> float:
    """One Euler step [s] of drive ``d``'s observer on node ``i`` (module docstring) from its
    measured ``omega_meas`` [rad/s]; returns T̂ [N], the tension its law feeds back."""
    k = di[d, B.DI_OBS] - 1
    a, b = si[k, B.S_A], si[k, B.S_B]
    off_w = offsets[B.O_OMEGA]
    omega_a = omega_meas if a == i else x[off_w + a]  # the other end's tachometer
    omega_b = omega_meas if b == i else x[off_w + b]
    v_a = arm(si[k, B.S_ARMA], a, x, offsets, nodes) * omega_a
    v_b = arm(si[k, B.S_ARMB], b, x, offsets, nodes) * omega_b
    src, frm = si[k, B.S_SRC], si[k, B.S_FROM]
    if src == B.SRC_WOUND:
        t_in = fb[d, B.FB_OBS_TIN]
    elif src == B.SRC_LAYERS:
        t_in = 0.0
        for j in range(si[k, B.S_COUNT]):
            t_in += reference_tension(layers[frm + j], refs)
    elif src == B.SRC_PREVIOUS:
        t_in = reference_tension(frm, refs)
    else:  # a lane: its share of the base web at the knife
        t_in = sf[k, B.SF_SHARE] * reference_tension(frm, refs)
    t_hat, w_hat = istate[d, B.I_THAT], istate[d, B.I_WHAT]
    ea, length = fb[d, B.FB_OBS_EA], fb[d, B.FB_OBS_LENGTH]
    if offsets[B.O_EXACT]:  # the line's transport, as the plant's (B1) (errata E-6.6)
        dt_hat = _exact_rate(length, ea, v_a, v_b, t_in, t_hat, t_hat)
    else:
        dt_hat = (ea * (v_b - v_a) + t_in * v_a - t_hat * v_b) / length
    web_torque = 0.0  # every span on the node: T̂ for the observed one, the others' references
    for s in range(si.shape[0]):
        if si[s, B.S_A] != i and si[s, B.S_B] != i:
            continue
        tension = t_hat if s == k else reference_tension(s, refs)
        if si[s, B.S_A] == i:
            web_torque += arm(si[s, B.S_ARMA], i, x, offsets, nodes) * tension
        else:
            web_torque -= arm(si[s, B.S_ARMB], i, x, offsets, nodes) * tension
    torque = x[offsets[B.O_TORQUE] + d] * nodes[i, B.N_RATIO]
    friction = _friction(w_hat, fb[d, B.FB_BMODEL], nodes[i, B.N_COULOMB]) + fb[
        d, B.FB_BMOTOR] * w_hat
    dw_hat = (web_torque + torque - friction) / node_inertia(i, x, offsets, nodes, rolls)
    residual = omega_meas - w_hat
    istate[d, B.I_THAT] = t_hat + dt * (dt_hat + fb[d, B.FB_OBS_LT] * residual)
    istate[d, B.I_WHAT] = w_hat + dt * (dw_hat + fb[d, B.FB_OBS_LW] * residual)
    return istate[d, B.I_THAT]
