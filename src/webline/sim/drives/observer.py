"""A decentralized tension observer per section (thesis Sec. 6.4, future work), in the loop.

For a drive on node i whose zone is the single span k next to it (k = i - 1 or k = i), the
observer integrates the span equation (6.8) with the *measured* web speeds of its two rollers
and the torque balance of its own roller with the motor torque and the known interconnection
(the other neighbouring span at its reference tension):

    L dT̂/dt = EA (v_{k+1} - v_k) + T_{k-1} v_k - T̂ v_{k+1}   (exact transport: its exact form)
    J dω̂/dt = r (T_out - T_in) + n τ - b ω̂ - c sgn ω̂     (T̂ in place of span k)

and corrects both with the speed residual ω_meas - ω̂: T̂ += l_T (ω - ω̂) dt, ω̂ += l_ω (ω - ω̂) dt.
The error (T - T̂, ω - ω̂) then obeys [[-v/L, -l_T], [±r/J, -b/J - l_ω]]; l_ω, l_T place both
poles at -λ (``observer_bandwidth``; ``drive_table.observer_gains``). The tension enters the
speed only through r/J, so an EA error biases T̂ through the span equation (study
``tension-observer``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import roller, span
from webline.sim.elements import layout as L
from webline.sim.elements.signals import gaussian, jit

_friction: Any = jit(roller.friction_torque)
_exact_rate: Any = jit(span.exact_stretch_rate)


@jit
def observe(d: int, i: int, dt: float, tick: int, radius: float, inertia: float,
            omega_meas: float, x: np.ndarray, istate: np.ndarray, ds: np.ndarray,
            offsets: np.ndarray, nodes: np.ndarray, drives: np.ndarray, web: np.ndarray,
            span_ref: np.ndarray) -> float:
    """One Euler step [s] of drive ``d``'s observer on node ``i``; returns T̂ [N]."""
    k = ds[d, L.DS_LOADCELL]
    other = int(drives[d, L.D_OBS_OTHER])
    omega_other = x[offsets[L.O_OMEGA] + other]
    if offsets[L.O_NOISE] and web[L.W_NOISE_V] > 0.0:  # its tachometer, another stream
        omega_other += web[L.W_NOISE_V] * gaussian(int(web[L.W_SEED]), tick,
                                                   2 * ds.shape[0] + d) / nodes[other, L.N_RADIUS]
    v_own, v_other = radius * omega_meas, nodes[other, L.N_RADIUS] * omega_other
    upstream = i == k  # the drive's roller is the span's upstream end
    v_in, v_out = (v_own, v_other) if upstream else (v_other, v_own)
    t_hat, w_hat = istate[d, L.I_THAT], istate[d, L.I_WHAT]
    t_before = web[L.W_T0] if k == 0 else span_ref[k - 1]
    length = drives[d, L.D_OBS_LENGTH]
    ea = drives[d, L.D_OBS_EA]
    if offsets[L.O_EXACT]:  # the line's own transport (E-6.6): else a bias ~(T_in² - T²)/EA
        dt_hat = _exact_rate(length, ea, v_in, v_out, t_before, t_hat, t_hat)
    else:
        dt_hat = (ea * (v_out - v_in) + t_before * v_in - t_hat * v_out) / length
    if upstream:  # own roller: T_out = T̂, T_in = the span before
        t_in = 0.0 if i == 0 else span_ref[i - 1]  # an unwind roll: no span before it
        net = radius * (t_hat - t_in)
    else:  # own roller: T_in = T̂, T_out = the span after (its reference)
        t_out = span_ref[i] if i < span_ref.shape[0] else 0.0
        net = radius * (t_out - t_hat)
    torque = x[offsets[L.O_TORQUE] + d] * nodes[i, L.N_RATIO]  # the drive's torque (current)
    ratio = nodes[i, L.N_RATIO]
    friction = _friction(w_hat, drives[d, L.D_BMODEL], nodes[i, L.N_COULOMB])
    friction += ratio * ratio * drives[d, L.D_BMOTOR] * w_hat
    dw_hat = (net + torque - friction) / inertia
    residual = omega_meas - w_hat
    istate[d, L.I_THAT] = t_hat + dt * (dt_hat + drives[d, L.D_OBS_LT] * residual)
    istate[d, L.I_WHAT] = w_hat + dt * (dw_hat + drives[d, L.D_OBS_LW] * residual)
    return istate[d, L.I_THAT]

