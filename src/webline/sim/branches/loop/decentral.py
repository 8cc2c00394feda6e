"""A decentralized drive's tick on a branched line (docs/branching.md, "State feedback"), as
the chain's ``sim.drives.controllers.decentralized_command`` and ``adapt``: tables in
``layout`` (FB_*, the reference rows of ``sim.branches.drives.decentral.prepare``).

    u = u_eq + f - g (K_T x_T + K_V x_V)      (6.39-6.42; adaptive 6.62-6.68 with E-6.8)

x_T the zone's loadcell tension (or lanes' sum) minus its reference, x_V the measured surface
speed minus the reference; u_eq the torque that holds the node on its reference motion,
from the reference tensions of every span on the node (a junction's too); f cancels a roll's
velocity-squared term; g = J / (n r) over its design value keeps the speed row's closed-loop
entries as designed while a roll's inertia and radius change. Across a compliant
transmission J counts the reflected motor n² J_m (the design lumps it, as the chain's) and
the measured speed is the side ``feedback`` names (``loop.transmission.measured_omega``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics import motor, roll, roller
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.break_limits import stop_acceleration
from webline.sim.branches.loop.plant import arm, node_inertia
from webline.sim.branches.loop.transmission import motor_beyond
from webline.sim.elements.signals import jit, profile_at, profile_slope_at

_friction: Any = jit(roller.friction_torque)
_radius_rate: Any = jit(roll.radius_rate)
_saturate: Any = jit(motor.saturate)


@jit
def reference_changes(t: float, istate: np.ndarray, di: np.ndarray, cells: np.ndarray,
                      refs: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                      prof_off: np.ndarray) -> None:
    """Into the last row of ``refs`` (from column 1): each loadcell's reference at ``t`` [s]
    times its drive's taper factor (its last tick's, ``I_FACTOR``) minus its value at the
    design point [N] (the row before the last)."""
    for d in range(di.shape[0]):
        for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
            refs[-1, 1 + c] = istate[d, B.I_FACTOR] * profile_at(
                cells[c, 1], t, prof_t, prof_v, prof_off) - refs[-2, 1 + c]


@jit
def decentral_command(d: int, family: int, i: int, t: float, dt: float, radius: float,
                      v_meas: float, x_t: float, stopping: float, adapting: bool,
                      x: np.ndarray, istate: np.ndarray,
                      offsets: np.ndarray, nodes: np.ndarray, rolls: np.ndarray,
                      si: np.ndarray, df: np.ndarray, fb: np.ndarray,
                      refs: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                      prof_off: np.ndarray) -> float:
    """Torque command [N·m] of decentralized drive ``d`` (``layout.FAMILY_*`` ``family``) on
    node ``i`` (module docstring):
    ``radius`` [m] the one it converts speeds with, ``v_meas`` [m/s] its measured surface
    speed, ``x_t`` [N] its zone's tension error (measured minus reference); each loadcell's
    reference change this tick in ``refs``' last row (``reference_changes``). ``stopping``:
    the line-speed factor of the ramp to a stop after a web break (1 without one): the
    reference speeds follow the ramp s(t) v(t), their acceleration s a - v / T (W8);
    ``adapting``: False from a break's detection on (the estimates keep their values)."""
    n_s, n_c = si.shape[0], refs.shape[1] - 1
    v_line = profile_at(0, t, prof_t, prof_v, prof_off)
    a_line = profile_slope_at(0, t, prof_t, prof_v, prof_off)
    if stopping < 1.0:  # (a break was detected: W5, W8)
        a_line = stop_acceleration(a_line, v_line, stopping, df)
    scale = stopping * v_line / refs[-2, 0]
    accel = a_line / refs[-2, 0]
    v_ref = refs[n_s + d, 0]
    for c in range(n_c):
        v_ref += refs[n_s + d, 1 + c] * refs[-1, 1 + c]
    a_ref, v_ref = accel * v_ref, scale * v_ref
    # the web's torque on the node at the reference tensions: every span on it
    web_torque = 0.0
    for k in range(n_s):
        if si[k, B.S_A] != i and si[k, B.S_B] != i:
            continue
        t_ref = refs[k, 0]
        for c in range(n_c):
            t_ref += refs[k, 1 + c] * refs[-1, 1 + c]
        if si[k, B.S_A] == i:  # the span pulls its upstream roller forward
            web_torque += arm(si[k, B.S_ARMA], i, x, offsets, nodes) * t_ref
        else:
            web_torque -= arm(si[k, B.S_ARMB], i, x, offsets, nodes) * t_ref
    inertia = node_inertia(i, x, offsets, nodes, rolls) + motor_beyond(d, df)  # (a belt's)
    ratio = df[d, B.D_RATIO]  # (a compliant drive's node has none: its torque is the belt's)
    omega_ref = v_ref / radius
    r_dot = _radius_rate(v_ref, radius, fb[d, B.FB_THICK], fb[d, B.FB_DIR])
    omega_dot = a_ref / radius - v_ref * r_dot / (radius * radius)
    adaptive = family == B.FAMILY_ADAPTIVE
    friction = istate[d, B.I_FRICTION] if adaptive else fb[d, B.FB_BMODEL]
    u_eq = (inertia * omega_dot - web_torque + fb[d, B.FB_BMOTOR] * omega_ref
            + _friction(omega_ref, friction, nodes[i, B.N_COULOMB])) / ratio
    x_v = v_meas - v_ref
    comp = 0.0
    if fb[d, B.FB_DIR] != 0.0:  # cancel the roll's velocity-squared term (f of 6.39, 6.42)
        comp = -fb[d, B.FB_DIR] * inertia * fb[d, B.FB_THICK] / (
            2.0 * math.pi * radius**3) * (v_meas * v_meas - v_ref * v_ref) / ratio
    gain = inertia / (ratio * radius) / df[d, B.D_GAINNORM]
    mrac = family == B.FAMILY_MRAC
    if mrac:  # adapted gains and a bias (the chain's sim.drives.mrac)
        feedback = -gain * (istate[d, B.I_KT] * x_t + istate[d, B.I_KV] * x_v) - istate[
            d, B.I_BIAS]
    else:
        feedback = -gain * (fb[d, B.FB_KT] * x_t + fb[d, B.FB_KV] * x_v)
    if adaptive:  # friction felt at the measured speed, not only at the reference
        feedback += friction * x_v / (radius * ratio)
    raw = u_eq + comp + feedback
    u = _saturate(raw, df[d, B.D_LIMIT])
    # the estimates adapt while the line runs: from a break's detection on the tension loops
    # are frozen and the motion is the stop's, whose errors they would learn as friction
    # (the laminator's foil unwind: b̂ from 0.05 to 24 N·m·s over a 5 s stop), so they keep
    # what they knew at the detection for the restart
    learning = u == raw and adapting
    if adaptive and learning:
        adapt(d, dt, x_v, omega_ref, gain, ratio, istate, fb)
    if mrac and learning:
        mrac_adapt(d, dt, x_t, x_v, istate, fb)
    return u


