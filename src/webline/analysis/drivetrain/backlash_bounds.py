"""Error bounds due to backlash (thesis 3.33-3.66) and the shift of the mean and standard deviation
of an output such as the web tension (4.7-4.10).

The backlash model is the linear compliant model plus a bounded input (3.47), (3.63):
    ż = A z + W r + D φ(z),  |φ| <= φmax = K α2 Δ,
so, by superposition (3.39)-(3.40), (3.55)-(3.56), the deviation from the backlash-free run
from the same initial state is e(t) = ∫_0^t e^{A(t-τ)} D φ(τ) dτ. Three bounds on |c e(t)| (or
on ‖e(t)‖ when no output row c is given):

* ``printed_bound`` — (3.41), (3.57), (3.66): φmax ‖∫_0^t e^{Aσ} D dσ‖. It moves sup|φ| out of
  the integral *inside* the norm, which holds only if the kernel c e^{Aσ} D keeps one sign on
  [0, t] (or φ is constant). It is the response to a constant φ = φmax, hence a lower bound
  on the worst case, and an oscillatory loop exceeds it (E-3.3).
* ``l1_bound`` — valid for any sign pattern of φ: φmax ∫_0^t |c e^{Aσ} D| dσ, the L1 norm of
  the impulse response (for a scalar output it is attained by φ = φmax sign(h(t - τ))).
* ``eigen_bound`` — (3.61)-(3.62) generalised to complex eigenvalues:
  φmax ‖c‖ cond(V) ‖D‖ (1 - e^{-αt})/α, α = min(-Re λ). Its derivation passes through the
  invalid step, but the result also bounds ∫‖e^{Aσ}D‖dσ, so it is valid for any sign pattern
  (V is the eigenvector matrix: 'orthonormal' in the text is wrong, E-3.4). Needs A Hurwitz,
  so it uses the loop in reduced coordinates.

Coordinates of the PI loop (3.51)-(3.53), rotary form of (3.63)-(3.64), rectilinear with
R1 = α1 = 1: 'thesis' z = [θm, ωm, θL, ωL, ξ] (A has a zero eigenvalue: the rigid rotation,
which D does not excite) and 'reduced' z = [d, ωm, ωL, ξ] with d = R1 θm - α1 θL, Hurwitz.
D = [0, -R1/Jm, 0, α1/JL, 0] with φ of (3.65) (the rectilinear (3.50) has the opposite signs on
both D and φ, which is the same product).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from webline.analysis.drivetrain.params import BacklashDrive, SpeedPI
from webline.physics.backlash import belt_gear_backlash_deviation


@dataclass(frozen=True)
class BacklashLoop:
    """Linear part of the PI loop with backlash: ż = A z + W r + F τL + D φ; ``load_speed`` is
    the row c with c z = ωL. ``phi_max`` [N] bounds |φ|."""

    a: np.ndarray
    w: np.ndarray
    f: np.ndarray
    d: np.ndarray
    load_speed: np.ndarray
    phi_max: float


def backlash_loop(plant: BacklashDrive, gains: SpeedPI,
                  coordinates: str = "thesis") -> BacklashLoop:
    """(3.52)-(3.53) for the PI on the motor speed (Fig. 3.15), τm = Kp (r - ωm) + Ki ξ."""
    jm, jl, bm, bl = plant.j_motor, plant.j_load, plant.b_motor, plant.b_load
    k, r1, a1 = plant.stiffness, plant.r_motor, plant.lever_load
    kp, ki = gains.kp, gains.ki
    if coordinates == "thesis":
        a = np.array([
            [0.0, 1.0, 0.0, 0.0, 0.0],
            [-k * r1 * r1 / jm, -(bm + kp) / jm, k * r1 * a1 / jm, 0.0, ki / jm],
            [0.0, 0.0, 0.0, 1.0, 0.0],
            [k * a1 * r1 / jl, 0.0, -k * a1 * a1 / jl, -bl / jl, 0.0],
            [0.0, -1.0, 0.0, 0.0, 0.0],
        ])
        w, f = np.array([0.0, kp / jm, 0.0, 0.0, 1.0]), np.array([0.0, 0.0, 0.0, 1.0 / jl, 0.0])
        d, c = np.array([0.0, -r1 / jm, 0.0, a1 / jl, 0.0]), np.array([0.0, 0.0, 0.0, 1.0, 0.0])
    elif coordinates == "reduced":
        a = np.array([
            [0.0, r1, -a1, 0.0],
            [-k * r1 / jm, -(bm + kp) / jm, 0.0, ki / jm],
            [k * a1 / jl, 0.0, -bl / jl, 0.0],
            [0.0, -1.0, 0.0, 0.0],
        ])
        w, f = np.array([0.0, kp / jm, 0.0, 1.0]), np.array([0.0, 0.0, 1.0 / jl, 0.0])
        d, c = np.array([0.0, -r1 / jm, a1 / jl, 0.0]), np.array([0.0, 0.0, 1.0, 0.0])
    else:
        raise ValueError(f"coordinates must be 'thesis' or 'reduced', got {coordinates!r}")
    return BacklashLoop(a, w, f, d, c, plant.deviation_bound)


def series_backlash_loop(a1: np.ndarray, b1: np.ndarray, c1: np.ndarray, a2: np.ndarray,
                         b2: np.ndarray, c2: np.ndarray, half_gap: float) -> BacklashLoop:
    """Fig. 3.13 / (3.33)-(3.37): G1 = (A1, B1, C1) feeding G2 = (A2, B2, C2) through a
    backlash y = u + f(u), |f| <= Δ = ``half_gap``. Single input r and single u, y, z; the
    returned loop has D = [0; B2], output row C = [0, C2] (in ``load_speed``) and no load
    input. Use it with the bounds below for (3.41)."""
    n1, n2 = a1.shape[0], a2.shape[0]
    b1, c1, b2, c2 = (np.asarray(v, float).ravel() for v in (b1, c1, b2, c2))
    a = np.block([[a1, np.zeros((n1, n2))], [np.outer(b2, c1), a2]])
    return BacklashLoop(a=a, w=np.concatenate([b1, np.zeros(n2)]), f=np.zeros(n1 + n2),
                        d=np.concatenate([np.zeros(n1), b2]),
                        load_speed=np.concatenate([np.zeros(n1), c2]), phi_max=half_gap)


def _horizon(a: np.ndarray) -> float:
    lam = np.linalg.eigvals(a)
    decay = -lam.real[np.abs(lam) > 1e-9 * max(1.0, np.abs(lam).max())]
    if decay.size == 0 or decay.min() <= 0.0:
        raise ValueError("the loop is not asymptotically stable: no finite bound as t -> inf")
    return 40.0 / decay.min()


def _grid(a: np.ndarray, t: float, samples: int | None) -> np.ndarray:
    """σ grid on [0, t]: at least 40 points per period of the fastest mode."""
    if samples is None:
        fastest = float(np.abs(np.linalg.eigvals(a)).max())
        samples = int(min(2_000_000, max(20_000, np.ceil(t * fastest * 40.0 / (2.0 * np.pi)))))
    return np.linspace(0.0, t, samples + 1)


def _modal_response(a: np.ndarray, d: np.ndarray, sigma: np.ndarray,
                    integrated: bool) -> np.ndarray:
    """e^{Aσ} D (or ∫_0^σ e^{As} ds D) for every σ, columns; modal sums when A is
    diagonalisable and well conditioned, else by stepping expm."""
    lam, vec = np.linalg.eig(a)
    if np.linalg.cond(vec) < 1e8:
        coef = np.linalg.solve(vec, d.astype(complex))
        if integrated:
            small = np.abs(lam) < 1e-12 * max(1.0, float(np.abs(lam).max()))
            safe = np.where(small, 1.0, lam)
            modes = np.where(small[:, None], sigma[None, :],
                             np.expm1(np.outer(safe, sigma)) / safe[:, None])
        else:
            modes = np.exp(np.outer(lam, sigma))
        return (vec @ (coef[:, None] * modes)).real
    h = sigma[1] - sigma[0]
    n = a.shape[0]
    aug = np.zeros((n + 1, n + 1))
    aug[:n, :n], aug[:n, n] = a, d
    step, piece = expm(a * h), expm(aug * h)[:n, n]
    out = np.empty((n, sigma.size))
    x = np.zeros(n) if integrated else d.astype(float)
    for i in range(sigma.size):
        out[:, i] = x
        if integrated:
            x, piece = x + piece, step @ piece
        else:
            x = step @ x
    return out


def _measure(values: np.ndarray, output: np.ndarray | None) -> np.ndarray:
    return np.abs(output @ values) if output is not None else np.linalg.norm(values, axis=0)


def printed_bound(loop: BacklashLoop, t: float | None = None,
                  output: np.ndarray | None = None) -> float:
    """(3.41)/(3.57)/(3.66): φmax ‖∫_0^t e^{Aσ} D dσ‖ (|c ∫...| for an ``output`` row c).

    NOT a bound in general: valid only when the kernel keeps one sign (module docstring).
    ``t`` [s]; None for t → ∞.
    """
    a, d = loop.a, loop.d
    t = _horizon(a) if t is None else t
    n = a.shape[0]
    aug = np.zeros((n + 1, n + 1))
    aug[:n, :n], aug[:n, n] = a, d
    integral = expm(aug * t)[:n, n]
    return float(loop.phi_max * _measure(integral[:, None], output)[0])


def printed_bound_peak(loop: BacklashLoop, t: float | None = None,
                       output: np.ndarray | None = None, samples: int | None = None) -> float:
    """max over s in [0, t] of ``printed_bound`` at s (the most generous reading of the
    time-dependent (3.57)); still not a bound in general. ``t`` [s], None: 40 time constants."""
    t = _horizon(loop.a) if t is None else t
    sigma = _grid(loop.a, t, samples)
    values = _modal_response(loop.a, loop.d, sigma, integrated=True)
    return float(loop.phi_max * _measure(values, output).max())


def l1_bound(loop: BacklashLoop, t: float | None = None, output: np.ndarray | None = None,
             samples: int | None = None) -> float:
    """Valid for any sign pattern of φ: φmax ∫_0^t |c e^{Aσ} D| dσ (‖e^{Aσ} D‖ without c).

    Trapezoid rule on a grid of at least 40 points per period of the fastest mode (the kinks
    of |h| at its zeros make the error O(h²) per zero: below 1e-5 relative here). ``t`` [s];
    None for t → ∞ (40 slowest time constants: tail below e^-40).
    """
    t = _horizon(loop.a) if t is None else t
    sigma = _grid(loop.a, t, samples)
    values = _measure(_modal_response(loop.a, loop.d, sigma, integrated=False), output)
    return float(loop.phi_max * np.trapezoid(values, sigma))


def eigen_bound(loop: BacklashLoop, t: float | None = None,
                output: np.ndarray | None = None) -> float:
    """(3.61)/(3.62), complex eigenvalues allowed: φmax ‖c‖ cond(V) ‖D‖ (1 - e^{-αt})/α.

    Valid for any sign pattern; needs A Hurwitz (use the 'reduced' coordinates).
    """
    lam, vec = np.linalg.eig(loop.a)
    alpha = float(np.min(-lam.real))
    if alpha <= 1e-9 * max(1.0, float(np.abs(lam).max())):
        raise ValueError("A is not Hurwitz: use backlash_loop(..., coordinates='reduced')")
    factor = (1.0 - np.exp(-alpha * t)) / alpha if t is not None else 1.0 / alpha
    gain = np.linalg.norm(output) if output is not None else 1.0
    return float(loop.phi_max * gain * np.linalg.cond(vec) * np.linalg.norm(loop.d) * factor)


def worst_case_phi(loop: BacklashLoop, t: float, output: np.ndarray,
                   samples: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(τ grid [s], φ(τ) [N]) = φmax sign(c e^{A(t-τ)} D): the admissible input that attains
    the L1 bound at time t (and so exceeds the printed one when the kernel changes sign)."""
    sigma = _grid(loop.a, t, samples)
    h = output @ _modal_response(loop.a, loop.d, sigma, integrated=False)
    return t - sigma[::-1], loop.phi_max * np.sign(h[::-1])


