"""A PI speed loop sampled with a zero-order hold around a linear drive: the closed loop's
discrete matrix, its eigenvalues as continuous-time equivalents, and a step with a torque limit.

What it models is what a digital drive (or the ECP listing of thesis Appendix B) runs: every
``ts`` [s] the speed is read, either as the true speed (a tachogenerator, an ideal observer:
``estimate = "ideal"``) or as the backward difference of the position over one sample (an
encoder: ``estimate = "difference"``, the listing's ``vm = (enc1_pos - past_pos)/ts``), the PI
u_k = kp e_k + ki S_k, S_k = S_{k-1} + ts e_k (the listing's ``sum_error``, with ki in
continuous units: ki_listing = ki ts), and the torque is held until the next sample.

Discrete state z_k = [x_k, S_{k-1}, p_{k-1}] with x the plant's state and p the fed-back
position (used by the backward difference only).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm


@dataclass(frozen=True)
class SampledLoop:
    """Discrete closed loop: z_{k+1} = F z_k + G r (reference r [rad/s] or [m/s]); ``u_row``
    and ``u_ref`` give the (unsaturated) input u_k = u_row z_k + u_ref r; ``ad``, ``bd`` the
    zero-order-hold plant; ``ts`` [s]."""

    f: np.ndarray
    g: np.ndarray
    u_row: np.ndarray
    u_ref: float
    ad: np.ndarray
    bd: np.ndarray
    ts: float
    n_plant: int
    kp: float
    ki: float
    c_x: np.ndarray
    c_p: float
    position: int


def zoh(a: np.ndarray, b: np.ndarray, ts: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero-order-hold discretisation (exact for a held input) of x' = A x + b u."""
    n = a.shape[0]
    aug = np.zeros((n + 1, n + 1))
    aug[:n, :n], aug[:n, n] = a, b
    phi = expm(aug * ts)
    return phi[:n, :n], phi[:n, n]


def sampled_pi(a: np.ndarray, b: np.ndarray, speed: int, position: int, kp: float, ki: float,
               ts: float, estimate: str = "ideal") -> SampledLoop:
    """The sampled PI loop around x' = A x + b u: state index ``speed`` fed back (or, with
    ``estimate = "difference"``, the backward difference of state ``position``); gains kp
    [N·m·s/rad or N·s/m], ki [N·m/rad or N/m]; sample time ``ts`` [s]."""
    if estimate not in ("ideal", "difference"):
        raise ValueError(f"estimate must be 'ideal' or 'difference', got {estimate!r}")
    n = a.shape[0]
    ad, bd = zoh(a, b, ts)
    # measured speed y_k = c_x x_k + c_p p_{k-1}
    c_x = np.zeros(n)
    c_p = 0.0
    if estimate == "ideal":
        c_x[speed] = 1.0
    else:
        c_x[position] = 1.0 / ts
        c_p = -1.0 / ts
    # e_k = r - y_k; u_k = (kp + ki ts) e_k + ki S_{k-1}
    kk = kp + ki * ts
    u_row = np.concatenate([-kk * c_x, [ki, -kk * c_p]])
    m = n + 2
    f = np.zeros((m, m))
    f[:n, :] = np.outer(bd, u_row)
    f[:n, :n] += ad
    f[n, :n] = -ts * c_x  # S_k = S_{k-1} + ts e_k
    f[n, n] = 1.0
    f[n, n + 1] = -ts * c_p
    f[n + 1, position] = 1.0  # p_k = position of x_k
    g = np.zeros(m)
    g[:n] = bd * kk
    g[n] = ts
    return SampledLoop(f, g, u_row, kk, ad, bd, ts, n, kp, ki, c_x, c_p, position)


def equivalent_eigenvalues(loop: SampledLoop) -> np.ndarray:
    """The closed loop's eigenvalues z mapped to s = ln(z)/ts [1/s] (a z on the negative real
    axis maps to the Nyquist frequency), zero z (the unused delay state) dropped."""
    z = np.linalg.eigvals(loop.f)
    z = z[np.abs(z) > 1e-12]
    return np.log(z.astype(complex)) / loop.ts


def spectral_radius(loop: SampledLoop) -> float:
    """max |z| of the closed loop [-]: > 1 is unstable when sampled."""
    return float(np.max(np.abs(np.linalg.eigvals(loop.f))))


def step(loop: SampledLoop, reference: float, n_steps: int,
         limit: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """Plant states (n_steps + 1 samples) and held inputs (n_steps) after a step of the
    reference at k = 0, the input clipped to ±``limit``; the integral stops while the input
    saturates in the direction it pushes (conditional integration, as webline's drives)."""
    n, ts = loop.n_plant, loop.ts
    x = np.zeros(n)
    s_prev = 0.0  # S_{k-1}
    p_prev = 0.0  # p_{k-1}
    xs = np.empty((n_steps + 1, n))
    us = np.empty(n_steps)
    for k in range(n_steps):
        xs[k] = x
        e = float(reference - (loop.c_x @ x + loop.c_p * p_prev))
        s_k = s_prev + ts * e
        raw = loop.kp * e + loop.ki * s_k
        if abs(raw) > limit and e * raw > 0.0:
            s_k = s_prev  # conditional integration
            raw = loop.kp * e + loop.ki * s_k
        u = float(np.clip(raw, -limit, limit))
        p_prev = float(x[loop.position])
        s_prev = s_k
        x = loop.ad @ x + loop.bd * u
        us[k] = u
    xs[n_steps] = x
    return xs, us
