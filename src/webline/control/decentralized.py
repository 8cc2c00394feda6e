"""Design of the decentralized controllers of thesis Ch. 6 on each section's own model.

Everything is designed in scaled units, x̃ = S x with S = diag(1/tension_scale, 1/speed_scale)
and ũ = u/torque_scale, so that the weights and the adaptation rate are dimensionless:

* state feedback: LQ with Q = I, R = ρ on (S A S⁻¹, S B u_s), ρ ≥ 1 raised (bisection on
  log ρ) until the section's fastest closed-loop pole is below ``max_bandwidth`` — a model
  without the torque lag and the sampling must not be asked for a loop faster than they allow;
  the closed-loop section matrix is Ā = A - B Kᵀ, and K is computed from it directly (the
  printed gain formulas after 6.57 have sign errors, E-6.7);
* adaptive control: the reference model is the LQ closed loop, A_m = Ā (6.63 holds with
  k = the LQ gain), P solves A_mᵀP + P A_m = -I, and the adaptive law uses P B in scaled units.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.control.sections import SectionModel


@dataclass(frozen=True)
class SectionDesign:
    """A section's design: gain on (T, V) deviations (physical: [N·m/N, N·m·s/m]; a master
    section has a zero tension gain), its scaled version, the scaled P·B of the adaptive law
    and the closed-loop section matrix Ā [SI]."""

    gain: np.ndarray
    gain_scaled: np.ndarray
    pb_scaled: np.ndarray
    closed: np.ndarray


def lq_gain(a: np.ndarray, b: np.ndarray, rho: float) -> np.ndarray:
    """LQ state-feedback gain for Q = I, R = ``rho`` (u = -K x)."""
    import scipy.linalg  # here: PI-only lines (the main job's) never import scipy

    p = scipy.linalg.solve_continuous_are(a, b, np.eye(a.shape[0]), rho * np.eye(1))
    return (b.T @ p).ravel() / rho


def design_section(model: SectionModel, tension_scale: float, speed_scale: float,
                   torque_scale: float, max_bandwidth: float = np.inf) -> SectionDesign:
    """LQ design of one section in scaled units (module docstring); scales in [N], [m/s],
    [N·m], ``max_bandwidth`` [rad/s]."""
    has_tension = model.a.shape[0] == 2
    scales = np.array([tension_scale, speed_scale]) if has_tension else np.array([speed_scale])
    s = np.diag(1.0 / scales)
    a = s @ model.a @ np.diag(scales)
    b = s @ model.b * torque_scale

    def fastest(log_rho: float) -> float:
        k = lq_gain(a, b, 10.0**log_rho)
        return float(np.abs(np.linalg.eigvals(a - b @ k[None, :])).max())

    low, high = 0.0, 16.0
    if fastest(low) > max_bandwidth:
        for _ in range(30):  # 2^-30 of the 16 decades: far finer than the cap needs
            mid = 0.5 * (low + high)
            low, high = (mid, high) if fastest(mid) > max_bandwidth else (low, mid)
        low = high
    k_scaled = lq_gain(a, b, 10.0**low)
    a_closed = a - b @ k_scaled[None, :]
    import scipy.linalg  # (lq_gain's comment)

    lyap = scipy.linalg.solve_continuous_lyapunov(a_closed.T, -np.eye(len(scales)))
    pb = (lyap @ b).ravel()
    gain = torque_scale * k_scaled / scales
    closed = model.a - model.b @ gain[None, :]
    if not has_tension:
        k_scaled, pb, gain = (np.r_[0.0, v] for v in (k_scaled, pb, gain))
    return SectionDesign(gain=gain, gain_scaled=k_scaled, pb_scaled=pb, closed=closed)
