"""Singular perturbation of linear time-invariant systems (thesis Appendix A, after Kokotovic,
Khalil and O'Reilly).

The system (A-16)
    ẋ = A11 x + A12 z,        x ∈ Rⁿ (slow)
    ε ż = A21 x + A22 z,      z ∈ Rᵐ (fast), A22 nonsingular,
is brought to block-triangular ("actuator") form by η = z + L x (A-17), which gives (A-18)
    ẋ = (A11 - A12 L) x + A12 η,    ε η̇ = R(L, ε) x + (A22 + ε L A12) η,
    R(L, ε) = A21 - A22 L + ε L A11 - ε L A12 L                     (A-19).
When R(L, ε) = 0 the eigenvalues split exactly into those of the slow matrix A11 - A12 L and
those of the fast matrix (A22 + ε L A12)/ε (A-25)-(A-27). R = 0 rearranges to the fixed point
    L = A22⁻¹ A21 + ε A22⁻¹ L (A11 - A12 L),   L0 = A22⁻¹ A21        (A-24),
which contracts for ε below ε1 of (A-23); each iteration gains one power of ε: L_k - L = O(ε^(k+1)).

Approximations, with A0 = A11 - A12 A22⁻¹ A21:
* reduced (A-28): slow ≈ eig(A0) + O(ε), fast ≈ [eig(A22) + O(ε)]/ε;
* corrected (A-29, A-30): slow matrix A0 - ε A12 A22⁻² A21 A0 and fast matrix
  A22 + ε A22⁻¹ A21 A12, both with O(ε²) error (in the p = ε s scale for the fast one). The
  printed (A-30a) has A22⁻¹ where the first iterate of (A-24) (and A-22) gives A22⁻²: with the
  printed form the slow error stays O(ε) (E-A.1 in docs/errata.md).

Matrices may depend on ε: a ``SingularlyPerturbed`` holds them evaluated at its ε.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SingularlyPerturbed:
    """ẋ = A11 x + A12 z, ε ż = A21 x + A22 z (A-16), with the blocks evaluated at ``eps``."""

    a11: np.ndarray
    a12: np.ndarray
    a21: np.ndarray
    a22: np.ndarray
    eps: float

    @property
    def n(self) -> int:
        """Number of slow states."""
        return self.a11.shape[0]

    @property
    def m(self) -> int:
        """Number of fast states."""
        return self.a22.shape[0]

    def full_matrix(self) -> np.ndarray:
        """The (n+m)x(n+m) state matrix in the t scale: [[A11, A12], [A21/ε, A22/ε]]."""
        return np.block([[self.a11, self.a12], [self.a21 / self.eps, self.a22 / self.eps]])


@dataclass(frozen=True)
class Decomposition:
    """Slow and fast subsystems (A-20, A-26, A-27) for one L.

    lmat: the L used; slow_matrix: A11 - A12 L (t scale); fast_matrix: A22 + ε L A12 (p = ε s
    scale); eps: ε.
    """

    lmat: np.ndarray
    slow_matrix: np.ndarray
    fast_matrix: np.ndarray
    eps: float

    @property
    def slow_eigenvalues(self) -> np.ndarray:
        """Roots of ψs(s, ε) (A-26) [1/time]."""
        return np.linalg.eigvals(self.slow_matrix)

    @property
    def fast_eigenvalues_p(self) -> np.ndarray:
        """Roots of ψf(p, ε) (A-27) in the stretched scale p = ε s."""
        return np.linalg.eigvals(self.fast_matrix)

    @property
    def fast_eigenvalues(self) -> np.ndarray:
        """Fast eigenvalues in the t scale, s = p/ε [1/time]."""
        return self.fast_eigenvalues_p / self.eps

    @property
    def slow_poly(self) -> np.ndarray:
        """Coefficients of ψs(s, ε) (monic, highest power first)."""
        return np.poly(self.slow_matrix)

    @property
    def fast_poly(self) -> np.ndarray:
        """Coefficients of ψf(p, ε) in p (monic, highest power first)."""
        return np.poly(self.fast_matrix)


def riccati_residual(sp: SingularlyPerturbed, lmat: np.ndarray) -> np.ndarray:
    """R(L, ε) of (A-19)."""
    e = sp.eps
    return sp.a21 - sp.a22 @ lmat + e * lmat @ sp.a11 - e * lmat @ sp.a12 @ lmat


def l_iterates(sp: SingularlyPerturbed, iterations: int) -> list[np.ndarray]:
    """[L0, L1, ..., L_iterations] of the fixed-point scheme (A-24)."""
    out = [np.linalg.solve(sp.a22, sp.a21)]
    for _ in range(iterations):
        out.append(l_step(sp, out[-1]))
    return out


def solve_l(sp: SingularlyPerturbed, tol: float = 1e-13, max_iterations: int = 500) -> np.ndarray:
    """L(ε) with R(L, ε) = 0 by iterating (A-24) to convergence (relative step < ``tol``).

    Raises ``ArithmeticError`` when the iteration does not converge to a root of (A-19) (ε too
    large: see ``validity_eps``, and ``l_from_eigenvectors`` for a direct alternative).
    """
    lmat = l_iterates(sp, 0)[0]
    scale = float(np.linalg.norm(sp.a21) + np.linalg.norm(sp.a22) * np.linalg.norm(lmat))
    for _ in range(max_iterations):
        new = l_step(sp, lmat)
        if not np.all(np.isfinite(new)) or np.linalg.norm(new) > 1e6 * max(1.0, scale):
            break
        if np.linalg.norm(new - lmat) <= tol * max(1.0, float(np.linalg.norm(new))):
            return new
        lmat = new
    raise ArithmeticError(f"the L(eps) iteration (A-24) did not converge at eps = {sp.eps:g}")


def l_from_eigenvectors(sp: SingularlyPerturbed) -> np.ndarray:
    """L(ε) from the slow invariant subspace: on it η = z + L x = 0, so with the eigenvectors
    [X; Z] of the n eigenvalues of smallest modulus, L = -Z X⁻¹. Independent of (A-24) and
    valid whenever those n eigenvalues are separated from the others (no conjugate pair split).
    """
    lam, vec = np.linalg.eig(sp.full_matrix())
    order = _slow_first(lam)
    _check_split(lam[order], sp.n)
    basis = vec[:, order[: sp.n]]
    lmat = -np.linalg.solve(basis[: sp.n].T, basis[sp.n :].T).T
    return np.real_if_close(lmat, tol=1e6).real


def l_step(sp: SingularlyPerturbed, lmat: np.ndarray) -> np.ndarray:
    """One step of (A-24): A22⁻¹ A21 + ε A22⁻¹ L (A11 - A12 L)."""
    return np.linalg.solve(sp.a22, sp.a21 + sp.eps * lmat @ (sp.a11 - sp.a12 @ lmat))


def decompose(sp: SingularlyPerturbed, iterations: int | None = None) -> Decomposition:
    """Slow and fast subsystems with L from ``iterations`` steps of (A-24) (0 gives L0 = A22⁻¹ A21),
    or the converged L(ε) when ``iterations`` is None (then the split is exact)."""
    lmat = solve_l(sp) if iterations is None else l_iterates(sp, iterations)[-1]
    return Decomposition(lmat=lmat, slow_matrix=sp.a11 - sp.a12 @ lmat,
                         fast_matrix=sp.a22 + sp.eps * lmat @ sp.a12, eps=sp.eps)


def reduced_matrices(sp: SingularlyPerturbed) -> tuple[np.ndarray, np.ndarray]:
    """(A0, A22) of Theorem A.3.1 / (A-28): A0 = A11 - A12 A22⁻¹ A21."""
    return sp.a11 - sp.a12 @ np.linalg.solve(sp.a22, sp.a21), sp.a22


def corrected_matrices(sp: SingularlyPerturbed) -> tuple[np.ndarray, np.ndarray]:
    """(A0c, A22c) of (A-29)-(A-30) as derived from the first iterate L1 of (A-24):
    A0c = A0 - ε A12 A22⁻² A21 A0, A22c = A22 + ε A22⁻¹ A21 A12 (E-A.1: A22⁻², not A22⁻¹)."""
    a0, _ = reduced_matrices(sp)
    inv_a21 = np.linalg.solve(sp.a22, sp.a21)
    a0c = a0 - sp.eps * sp.a12 @ np.linalg.solve(sp.a22, inv_a21 @ a0)
    return a0c, sp.a22 + sp.eps * inv_a21 @ sp.a12


def corrected_matrices_printed(sp: SingularlyPerturbed) -> tuple[np.ndarray, np.ndarray]:
    """(A0c, A22c) exactly as printed in (A-30): A0c = A0 - ε A12 A22⁻¹ A21 A0 (O(ε) only)."""
    a0, _ = reduced_matrices(sp)
    inv_a21 = np.linalg.solve(sp.a22, sp.a21)
    return a0 - sp.eps * sp.a12 @ inv_a21 @ a0, sp.a22 + sp.eps * inv_a21 @ sp.a12


def validity_eps(sp: SingularlyPerturbed) -> float:
    """ε1 of (A-23) (spectral norms): for 0 <= ε < ε1 a solution L(ε) exists and the iteration
    (A-24) converges to it."""
    a0, _ = reduced_matrices(sp)
    inv = np.linalg.inv(sp.a22)
    n_inv, n_a0 = np.linalg.norm(inv, 2), np.linalg.norm(a0, 2)
    n_a12, n_l0 = np.linalg.norm(sp.a12, 2), np.linalg.norm(inv @ sp.a21, 2)
    return 1.0 / (n_inv * (n_a0 + n_a12 * n_l0 + 2.0 * np.sqrt(n_a0 * n_a12 * n_l0)))


def _slow_first(lam: np.ndarray) -> np.ndarray:
    return np.lexsort((lam.imag, np.abs(lam)))


def _check_split(lam_sorted: np.ndarray, n_slow: int) -> None:
    if 0 < n_slow < lam_sorted.size:
        last, first = lam_sorted[n_slow - 1], lam_sorted[n_slow]
        if abs(last.imag) > 0 and abs(first - np.conj(last)) <= 1e-9 * abs(last):
            raise ValueError("the slow/fast split would separate a complex-conjugate pair: the "
                             "system has no clear time-scale separation at this eps")


def split_eigenvalues(a: np.ndarray, n_slow: int) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues of ``a`` split into the ``n_slow`` of smallest modulus and the rest, each
    sorted by (modulus, imaginary part). Raises ``ValueError`` if that splits a conjugate pair.
    """
    lam = np.linalg.eigvals(a)
    lam = lam[_slow_first(lam)]
    _check_split(lam, n_slow)
    return lam[:n_slow], lam[n_slow:]


def eigenvalue_distance(approx: np.ndarray, exact: np.ndarray) -> float:
    """max over ``approx`` of the distance to the nearest of ``exact`` (matching sets)."""
    return float(max(np.min(np.abs(exact - value)) for value in approx))
