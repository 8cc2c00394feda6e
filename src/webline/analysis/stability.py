"""Distance to instability and the bounded-real Riccati equation of thesis Sec. 6.2 (numerics).

The distance of a square matrix A (real or complex) to the matrices with an eigenvalue on the
imaginary axis (6.14) is

    δs(A) = min_ω σ_min(A - jωI)                                            (6.15)

[same unit as A, e.g. 1/s]. For a Hurwitz A it is 1/‖(sI - A)⁻¹‖∞, the reciprocal of the H∞
norm of the resolvent. It is computed by bisection on the Hamiltonian of Lemma 6.2.1,

    H_ρ = [[A, -ρI], [ρI, -Aᴴ]],                                            (6.16)

which has an eigenvalue jω if and only if ρ is a singular value of A - jωI, hence an
imaginary eigenvalue if and only if ρ ≥ δs(A) (6.17). Each level ρ whose Hamiltonian has
imaginary eigenvalues jω₁ < … < jω_m is checked on σ_min at the ω_k and at the midpoints of
consecutive ones (the level-set idea of Boyd-Balakrishnan-Bruinsma-Steinbuch): σ_min is below ρ
on the whole interval between consecutive crossings of a dip, so a midpoint value is a *true*
upper bound below ρ, while eigenvalues that only look imaginary through rounding are rejected.
Levels without such a value are certified lower bounds. The final upper bound is polished by a
local minimisation of σ_min(A - jωI) near its best ω (σ_min is smooth at a simple minimum, so
the value converges to machine precision).

``solve_bounded_real_are`` solves the ARE (6.49), Āᵀ P + P Ā + N P² + q I = 0, from the stable
invariant subspace of its Hamiltonian (6.51) — scipy's ``solve_continuous_are`` needs the
quadratic term with the other sign. It has a (stabilising, positive definite) solution for a
Hurwitz Ā exactly when √(N q) < δs(Ā) (bounded-real lemma), which is (6.54) with q = ξ² + ε.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

#: Hamiltonian eigenvalues with |Re λ| below this times ‖H_ρ‖ are candidates for the imaginary
#: axis; a generous value costs only extra σ_min evaluations, since every candidate is checked.
AXIS_TOLERANCE = 1e-6


@dataclass(frozen=True)
class InstabilityDistance:
    """δs(A) with how it was found: ``value`` [unit of A] is attained at frequency ``omega``
    [rad/s if A is in 1/s] and certified from below by ``lower`` (no Hamiltonian H_ρ with
    ρ ≤ lower has an imaginary eigenvalue); ``iterations`` of the bisection."""

    value: float
    omega: float
    lower: float
    iterations: int


def sigma_min(a: np.ndarray, omega: float) -> float:
    """Smallest singular value of A - jωI (the function minimised in 6.15)."""
    a = np.asarray(a)
    return float(scipy.linalg.svdvals(a - 1j * omega * np.eye(a.shape[0]))[-1])


def hamiltonian(a: np.ndarray, rho: float) -> np.ndarray:
    """H_ρ of Lemma 6.2.1 (6.16), with Aᴴ for a complex A."""
    a = np.asarray(a)
    eye = np.eye(a.shape[0])
    return np.block([[a, -rho * eye], [rho * eye, -a.conj().T]])


def imaginary_frequencies(a: np.ndarray, rho: float,
                          tolerance: float = AXIS_TOLERANCE) -> np.ndarray:
    """Sorted ω of the eigenvalues of H_ρ within ``tolerance`` x ‖H_ρ‖ of the imaginary axis:
    the candidate frequencies at which ρ is a singular value of A - jωI."""
    h = hamiltonian(a, rho)
    eig = np.linalg.eigvals(h)
    scale = max(np.linalg.norm(h, 1), np.finfo(float).tiny)
    return np.sort(eig.imag[np.abs(eig.real) <= tolerance * scale])


def frequency_sweep_distance(a: np.ndarray, omegas: np.ndarray) -> float:
    """min over the given frequencies ``omegas`` of σ_min(A - jωI): an upper bound of δs(A)
    (6.15) that tends to it as the grid is refined."""
    return min(sigma_min(a, float(w)) for w in np.atleast_1d(omegas))


def _polish(a: np.ndarray, omega: float, width: float) -> tuple[float, float]:
    """Local minimum of σ_min(A - jωI) in [omega - width, omega + width]: (value, ω)."""
    import scipy.optimize  # here: importing it costs ~0.3 s, and a run's report never needs it

    res = scipy.optimize.minimize_scalar(lambda w: sigma_min(a, w), bounds=(omega - width,
                                         omega + width), method="bounded",
                                         options={"xatol": 1e-14 * max(1.0, abs(omega))})
    return (float(res.fun), float(res.x)) if res.fun < sigma_min(a, omega) else (
        sigma_min(a, omega), omega)


def instability_distance(a: np.ndarray, *, rtol: float = 1e-12,
                         max_iter: int = 200) -> InstabilityDistance:
    """δs(A) of (6.14)-(6.17) by bisection on H_ρ (module docstring), to relative accuracy
    ``rtol`` between the certified lower bound and the attained value (before polishing)."""
    a = np.asarray(a)
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ValueError(f"a square matrix is needed, got shape {a.shape}")
    eig = np.linalg.eigvals(a)
    norm = max(float(np.linalg.norm(a, 2)), np.finfo(float).tiny)
    if np.min(np.abs(eig.real)) <= 8 * np.finfo(float).eps * norm:
        return InstabilityDistance(0.0, float(eig.imag[np.argmin(np.abs(eig.real))]), 0.0, 0)
    # attained values: at ω = 0 and at the eigenvalues' frequencies (σ_min ≤ |Re λ| there)
    candidates = np.concatenate(([0.0], eig.imag))
    values = [sigma_min(a, w) for w in candidates]
    k = int(np.argmin(values))
    high, omega, low = values[k], float(candidates[k]), 0.0
    width = max(high, 1e-3 * norm)
    iterations = 0
    while high - low > rtol * high and iterations < max_iter:
        iterations += 1
        rho = 0.5 * (low + high) if low == 0.0 or high < 4 * low else np.sqrt(low * high)
        crossings = imaginary_frequencies(a, rho)
        points = np.concatenate((crossings, 0.5 * (crossings[1:] + crossings[:-1])))
        values = [sigma_min(a, w) for w in points]
        below = [j for j, v in enumerate(values) if v < rho]
        if not below:
            low = rho  # no dip under ρ: δs ≥ ρ
            continue
        j = min(below, key=lambda j: values[j])
        high, omega = values[j], float(points[j])  # < ρ < previous high
        if len(crossings) > 1:
            width = max(float(np.diff(crossings).max()), 1e-12 * (1 + abs(omega)))
    value, omega = _polish(a, omega, width)
    return InstabilityDistance(min(value, high), omega, min(low, value), iterations)


def distance_to_instability(a: np.ndarray, *, rtol: float = 1e-12) -> float:
    """δs(A) = min_ω σ_min(A - jωI) (thesis 6.14, 6.15) [unit of A], computed by bisection on
    the Hamiltonian of Lemma 6.2.1 (see ``instability_distance``); 0 if A already has an
    eigenvalue on the imaginary axis."""
    return instability_distance(a, rtol=rtol).value


def distance_2x2(a: np.ndarray) -> float:
    """δs(A) of a real 1x1 or 2x2 matrix in closed form (a cross-check of the bisection, and
    fast enough for searches).

    For A = [[a, b], [c, d]] with trace t and determinant Δ, σ² is a squared singular value of
    A - jωI iff σ⁴ - (‖A‖²_F + 2ω²) σ² + (Δ - ω²)² + ω² t² = 0. Setting the derivative with
    respect to ω² to zero gives ω² = Δ + σ² - t²/2, and substituting back (‖A‖²_F + 2Δ - t² =
    (b - c)²) the stationary value

        σ*² = t² (Δ - t²/4) / (b - c)²,

    attained if ω*² = Δ + σ*² - t²/2 > 0; otherwise the minimum is at ω = 0, σ_min(A). A
    symmetric A (b = c) is normal: δs = min |Re λ|.
    """
    a = np.asarray(a, dtype=float)
    if a.shape == (1, 1):
        return abs(float(a[0, 0]))
    if a.shape != (2, 2):
        raise ValueError(f"a 1x1 or 2x2 matrix is needed, got shape {a.shape}")
    (p, b), (c, d) = a.tolist()
    t, det = p + d, p * d - b * c
    frob = p * p + b * b + c * c + d * d

    def smallest(w2: float) -> float:
        """σ_min(A - jωI) at ω² = w2, as |det| / σ_max (no cancellation)."""
        big = frob + 2 * w2
        det2 = (det - w2) ** 2 + w2 * t * t
        s_max2 = 0.5 * (big + np.sqrt(max(big * big - 4 * det2, 0.0)))
        return float(np.sqrt(det2 / s_max2)) if s_max2 > 0 else 0.0

    best = smallest(0.0)
    if b == c:  # normal
        disc = 0.25 * t * t - det
        return float(min(abs(0.5 * t + np.sqrt(disc)), abs(0.5 * t - np.sqrt(disc)))
                     if disc >= 0 else abs(0.5 * t))
    s2 = t * t * (det - 0.25 * t * t) / (b - c) ** 2
    w2 = det + s2 - 0.5 * t * t
    if s2 >= 0.0 and w2 > 0.0:
        best = min(best, smallest(w2))
    return best


@dataclass(frozen=True)
class RiccatiSolution:
    """Solution P of (6.49) and its relative residual ‖ĀᵀP + PĀ + N P² + qI‖ / (‖Ā‖‖P‖ + q)."""

    p: np.ndarray
    residual: float


def solve_bounded_real_are(a_bar: np.ndarray, n: float, q: float,
                           tolerance: float = 1e-8) -> RiccatiSolution | None:
    """Stabilising solution P = Pᵀ > 0 of Āᵀ P + P Ā + P (N I) P + q I = 0 (6.49), from the
    stable invariant subspace [X₁; X₂] of the Hamiltonian (6.51) H = [[Ā, N I], [-q I, -Āᵀ]]
    as P = X₂ X₁⁻¹. None when Ā is not Hurwitz, H is not hyperbolic, or the result fails the
    checks (residual above ``tolerance``, P not positive definite)."""
    a_bar = np.asarray(a_bar, dtype=float)
    m = a_bar.shape[0]
    if np.linalg.eigvals(a_bar).real.max() >= 0.0:
        return None
    eye = np.eye(m)
    h = np.block([[a_bar, n * eye], [-q * eye, -a_bar.T]])
    eig = np.linalg.eigvals(h)
    if np.abs(eig.real).min() <= AXIS_TOLERANCE * np.linalg.norm(h, 1):
        return None
    _, z, dim = scipy.linalg.schur(h, output="real", sort="lhp")
    if dim != m:
        return None
    x1, x2 = z[:m, :m], z[m:, :m]
    if np.linalg.cond(x1) > 1e12:
        return None
    p = np.linalg.solve(x1.T, x2.T).T
    p = 0.5 * (p + p.T)
    res = a_bar.T @ p + p @ a_bar + n * p @ p + q * eye
    residual = float(np.linalg.norm(res, 2) / (np.linalg.norm(a_bar, 2) * np.linalg.norm(p, 2)
                                               + q))
    if residual > tolerance or np.linalg.eigvalsh(p).min() <= 0.0:
        return None
    return RiccatiSolution(p, residual)

