"""Honest intervals of a fit: standard errors that include what the noise alone does not
explain, and intervals that respect the bounds.

The residuals of a fit are white noise only where the model is right and the simulation
exact; a model error, a resampled log or a simulation step leaves residuals that are
correlated over many samples (a record of 160 000 correlated points is not 160 000
independent ones). The covariance here is a batch-means sandwich (a heteroscedasticity- and
autocorrelation-consistent estimate): the scores Jₜ rₜ are summed over blocks of time several
times the residuals' integrated correlation time τ (all signals of a block together, so a
model error that moves several signals at once counts once), and

    cov = A⁻¹ (Σ_b G_b G_bᵀ) A⁻¹ · m / (m - n),   A = JᵀJ,   G_b = Σ_{t ∈ b} Jₜ rₜ,

which for white residuals of unit variance is A⁻¹ again. Each standard error is at least the
noise-only one, A⁻¹, scaled by the residual scale where it exceeds 1 (the noise floor cannot
be beaten; a smaller batch-means estimate is its own scatter). The t quantile takes the
number of blocks less the parameters as its degrees of freedom: the effective sample size.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

#: blocks span this many integrated correlation times (the batch-means estimate of a
#: variance is low by about τ/B for blocks of B samples)
BLOCK_TIMES = 4.0
#: at least this many blocks (and ``BLOCKS_PER_PARAMETER`` per parameter): fewer would make
#: the covariance estimate itself too uncertain
MIN_BLOCKS = 20
BLOCKS_PER_PARAMETER = 5
#: Sokal's window: the autocorrelation is summed up to the first lag M >= C τ(M)
SOKAL_C = 5.0
#: a parameter within this share of its range from a bound is "at" it
NEAR_BOUND = 0.01


def correlation_time(series: np.ndarray) -> float:
    """Integrated autocorrelation time τ = 1 + 2 Σ ρ_k [samples] of ``series`` (NaN: not
    measured, taken as zero after the mean is removed), summed over Sokal's window; 1 for
    white noise."""
    y = np.asarray(series, dtype=float)
    ok = np.isfinite(y)
    if ok.sum() < 8:
        return 1.0
    y = np.where(ok, y - float(np.mean(y[ok])), 0.0)
    n = len(y)
    spectrum = np.fft.rfft(y, 2 * n)
    acov = np.fft.irfft(spectrum * np.conj(spectrum))[:n]
    if acov[0] <= 0:
        return 1.0
    rho = acov[1 : n // 2] / acov[0]
    taus = 1.0 + 2.0 * np.cumsum(rho)
    window = np.flatnonzero(np.arange(1, len(taus) + 1) >= SOKAL_C * taus)
    tau = float(taus[window[0]] if len(window) else taus[-1]) if len(taus) else 1.0
    return max(1.0, tau)


@dataclass(frozen=True)
class Covariance:
    """Covariance of the scaled parameters, standard errors [scaled], the block length
    [compared points], the number of blocks (the effective sample size) and the correlation
    time [compared points] the blocks were cut from (the longest record's; ``taus`` each
    record's)."""

    cov: np.ndarray
    stderr: np.ndarray
    stderr_noise: np.ndarray
    block: int
    blocks: int
    tau: float
    taus: tuple[float, ...] = ()


def honest_covariance(jac: np.ndarray, r: np.ndarray | Sequence[np.ndarray]) -> Covariance:
    """The covariance of the module docstring for the Jacobian ``jac`` (rows: the finite
    entries of ``r`` in row-major order; columns: scaled parameters) and the weighted
    residuals ``r`` (signals x compared points, NaN: not measured), or a list of them, one
    per record of a joint fit (rows in the list's order): each record is cut into blocks of
    its own correlation time, and no block spans two records (their noise is independent).
    ``block`` and ``tau`` are the longest record's."""
    records = [r] if isinstance(r, np.ndarray) else list(r)
    m, n = jac.shape
    ids_all, flats, taus, lengths = [], [], [], []
    first = 0
    for part in records:
        finite = np.isfinite(part)
        _, times = np.nonzero(finite)
        tau = max((correlation_time(s) for s in part), default=1.0)
        fewest = max(MIN_BLOCKS, BLOCKS_PER_PARAMETER * n)
        block = max(1, min(math.ceil(BLOCK_TIMES * tau), part.shape[1] // fewest or 1))
        ids = times // block
        ids_all.append(ids + first)
        first += int(ids.max()) + 1 if len(ids) else 0
        flats.append(part[finite])
        taus.append(tau)
        lengths.append(block)
    flat = np.concatenate(flats) if flats else np.empty(0)
    ids = np.concatenate(ids_all) if ids_all else np.empty(0, dtype=int)
    count = max(1, first)
    scores = np.zeros((count, n))
    np.add.at(scores, ids, jac * flat[:, None])
    inverse = np.linalg.pinv(jac.T @ jac)
    cov = inverse @ (scores.T @ scores) @ inverse * (m / max(1, m - n))
    scale = math.sqrt(float(flat @ flat) / max(1, m - n))
    noise = np.sqrt(np.clip(np.diag(inverse), 0.0, None)) * max(1.0, scale)
    sandwich = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    stderr = np.maximum(sandwich, noise)
    # the correlation of the sandwich, its diagonal raised to the chosen standard errors
    ratio = np.where(sandwich > 0, stderr / np.where(sandwich > 0, sandwich, 1.0), 1.0)
    cov = cov * np.outer(ratio, ratio)
    longest = int(np.argmax(taus)) if taus else 0
    return Covariance(cov, stderr, np.sqrt(np.clip(np.diag(inverse), 0.0, None)),
                      lengths[longest] if lengths else 1, count,
                      taus[longest] if taus else 1.0, tuple(taus))


def intervals(
    value: np.ndarray, stderr: np.ndarray, low: np.ndarray, high: np.ndarray, dof: int
) -> tuple[np.ndarray, list[str], list[str]]:
    """95 % intervals [SI] of ``value`` ± t₀.₉₇₅(dof) ``stderr``, their kind per parameter
    ("two-sided", or "one-sided" for a value at a bound: [bound, value + t₀.₉₅ stderr]
    inward) and which bound each value is at ("low", "high" or "")."""
    from scipy.stats import t as student

    two = float(student.ppf(0.975, max(1, dof)))
    one = float(student.ppf(0.95, max(1, dof)))
    out = np.column_stack([value - two * stderr, value + two * stderr])
    kinds, at = [], []
    for i in range(len(value)):
        near = NEAR_BOUND * (high[i] - low[i])
        if value[i] <= low[i] + near:
            out[i] = (low[i], value[i] + one * stderr[i])
            kinds.append("one-sided")
            at.append("low")
        elif value[i] >= high[i] - near:
            out[i] = (value[i] - one * stderr[i], high[i])
            kinds.append("one-sided")
            at.append("high")
        else:
            kinds.append("two-sided")
            at.append("")
    return out, kinds, at


#: the profile walks out from the fitted value in steps of this share of the Wald interval's
#: half width (at most ``PROFILE_MAX_STEP`` of the bounds' range), at most ``PROFILE_STEPS``
#: of them each way (then the bound is the end), and bisects the step that crosses
#: ``PROFILE_BISECTIONS`` times
PROFILE_STEP, PROFILE_MAX_STEP, PROFILE_STEPS, PROFILE_BISECTIONS = 0.5, 0.1, 12, 4
#: least-squares evaluations for the other parameters at each profile point (warm started)
PROFILE_NFEV = 12


def profile_intervals(
    residual: Callable[[np.ndarray], np.ndarray], x: np.ndarray, stderr: np.ndarray,
    stderr_noise: np.ndarray, dof: int,
) -> tuple[np.ndarray, list[str]]:
    """95 % profile-likelihood intervals of the scaled parameters ``x`` (the fit's minimum
    of ½|``residual``|², bounds [0, 1]): for each parameter the values θ at which the cost
    minimised over the others, c(θ), rises above the minimum by

        Δ* = ½ t₀.₉₇₅(dof)² (stderr / stderr_noise)²,

    the threshold at which a quadratic cost (½ (θ - θ̂)² / stderr_noise², unit-variance
    residuals) gives θ̂ ± t stderr: where the region is an ellipsoid the profile interval is
    the honest Wald interval, where it is not (a curved valley, a cost flat on one side) it
    follows the cost. The profile walks out in steps of ``PROFILE_STEP`` of the Wald half
    width (``PROFILE_MAX_STEP`` of the range at most), refitting the others (warm started,
    ``PROFILE_NFEV`` evaluations) at each step, bisects the step where √(c - c_min) crosses
    √Δ* and places the end by linear interpolation inside it (exact for a quadratic cost).
    A side that reaches its bound below the threshold ends there: "one-sided". Returns the
    intervals (n x 2, scaled) and each one's kind ("profile" or "profile, one-sided")."""
    from scipy.optimize import least_squares
    from scipy.stats import t as student

    two = float(student.ppf(0.975, max(1, dof)))
    n = len(x)
    base = residual(x)
    c_min = 0.5 * float(base @ base)
    out = np.empty((n, 2))
    kinds = []
    for i in range(n):
        others = [j for j in range(n) if j != i]

        def rise(theta: float, z: np.ndarray, i: int = i, others: list[int] = others
                 ) -> tuple[float, np.ndarray]:
            """(√(c(θ) - c_min), the others' values there), refitted from ``z``."""
            def at(zz: np.ndarray) -> np.ndarray:
                full = np.empty(n)
                full[i], full[others] = theta, zz
                return residual(full)

            if others:
                z = least_squares(at, z, bounds=(0.0, 1.0), method="trf",
                                  max_nfev=PROFILE_NFEV).x
            r = at(z)
            return math.sqrt(max(0.0, 0.5 * float(r @ r) - c_min)), z

        ratio = stderr[i] / stderr_noise[i] if stderr_noise[i] > 0 else 1.0
        target = math.sqrt(0.5) * two * ratio  # √Δ*
        step = min(PROFILE_STEP * two * stderr[i], PROFILE_MAX_STEP)
        open_side = False
        for side, sign in ((0, -1.0), (1, 1.0)):
            inner, rise_in, z = float(x[i]), 0.0, x[others].copy()
            end, reached = (0.0 if sign < 0 else 1.0), False
            for k in range(1, PROFILE_STEPS + 1):
                theta = min(max(float(x[i]) + sign * k * step, 0.0), 1.0)
                up, z_out = rise(theta, z)
                if up >= target:
                    outer, rise_out = theta, up
                    for _ in range(PROFILE_BISECTIONS):  # the crossing, within the step
                        mid = 0.5 * (inner + outer)
                        up, z_mid = rise(mid, z)
                        if up >= target:
                            outer, rise_out = mid, up
                        else:
                            inner, rise_in, z = mid, up, z_mid
                    share = (target - rise_in) / (rise_out - rise_in)
                    end, reached = inner + share * (outer - inner), True
                    break
                inner, rise_in, z = theta, up, z_out
                if theta in (0.0, 1.0):
                    break
            out[i, side] = end
            open_side = open_side or not reached
        kinds.append("profile, one-sided" if open_side else "profile")
    return out, kinds
