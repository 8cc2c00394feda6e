"""Inverse LQ for single-input sections (thesis 6.55-6.57) and LQ design from user weights.

For a section (A, b) and a gain k (u = -kᵀx), k is LQ-optimal for weights (Q, R) when the
Riccati solution P satisfies bᵀP = R kᵀ and Q = -(AᵀP + P A) + R k kᵀ (the ARE rewritten with
R⁻¹bᵀP = kᵀ). Both are linear in (P, R) and homogeneous, so R = 1 loses nothing: P ranges over
the affine family of symmetric matrices with P b = k, of dimension n(n-1)/2 (0 for the master's
scalar section, 1 for a tension-speed section). The weights exist iff some member has P ≻ 0
and Q ⪰ 0. f = min(λ_min(P), λ_min(Q)) is concave on the family (λ_min of a matrix affine in
the parameters is concave), so its maximum, found by a scalar search (one parameter) or a
simplex search, is global: max f ≥ 0 gives the weights, max f < 0 proves that none exist
(every member has an indefinite P or Q). Kalman's return-difference condition
|1 + kᵀ(jωI - A)⁻¹b| ≥ 1 for all ω is the same fact in the frequency domain (a test checks
both agree).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.optimize


@dataclass(frozen=True)
class InverseLQ:
    """Weights Q (n x n), R (1 x 1) and the Riccati solution P for which the gain is LQ
    optimal, or ``feasible`` False; ``margin`` = max over the family of min(λ_min P, λ_min Q)
    (≥ 0 iff feasible, in the units of P with R = 1)."""

    feasible: bool
    q: np.ndarray
    r: np.ndarray
    p: np.ndarray
    margin: float


def lq_design(a: np.ndarray, b: np.ndarray, q: np.ndarray, r: np.ndarray | float) -> np.ndarray:
    """LQ gain K (u = -K x) of ``a``, ``b`` for user weights ``q`` ⪰ 0, ``r`` ≻ 0 (scipy's ARE
    solver); shapes (m, n). Units: those of the model's states and inputs."""
    b = np.atleast_2d(np.asarray(b, dtype=float).reshape(a.shape[0], -1))
    r = np.atleast_2d(np.asarray(r, dtype=float))
    p = scipy.linalg.solve_continuous_are(a, b, q, r)
    return np.linalg.solve(r, b.T @ p)


def inverse_lq(a: np.ndarray, b: np.ndarray, k: np.ndarray, tol: float = 1e-9) -> InverseLQ:
    """Weights for which the gain ``k`` (n) of the single-input section ``a`` (n x n), ``b``
    (n) is LQ optimal, or a proof that none exist (module docstring). ``tol``: relative
    tolerance on the margin (scaled by ‖k‖ ‖A‖-size terms)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float).ravel()
    k = np.asarray(k, dtype=float).ravel()
    n = a.shape[0]
    p0, basis = _family(b, k, n)

    def matrices(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        p = p0 + sum((ti * e for ti, e in zip(t, basis, strict=True)), np.zeros((n, n)))
        q = -(a.T @ p + p @ a) + np.outer(k, k)
        return p, 0.5 * (q + q.T)

    def f(t: np.ndarray) -> float:
        p, q = matrices(t)
        return float(min(np.linalg.eigvalsh(p)[0], np.linalg.eigvalsh(q)[0]))

    if not basis:
        best = np.zeros(0)
    elif len(basis) == 1:
        scale = float(np.abs(p0).max()) or 1.0
        res = scipy.optimize.minimize_scalar(lambda s: -f(np.array([s * scale])))
        best = np.array([res.x * scale])
    else:
        res = scipy.optimize.minimize(lambda t: -f(t), np.zeros(len(basis)), method="Nelder-Mead",
                                      options={"xatol": 1e-12, "fatol": 1e-14, "maxiter": 20000})
        best = res.x
    p, q = matrices(best)
    margin = f(best)
    size = float(np.abs(q).max() + np.abs(p).max()) or 1.0
    feasible = margin >= -tol * size
    return InverseLQ(feasible, q, np.ones((1, 1)), p, margin)


def return_difference(a: np.ndarray, b: np.ndarray, k: np.ndarray,
                      omega: np.ndarray) -> np.ndarray:
    """|1 + kᵀ(jωI - A)⁻¹b| at ``omega`` [rad/s] (Kalman: ≥ 1 everywhere for an LQ gain)."""
    n = a.shape[0]
    b = np.asarray(b, dtype=float).ravel()
    return np.array([abs(1.0 + k @ np.linalg.solve(1j * w * np.eye(n) - a, b)) for w in omega])


def _family(b: np.ndarray, k: np.ndarray, n: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """A symmetric P0 with P0 b = k and a basis of the symmetric matrices N with N b = 0."""
    pairs = [(i, j) for i in range(n) for j in range(i, n)]

    def sym(v: np.ndarray) -> np.ndarray:
        m = np.zeros((n, n))
        for (i, j), x in zip(pairs, v, strict=True):
            m[i, j] = m[j, i] = x
        return m

    # the linear map v -> sym(v) b as a matrix
    lin = np.column_stack([sym(e) @ b for e in np.eye(len(pairs))])
    v0, *_ = np.linalg.lstsq(lin, k, rcond=None)
    if not np.allclose(lin @ v0, k, rtol=1e-10, atol=1e-12 * np.abs(k).max()):
        raise ValueError("no symmetric P with P b = k (b is zero?)")
    null = scipy.linalg.null_space(lin)
    return sym(v0), [sym(v) for v in null.T]
