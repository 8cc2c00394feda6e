"""The decentralized MRAC of thesis Sec. 6.3 in the compiled loop (6.66-6.68, E-6.8, E-6.14).

Section i: ẋ = A x + b u + Σ A_ij x_j with A = A_m + b kᵀ (6.63), A_m the design's closed loop.
The reference model (6.66) is driven by r_i, the deviation of the input from the equilibrium
input; webline computes the equilibrium input every tick (u_eq, from the references), so r ≡ 0
and, started at the equilibrium x_m(0) = 0, the reference model with its interconnections and
k_mᵀx_m stays exactly at rest: e_i = x_i (docs/errata.md E-6.14). With the control
u = u_eq + f - k̂ᵀx - ĉ (6.68a plus a bias ĉ for the equilibrium input's friction error d) the
error obeys ė = A_m e + b (k̃ᵀx + d - ĉ) + Σ A_ij e_j, and
V = Σ eᵀPe + k̃ᵀΓ⁻¹k̃ + (d - ĉ)²/γ_c decreases (up to the interconnection terms bounded by
(6.69)) along

    dk̂/dt = +Γ (eᵀP b) x,    dĉ/dt = +γ_c (eᵀP b)        (the sign of 6.68b corrected)

P from A_mᵀP + P A_m = -I in the design's scaled units (``control.decentralized``).
"""

from __future__ import annotations

import numpy as np

from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit


@jit
def mrac_feedback(d: int, x_t: float, x_v: float, gain: float, istate: np.ndarray) -> float:
    """-k̂ᵀx - ĉ [N·m] of drive ``d`` for deviations ``x_t`` [N], ``x_v`` [m/s]; ``gain``
    follows the roll inertia as for the state feedback."""
    return -gain * (istate[d, L.I_KT] * x_t + istate[d, L.I_KV] * x_v) - istate[d, L.I_BIAS]


@jit
def mrac_adapt(d: int, dt: float, x_t: float, x_v: float, istate: np.ndarray,
               drives: np.ndarray) -> None:
    """One Euler step [s] of the adaptive law (module docstring), σ-modification towards the
    design and projection onto the box of ``parameter_bound`` around it."""
    s = drives[d, L.D_PBT] * x_t + drives[d, L.D_PBV] * x_v
    leak = drives[d, L.D_LEAK] * drives[d, L.D_GAMMA]
    k_t = istate[d, L.I_KT]
    k_t += dt * (drives[d, L.D_GKT] * s * x_t - leak * (k_t - drives[d, L.D_KT]))
    k_v = istate[d, L.I_KV]
    k_v += dt * (drives[d, L.D_GKV] * s * x_v - leak * (k_v - drives[d, L.D_KV]))
    bias = istate[d, L.I_BIAS]
    bias += dt * (drives[d, L.D_GBIAS] * s - leak * bias)
    istate[d, L.I_KT] = _clip(k_t, drives[d, L.D_KT], drives[d, L.D_KBT])
    istate[d, L.I_KV] = _clip(k_v, drives[d, L.D_KV], drives[d, L.D_KBV])
    istate[d, L.I_BIAS] = _clip(bias, 0.0, drives[d, L.D_CBOUND])


@jit
def _clip(value: float, centre: float, half_width: float) -> float:
    return min(max(value, centre - half_width), centre + half_width)
