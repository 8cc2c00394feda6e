"""Identifiability verdicts and fit.json's shape (issue 24 item 3), from constructed
Jacobians: no simulation."""

from __future__ import annotations

import numpy as np

from webline.twin.fitting.identify import identifiability


def verdict(jac, ci95=None, low=None, high=None):
    n = jac.shape[1]
    ci95 = np.tile([0.4, 0.6], (n, 1)) if ci95 is None else ci95
    low = np.zeros(n) if low is None else low
    high = np.ones(n) if high is None else high
    cov = np.linalg.pinv(jac.T @ jac)
    d = np.sqrt(np.clip(np.diag(cov), 1e-300, None))
    return identifiability(jac, ci95, low, high, cov / np.outer(d, d),
                           [f"p{i}" for i in range(n)])


def test_independent_columns_are_identifiable():
    rng = np.random.default_rng(0)
    result = verdict(rng.normal(size=(200, 3)))
    assert result.identifiable.all()
    assert result.reasons == ("", "", "")


def test_two_parameters_acting_alike_are_named_and_the_third_is_kept():
    # viscous and Coulomb friction at one constant speed: the same column up to a factor
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(200, 1)), rng.normal(size=(200, 1))
    result = verdict(np.hstack([a, 2.0 * a + 1e-9 * b, b]))
    assert list(result.identifiable) == [False, False, True]
    assert "singular direction" in result.reasons[0]
    assert "p1" in result.reasons[0] and "p0" in result.reasons[1]


def test_a_parameter_the_data_do_not_depend_on_is_named():
    rng = np.random.default_rng(2)
    jac = np.hstack([rng.normal(size=(100, 1)), np.zeros((100, 1))])
    result = verdict(jac)
    assert list(result.identifiable) == [True, False]
    assert "do not depend on it" in result.reasons[1]


def test_an_interval_wider_than_the_bounds_is_named():
    rng = np.random.default_rng(3)
    ci95 = np.array([[0.4, 0.6], [-0.2, 1.3]])
    result = verdict(rng.normal(size=(100, 2)), ci95=ci95)
    assert list(result.identifiable) == [True, False]
    assert "wider than its bounds" in result.reasons[1]


def test_correlated_parameters_with_narrow_intervals_are_identified():
    """Two estimates correlated -0.996 (as EA and a span length through their ratio): each
    still identified where its interval is a small share of its bounds (the standard
    errors carry the correlation), each named where the interval is wide."""
    rng = np.random.default_rng(4)
    a, b = rng.normal(size=(400, 1)), rng.normal(size=(400, 1))
    jac = np.hstack([a, a + 0.09 * b])
    cov = np.linalg.pinv(jac.T @ jac)
    d = np.sqrt(np.diag(cov))
    correlation = cov / np.outer(d, d)
    assert abs(correlation[0, 1]) > 0.99
    narrow = identifiability(jac, np.tile([0.50, 0.55], (2, 1)), np.zeros(2), np.ones(2),
                             correlation, ["p0", "p1"])
    assert narrow.identifiable.all(), narrow.reasons
    wide = identifiability(jac, np.tile([0.30, 0.70], (2, 1)), np.zeros(2), np.ones(2),
                           correlation, ["p0", "p1"])
    assert not wide.identifiable.any() and "correlation -0.99" in wide.reasons[0]