def simulate_loop(plant: BacklashDrive, gains: SpeedPI, reference: Callable[[float], float],
                  t_eval: np.ndarray, backlash: bool = True,
                  load_torque: Callable[[float], float] | None = None) -> np.ndarray:
    """States [θm, ωm, θL, ωL, ξ] of the PI loop with (or without) backlash at ``t_eval`` [s],
    from rest: ż = A z + W r + F τL + β D φ(θm, θL) (3.52) with φ of (3.65)."""
    loop = backlash_loop(plant, gains, "thesis")
    args = (plant.stiffness, plant.r_motor, plant.lever_load, plant.gap_gain, plant.gap_neg,
            plant.gap_pos)

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        dz = loop.a @ z + loop.w * reference(t)
        if load_torque is not None:
            dz = dz + loop.f * load_torque(t)
        if backlash:
            dz = dz + loop.d * belt_gear_backlash_deviation(z[0], z[2], *args)
        return dz

    span = (float(t_eval[0]), float(t_eval[-1]))
    sol = solve_ivp(rhs, span, np.zeros(5), t_eval=t_eval, rtol=1e-9, atol=1e-12,
                    method="DOP853")
    return sol.y.T


@dataclass(frozen=True)
class StatisticsShift:
    """Mean and standard deviation of a sampled output without and with backlash (4.9, 4.10)."""

    mean_without: float
    mean_with: float
    std_without: float
    std_with: float

    @property
    def mean_shift(self) -> float:
        return self.mean_with - self.mean_without

    @property
    def std_shift(self) -> float:
        return self.std_with - self.std_without


