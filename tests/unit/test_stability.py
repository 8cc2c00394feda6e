"""Distance to instability (thesis 6.14-6.17) and the Riccati equation (6.49): the Hamiltonian
bisection against independent computations."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize

from webline.analysis import distance_to_instability, frequency_sweep_distance
from webline.analysis.stability import (
    distance_2x2,
    imaginary_frequencies,
    instability_distance,
    sigma_min,
    solve_bounded_real_are,
)


def random_unitary(n: int, rng: np.random.Generator) -> np.ndarray:
    z = rng.normal(size=(n, n)) + 1j * rng.normal(size=(n, n))
    q, r = np.linalg.qr(z)
    return q * (np.diag(r) / np.abs(np.diag(r)))


def swept_distance(a: np.ndarray) -> float:
    """min_ω σ_min(A - jωI) (6.15) by a dense sweep refined by a local optimiser at the best
    few grid points: independent of the Hamiltonian."""
    scale = float(np.linalg.norm(a, 2))
    # dense near 0 and out to beyond the spectrum: sinh spacing, 40 001 points
    grid = np.sinh(np.linspace(-1, 1, 40_001) * np.arcsinh(4 * scale / 1e-6)) * 1e-6
    values = np.array([sigma_min(a, w) for w in grid])
    best = np.inf
    interior = np.flatnonzero((values[1:-1] <= values[:-2]) & (values[1:-1] <= values[2:])) + 1
    for k in interior[np.argsort(values[interior])][:5]:
        res = scipy.optimize.minimize_scalar(lambda w: sigma_min(a, w),
                                             bounds=(grid[k - 1], grid[k + 1]),
                                             method="bounded", options={"xatol": 1e-15})
        best = min(best, float(res.fun), float(values[k]))
    return best


@pytest.mark.parametrize("n,seed", [(1, 0), (2, 1), (3, 2), (5, 3), (8, 4)])
def test_normal_matrix_distance_is_smallest_real_part(n, seed):
    """For normal A = Q diag(λ) Qᴴ, σ_min(A - jωI) = min_k |λ_k - jω|, so δs = min |Re λ|.
    The bisection stops at 1e-12 relative and the SVD is backward stable: 1e-10 is ample."""
    rng = np.random.default_rng(seed)
    lam = -rng.uniform(0.05, 5.0, n) + 1j * rng.normal(scale=3.0, size=n)
    q = random_unitary(n, rng)
    a = q @ np.diag(lam) @ q.conj().T
    assert distance_to_instability(a) == pytest.approx(np.abs(lam.real).min(), rel=1e-10)


NON_NORMAL = {
    "jordan-like": np.array([[-1.0, 1e3, 0.0], [0.0, -2.0, 1e3], [0.0, 0.0, -0.5]]),
    "oscillatory, large coupling": np.array([[-0.4, -1450.0], [8.2, -200.0]]),
    "complex upper triangular": np.triu(np.full((4, 4), 50.0 + 20.0j), 1)
    + np.diag([-1 + 3j, -0.5 - 7j, -2.0 + 0j, -0.3 + 1j]),
    "web section (SI)": np.array([[-0.25, 878.1], [-4.24, -137.4]]),
}


@pytest.mark.parametrize("name", list(NON_NORMAL))
def test_non_normal_distance_matches_refined_sweep(name):
    """Strongly non-normal matrices (δs far below min |Re λ|): the bisection agrees with a
    dense frequency sweep refined by a local optimiser to 1e-8 relative (σ_min is smooth at
    its minimum, so both converge to machine precision in value)."""
    a = NON_NORMAL[name]
    value = distance_to_instability(a)
    assert value < 0.5 * np.abs(np.linalg.eigvals(a).real).min()  # truly non-normal
    assert value == pytest.approx(swept_distance(a), rel=1e-8)


def test_sweep_is_an_upper_bound_and_hamiltonian_brackets_it():
    """Any sweep bounds δs from above; H_ρ (6.16) has no imaginary eigenvalue below δs and
    has one above it (Lemma 6.2.1)."""
    a = NON_NORMAL["oscillatory, large coupling"]
    found = instability_distance(a)
    assert found.lower <= found.value
    assert frequency_sweep_distance(a, np.linspace(-200, 200, 41)) >= found.value
    assert frequency_sweep_distance(a, [found.omega]) == pytest.approx(found.value, rel=1e-12)
    assert len(imaginary_frequencies(a, 0.9 * found.value, tolerance=1e-12)) == 0
    crossings = imaginary_frequencies(a, 1.1 * found.value, tolerance=1e-12)
    assert len(crossings) >= 2
    assert all(sigma_min(a, w) == pytest.approx(1.1 * found.value, rel=1e-8) or
               sigma_min(a, w) < 1.1 * found.value for w in crossings)


def test_eigenvalue_on_axis_gives_zero():
    assert distance_to_instability(np.array([[0.0, 1.0], [-1.0, 0.0]])) == 0.0


def test_closed_form_2x2_matches_bisection():
    """The closed form of ``distance_2x2`` (stationary point of σ_min² in ω²) against the
    bisection on 300 random real 2x2 matrices spanning 6 decades, stable or not."""
    rng = np.random.default_rng(5)
    for k in range(300):
        a = rng.normal(size=(2, 2)) * np.exp(rng.normal(size=(2, 2)) * 3)
        if k % 4 == 0:
            a[0, 1] = a[1, 0]  # symmetric: normal
        assert distance_2x2(a) == pytest.approx(distance_to_instability(a), rel=1e-8)


def test_riccati_exists_exactly_below_the_distance():
    """ĀᵀP + PĀ + N P² + qI = 0 (6.49) has its stabilising P > 0 iff N q < δs(Ā)²
    (bounded-real lemma; (6.54) with q = ξ² + ε). Residual at rounding level."""
    a_bar = NON_NORMAL["web section (SI)"]
    delta, n = distance_to_instability(a_bar), 3
    q_max = delta**2 / n
    sol = solve_bounded_real_are(a_bar, n, 0.99 * q_max)
    assert sol is not None
    assert sol.residual < 1e-10
    assert np.linalg.eigvalsh(sol.p).min() > 0
    assert np.linalg.eigvals(a_bar + n * sol.p).real.max() < 0  # the stabilising solution
    assert solve_bounded_real_are(a_bar, n, 1.01 * q_max) is None


def test_riccati_positive_solution_is_not_unique():
    """Lemma 6.2.2 claims a unique P > 0; the scalar 2aP + rP² + q = 0 with a = -1, r = 1,
    q = 0.5 has two positive roots 1 ± 1/√2 (E-6.10). The solver returns the stabilising
    (smaller) one, a + rP < 0."""
    sol = solve_bounded_real_are(np.array([[-1.0]]), 1.0, 0.5)
    assert sol is not None
    assert sol.p[0, 0] == pytest.approx(1 - np.sqrt(0.5), rel=1e-12)
    for root in (1 - np.sqrt(0.5), 1 + np.sqrt(0.5)):
        assert root > 0 and -2 * root + root**2 + 0.5 == pytest.approx(0.0, abs=1e-14)


def test_unstable_matrix_has_positive_distance_but_no_riccati():
    """δs measures the distance to the imaginary axis from either side, so (6.44) alone
    does not make Ā Hurwitz (E-6.9); the ARE has no positive definite solution then."""
    a = np.array([[1.0]])
    assert distance_to_instability(a) == pytest.approx(1.0)
    assert solve_bounded_real_are(a, 1.0, 0.1) is None
