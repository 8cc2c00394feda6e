"""Inverse LQ (``webline.control.inverse_lq``): known answers, Kalman's frequency-domain
condition as an independent check, and the thesis's gains (6.55)-(6.57)."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.control.gains import THESIS_GAINS, gains_from_closed
from webline.control.inverse_lq import inverse_lq, lq_design, return_difference
from webline.control.lumped import without_idlers
from webline.control.sections import section_models
from webline.model.operating_point import operating_point

OMEGA = np.logspace(-3, 6, 6001)  #: [rad/s] grid for the return difference


@pytest.fixture(scope="module")
def models():
    line = without_idlers(webline.load_line("hswl"))
    return section_models(line, operating_point(line))


def _check_recovered(a, b, k, result):
    """The returned weights are a certificate: P ≻ 0, Q ⪰ 0, and LQ with them gives k."""
    assert result.feasible and result.margin >= 0.0
    assert np.linalg.eigvalsh(result.p)[0] > 0.0
    assert np.linalg.eigvalsh(result.q)[0] > -1e-9 * np.abs(result.q).max()
    np.testing.assert_allclose(lq_design(a, b, result.q, result.r).ravel(), k, rtol=1e-6)


@pytest.mark.parametrize("section", range(4))
def test_lqr_gain_is_recovered_as_optimal(models, section):
    """K = lqr(A, b, Q, R) for random weights on each HSWL section (SI): inverse LQ finds
    weights (not necessarily the same ones: they are not unique) for which LQ gives K again."""
    m = models[section]
    rng = np.random.default_rng(section)
    n = m.a.shape[0]
    g = rng.normal(size=(n, n))
    q = g @ g.T + 1e-3 * np.eye(n)
    r = np.array([[10.0 ** rng.uniform(-6, -2)]])
    k = lq_design(m.a, m.b, q, r).ravel()
    _check_recovered(m.a, m.b, k, inverse_lq(m.a, m.b, k))


def test_agrees_with_kalmans_return_difference_condition(models):
    """A stabilising k of a single-input section is LQ-optimal iff |1 + kᵀ(jωI - A)⁻¹b| ≥ 1
    for all ω (Kalman 1964): on 30 random stabilising gains of the rewind section (LQ gains
    with each entry scaled by 0.3 ... 3, so that both verdicts occur), the
    verdict of the (P, Q) search equals that of the frequency sweep wherever the sweep's
    minimum is not just below 1 (1 - 1e-6 ... 0.99 are skipped; optimal gains approach 1 from
    above as ω -> ∞, so the sweep's minimum sits at 1 to rounding)."""
    m = models[3]
    rng = np.random.default_rng(1)
    compared = agreed = 0
    kinds = set()
    while compared < 30:
        q = np.diag(10.0 ** rng.uniform(-2, 4, size=2))
        k = lq_design(m.a, m.b, q, np.array([[1e-4]])).ravel() * rng.uniform(0.3, 3.0, size=2)
        if np.linalg.eigvals(m.a - m.b @ k[None, :]).real.max() >= 0:
            continue
        rd = return_difference(m.a, m.b, k, OMEGA).min()
        if 1.0 - 0.01 < rd < 1.0 - 1e-6:  # |1 + L| -> 1 as ω -> ∞: optimal gains touch 1
            continue
        compared += 1
        kinds.add(rd > 1.0 - 1e-6)
        agreed += inverse_lq(m.a, m.b, k).feasible == (rd > 1.0 - 1e-6)
    assert agreed == compared
    assert kinds == {True, False}  # both verdicts were exercised


def test_thesis_unwind_gain_of_6_55(models):
    """(6.55)-(6.57) in the thesis's units (lbf, ft/s; 500 ft/min, L1 = 20 ft, AE = 2000 lbf,
    t0 = 0): with Ã0's (1,2) entry -(AE - t0)/L1 (E-6.11) the gain (−C01, C02) = (−120, 200)
    that gives the printed second row of Ā0 is LQ-optimal for (Ã0, B̃0); with the printed
    +(AE - t0)/L1 the same closed loop is unstable (det < 0), and no weights exist."""
    v, length, ae = 500.0 / 60.0, 20.0, 2000.0
    b = np.array([0.0, 1.0])
    k = np.array([-THESIS_GAINS.c01, THESIS_GAINS.c02])
    corrected = np.array([[-v / length, -ae / length], [0.0, 0.0]])
    _check_recovered(corrected, b, k, inverse_lq(corrected, b, k))
    printed = np.array([[-v / length, ae / length], [0.0, 0.0]])
    assert np.linalg.eigvals(printed - np.outer(b, k)).real.max() > 0
    assert not inverse_lq(printed, b, k).feasible


def test_thesis_gains_on_webline_sections(models):
    """The thesis's closed loops as SI gains on webline's idler-free HSWL (E-6.7): the unwind
    and master gains are LQ-optimal, the process and rewind gains are not for any weights —
    their return difference dips below 1 (min 0.994 and 0.70), and the search agrees."""
    gains = gains_from_closed(models, THESIS_GAINS.closed_loops(models))
    expected = [True, True, False, False]
    for m, k, optimal in zip(models, gains, expected, strict=True):
        k = k[-m.a.shape[0]:]
        rd = return_difference(m.a, m.b, k, OMEGA).min()
        result = inverse_lq(m.a, m.b, k)
        assert result.feasible == optimal == (rd >= 1.0 - 1e-9), (m.states, rd, result.margin)
        if optimal:
            _check_recovered(m.a, m.b, k, result)
