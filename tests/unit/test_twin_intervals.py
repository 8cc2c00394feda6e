"""Honest intervals and verdicts of a fit (issue 36 items 1 and 5), checked on problems
with known answers: the correlation time of an AR(1) process, the coverage of a straight
line's slope under correlated noise, one-sided intervals at a bound, and the verdict rules."""

from __future__ import annotations

import numpy as np
import pytest

from webline.twin.fitting.intervals import correlation_time, honest_covariance, intervals
from webline.twin.fitting.verdict import judge


def ar1(rng: np.random.Generator, phi: float, n: int) -> np.ndarray:
    """Unit-variance AR(1) noise x_k = φ x_k-1 + √(1-φ²) e_k."""
    e = rng.normal(0.0, np.sqrt(1.0 - phi**2), n)
    x = np.empty(n)
    x[0] = rng.normal()
    for k in range(1, n):
        x[k] = phi * x[k - 1] + e[k]
    return x


def test_correlation_time_of_ar1_is_its_theory() -> None:
    """τ = (1 + φ)/(1 - φ) = 9 for φ = 0.8 (Sokal's window, 40 000 samples: ~5 %); 1 for
    white noise."""
    rng = np.random.default_rng(0)
    assert correlation_time(ar1(rng, 0.8, 40_000)) == pytest.approx(9.0, rel=0.15)
    assert correlation_time(rng.normal(size=40_000)) == pytest.approx(1.0, abs=0.1)


def test_slope_under_correlated_noise_is_covered() -> None:
    """A straight line fitted to 2000 points of AR(1) noise (φ = 0.9, τ = 19): the
    noise-only interval treats them as independent and covers the slope in about 1 of 3
    fits (its σ is √19 too small); the batch-means interval covers at least 90 % of 200
    fits (binomial σ of a 95 % share over 200: 1.5 %)."""
    rng = np.random.default_rng(1)
    t = np.linspace(0.0, 1.0, 2000)
    design = np.column_stack([np.ones_like(t), t])
    honest_hits = noise_hits = 0
    for _ in range(200):
        y = 0.5 + 2.0 * t + ar1(rng, 0.9, len(t))
        coef = np.linalg.lstsq(design, y, rcond=None)[0]
        r = (design @ coef - y)[None, :]
        cov = honest_covariance(design, r)
        ci, _, _ = intervals(
            coef, cov.stderr, np.array([-1e9, -1e9]), np.array([1e9, 1e9]), cov.blocks - 2
        )
        honest_hits += ci[1, 0] <= 2.0 <= ci[1, 1]
        noise_hits += abs(coef[1] - 2.0) <= 1.96 * cov.stderr_noise[1]
    assert honest_hits >= 180, honest_hits
    assert noise_hits <= 100, noise_hits


def test_a_value_at_its_bound_gets_a_one_sided_interval() -> None:
    """Within 1 % of the range from a bound: [bound, value + t0.95 σ]; inside: ± t0.975 σ."""
    ci, kinds, at = intervals(
        np.array([0.05, 3.0, 9.999]), np.array([0.2, 0.2, 0.2]), np.zeros(3), np.full(3, 10.0), 1000
    )
    assert kinds == ["one-sided", "two-sided", "one-sided"] and at == ["low", "", "high"]
    assert ci[0, 0] == 0.0 and ci[0, 1] == pytest.approx(0.05 + 1.646 * 0.2, rel=1e-3)
    assert ci[1] == pytest.approx([3.0 - 1.962 * 0.2, 3.0 + 1.962 * 0.2], rel=1e-3)
    assert ci[2, 1] == 10.0


@pytest.mark.parametrize(
    ("kwargs", "status", "fragment"),
    [
        ({}, "good", None),
        ({"residual_scale": 2.2}, "poor", "residuals 2.2 x the noise"),
        ({"at_bound": [("rollers.a.inertia", "low")]}, "poor", "at its lower bound"),
        ({"converged": False}, "poor", "not converged"),
        ({"converged": False, "residual_scale": 3.0}, "failed", "not converged"),
        ({"failure": "unstable at 2.1 s"}, "failed", "simulation failed"),
        ({"lacks": ["torque[drum]: residuals not white"]}, "poor", "likely lacks something"),
    ],
)
def test_verdict_rules(kwargs, status, fragment) -> None:
    args = {
        "residual_scale": 1.0,
        "converged": True,
        "message": "",
        "failure": "",
        "at_bound": [],
        **kwargs,
    }
    verdict = judge(**args)
    assert verdict.status == status
    if fragment:
        assert any(fragment in r for r in verdict.reasons), verdict.reasons
    else:
        assert verdict.reasons == ()
