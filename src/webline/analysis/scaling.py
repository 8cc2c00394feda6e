"""Coordinates for the decentralized certificate: a search over diagonal state scalings.

The certificate (6.44, 6.54) is a sufficient condition stated in given coordinates: with
x̃ = D⁻¹ x (D diagonal, the *unit* of every state) the section matrices become D_i⁻¹ Ā_i D_i
and the couplings D_j⁻¹ A_ji D_i, and δs and ξ change while the eigenvalues do not. Any D
for which the condition holds proves stability (the Lyapunov function of (6.45) is then
Σ x_iᵀ D_i⁻¹ P_i D_i⁻¹ x_i). The search maximises the smallest *log margin*

    μ_i = ln δs(D_i⁻¹ Ā_i D_i) - ln(√N_i ξ_i(D))        (the certificate holds iff all μ_i > 0)

over ln D by Nelder-Mead from several starts, optionally choosing for each section the best
of several candidate closed-loop matrices (ξ depends on D only, not on the controllers, so the
choice is per section). δs of 1x1 and 2x2 blocks is taken in closed form (``distance_2x2``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from webline.analysis.stability import distance_2x2, instability_distance

#: log margin standing for "cannot certify" (a non-Hurwitz block), finite for the optimiser
FAIL = -50.0


@dataclass(frozen=True)
class Structure:
    """Block structure of an interconnected system: block ``starts`` (length sections + 1),
    the off-diagonal ``coupling`` part of its state matrix [SI] and N_i per section."""

    starts: np.ndarray
    coupling: np.ndarray
    counts: np.ndarray

    def block(self, i: int) -> slice:
        return slice(int(self.starts[i]), int(self.starts[i + 1]))


def delta(a: np.ndarray) -> float:
    """δs of a block: closed form up to 2x2, Hamiltonian bisection beyond."""
    return distance_2x2(a) if a.shape[0] <= 2 else instability_distance(a, rtol=1e-9).value


def _norm(block: np.ndarray) -> float:
    """σ_max of a small real matrix (closed form up to 2x2)."""
    if block.shape[0] == 1 or block.shape[1] == 1:
        return float(np.sqrt(np.sum(block * block)))
    if block.shape == (2, 2):
        (p, b), (c, d) = block.tolist()
        frob = p * p + b * b + c * c + d * d
        det = p * d - b * c
        return float(np.sqrt(0.5 * (frob + np.sqrt(max(frob * frob - 4 * det * det, 0.0)))))
    return float(np.linalg.norm(block, 2))


def xi(structure: Structure, units: np.ndarray) -> np.ndarray:
    """ξ_i = (Σ_{j≠i} σ_max(Ã_ji)²)^½ in the coordinates x̃ = x / units (6.44)."""
    n = len(structure.starts) - 1
    out = np.zeros(n)
    for i in range(n):
        ui = units[structure.block(i)]
        for j in range(n):
            block = structure.coupling[structure.block(j), structure.block(i)]
            if j != i and np.any(block):
                out[i] += _norm(block * (ui[None, :] / units[structure.block(j)][:, None])) ** 2
    return np.sqrt(out)


def log_margins(structure: Structure, units: np.ndarray,
                candidates: Sequence[Sequence[np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Best log margin μ_i of each section over its candidate closed-loop matrices [SI], and
    the index of the best candidate (non-Hurwitz candidates never win)."""
    x = xi(structure, units)
    best, choice = np.full(len(candidates), FAIL), np.zeros(len(candidates), dtype=int)
    for i, options in enumerate(candidates):
        u = units[structure.block(i)]
        for k, a in enumerate(options):
            if not _hurwitz(a):
                continue
            d = delta(a * (u[None, :] / u[:, None]))
            if x[i] == 0.0 or structure.counts[i] == 0:
                mu = np.inf  # nothing couples into the P_i² term: (6.54) holds trivially
            else:
                mu = np.log(d) - 0.5 * np.log(structure.counts[i]) - np.log(x[i]) if d > 0 else FAIL
            if mu > best[i]:
                best[i], choice[i] = mu, k
    return best, choice


def _hurwitz(a: np.ndarray) -> bool:
    if a.shape == (1, 1):
        return bool(a[0, 0] < 0.0)
    if a.shape == (2, 2):  # trace < 0 and determinant > 0
        return bool(a[0, 0] + a[1, 1] < 0.0 and a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0] > 0.0)
    return bool(np.linalg.eigvals(a).real.max() < 0.0)


def best_units(structure: Structure, candidates: Sequence[Sequence[np.ndarray]],
               starts: Sequence[np.ndarray], max_evaluations: int = 1500) -> np.ndarray:
    """State units (SI per coordinate unit, first state fixed to 1: only ratios matter) that
    maximise min_i μ_i, searched by Nelder-Mead from each of ``starts`` and restarted from the
    best optimum (a restart escapes most of the simplex's stalls)."""
    def objective(log_rest: np.ndarray) -> float:
        units = np.exp(np.concatenate(([0.0], log_rest)))
        return -float(np.min(log_margins(structure, units, candidates)[0]))

    def search(x0: np.ndarray, evaluations: int) -> tuple[np.ndarray, float]:
        res = scipy.optimize.minimize(objective, x0, method="Nelder-Mead",
                                      options={"maxfev": evaluations, "xatol": 1e-5,
                                               "fatol": 1e-7, "adaptive": True})
        return res.x, float(res.fun)

    found = [search(np.log(np.asarray(s, dtype=float)[1:] / s[0]), max_evaluations)
             for s in starts]
    x, _ = search(min(found, key=lambda r: r[1])[0], max_evaluations)  # restart
    return np.exp(np.concatenate(([0.0], x)))


def balanced_units(a: np.ndarray) -> np.ndarray:
    """Osborne balancing of |A| (rows and columns of equal norm): a start for the search."""
    import scipy.linalg

    _, (scale, _) = scipy.linalg.matrix_balance(np.abs(a), permute=False, separate=True)
    return np.asarray(scale, dtype=float)