def statistics_shift(without: np.ndarray, deviation: np.ndarray) -> StatisticsShift:
    """(4.9)-(4.10) for samples T_0(iTs) of the output without backlash and the deviation
    Lp2 g(iTs) it gains with backlash (T_BL = T_0 + Lp2 g), population statistics (1/(n+1)):

    mean_with = mean_0 + mean(Lp2 g)                                          (4.9b)
    std_with = sqrt(std_0² + mean(f)),  f = (Lp2 g - gμ)² + 2 (T_0 - mean_0)(Lp2 g - gμ),
    gμ = mean(Lp2 g)                         (4.10b, with the square and the sum restored: E-4.2)

    Both shifts are at most sup|Lp2 g| (|mean(x)| <= sup|x|; |std(a+b) - std(a)| <= std(b)
    <= sup|b|), so any valid bound on |Lp2 g| (``l1_bound``) bounds them.
    """
    t0, g = np.asarray(without, float), np.asarray(deviation, float)
    mean0, g_mu = float(t0.mean()), float(g.mean())
    std0 = float(np.sqrt(np.mean((t0 - mean0) ** 2)))
    f = (g - g_mu) ** 2 + 2.0 * (t0 - mean0) * (g - g_mu)
    return StatisticsShift(mean0, mean0 + g_mu, std0, float(np.sqrt(std0**2 + f.mean())))