@jit
def adapt(d: int, dt: float, x_v: float, omega_ref: float, gain: float, ratio: float,
          istate: np.ndarray, fb: np.ndarray) -> None:
    """One Euler step of the friction estimate b̂ [N·m·s] (the chain's
    ``sim.drives.controllers.adapt``, E-6.8): db̂/dt = -γ g K_V n ω_ref x_V / max(ω_ref², 1)
    - σ γ (b̂ - b_model), projected onto [0, b_max]; ``x_v`` [m/s], ``omega_ref`` [rad/s]."""
    rate = fb[d, B.FB_GAMMA] * gain * fb[d, B.FB_KV] * ratio / max(omega_ref**2, 1.0)
    b_hat = istate[d, B.I_FRICTION]
    b_hat += dt * (-rate * omega_ref * x_v - fb[d, B.FB_LEAK] * fb[d, B.FB_GAMMA]
                   * (b_hat - fb[d, B.FB_BMODEL]))
    istate[d, B.I_FRICTION] = min(max(b_hat, 0.0), fb[d, B.FB_BMAX])


@jit
def mrac_adapt(d: int, dt: float, x_t: float, x_v: float, istate: np.ndarray,
               fb: np.ndarray) -> None:
    """One Euler step [s] of the MRAC's law (the chain's ``sim.drives.mrac.mrac_adapt``, Sec.
    6.3 with E-6.8 and E-6.14): s = eᵀPb, dk̂_j/dt = Γ_j s x_j, dĉ/dt = γ_c s, σ-modification
    towards the design and projection onto the box of ``parameter_bound`` around it."""
    s = fb[d, B.FB_PBT] * x_t + fb[d, B.FB_PBV] * x_v
    leak = fb[d, B.FB_LEAK] * fb[d, B.FB_GAMMA]
    k_t = istate[d, B.I_KT] + dt * (fb[d, B.FB_GKT] * s * x_t
                                    - leak * (istate[d, B.I_KT] - fb[d, B.FB_KT]))
    k_v = istate[d, B.I_KV] + dt * (fb[d, B.FB_GKV] * s * x_v
                                    - leak * (istate[d, B.I_KV] - fb[d, B.FB_KV]))
    bias = istate[d, B.I_BIAS] + dt * (fb[d, B.FB_GBIAS] * s - leak * istate[d, B.I_BIAS])
    istate[d, B.I_KT] = _clip(k_t, fb[d, B.FB_KT], fb[d, B.FB_KBT])
    istate[d, B.I_KV] = _clip(k_v, fb[d, B.FB_KV], fb[d, B.FB_KBV])
    istate[d, B.I_BIAS] = _clip(bias, 0.0, fb[d, B.FB_CBOUND])


@jit
def _clip(value: float, centre: float, half_width: float) -> float:
    return min(max(value, centre - half_width), centre + half_width)
