"""The pieces of a fit over several records (issue 36 item 2) that need no simulation: labels,
the scenario rule, the blocks of the honest covariance per record, the per-record verdict."""

from __future__ import annotations

import numpy as np
import pytest

from webline.errors import ArgumentError
from webline.twin.fitting.intervals import honest_covariance
from webline.twin.fitting.records import record_labels, scenario_list
from webline.twin.fitting.verdict import judge


def test_labels_are_file_names_made_unique():
    assert record_labels(["a/ramps.csv", "b/step.csv"]) == ["ramps.csv", "step.csv"]
    assert record_labels(["a/log.csv", "b/log.csv", "c.csv"]) == ["log.csv#1", "log.csv#2",
                                                                   "c.csv"]


def test_one_scenario_for_all_or_one_per_record():
    assert scenario_list(None, 2) == [None, None]
    assert scenario_list("startup", 3) == ["startup"] * 3
    assert scenario_list(["startup"], 2) == ["startup", "startup"]
    assert scenario_list(["a", None], 2) == ["a", None]
    with pytest.raises(ArgumentError, match="--scenario: 3 scenarios for 2 records"):
        scenario_list(["a", "b", "c"], 2, "--scenario")


def _records(rng, rho, sizes):
    """AR(1) residual records (one signal each) of unit marginal variance and a shared
    Jacobian column per record (a constant: an offset)."""
    out = []
    for size in sizes:
        e = rng.normal(size=size) * np.sqrt(1 - rho**2)
        r = np.empty(size)
        r[0] = rng.normal()
        for t in range(1, size):
            r[t] = rho * r[t - 1] + e[t]
        out.append(r[None, :])
    return out


def test_one_record_in_a_list_is_the_record_itself():
    rng = np.random.default_rng(5)
    [r] = _records(rng, 0.5, [4000])
    jac = np.ones((4000, 1))
    alone, listed = honest_covariance(jac, r), honest_covariance(jac, [r])
    assert listed.stderr == pytest.approx(alone.stderr, rel=1e-12)
    assert (listed.blocks, listed.block, listed.taus) == (alone.blocks, alone.block,
                                                          (alone.tau,))


def test_blocks_of_each_record_follow_its_own_correlation_time():
    """A white record and a strongly correlated one (AR(1), ρ = 0.9: τ = 19 samples): the
    correlated one is cut into ~4 τ blocks, the white one into single samples' blocks, and
    the standard error of their common offset is that of the least-squares estimate, the
    mean over both records' points: var = (n_w + n_c τ) / (n_w + n_c)² (each correlated
    point's variance counts τ times; within the batch-means scatter of ±20 %)."""
    rng = np.random.default_rng(6)
    white = rng.normal(size=(1, 2000))
    [correlated] = _records(rng, 0.9, [20000])
    jac = np.ones((22000, 1))
    cov = honest_covariance(jac, [white, correlated])
    assert cov.taus[0] == pytest.approx(1.0, abs=0.2)
    assert cov.taus[1] == pytest.approx(19.0, rel=0.3)
    # white: blocks of 4-5 samples (~450); correlated: of ~76 (~260); one block length for
    # both (the longest record's) would leave ~290 blocks, the effective points too few
    assert 600 < cov.blocks < 800
    expected = np.sqrt(2000 + 20000 * 19.0) / 22000
    assert cov.stderr[0] == pytest.approx(expected, rel=0.2)
    # the noise-only error sees 22 000 independent points: 4 x too small here
    assert cov.stderr_noise[0] < 0.3 * expected


def test_a_record_above_the_noise_makes_a_joint_fit_poor():
    common = dict(converged=True, message="", failure="", at_bound=[])
    joint = judge(residual_scale=1.2, records=[("ramps.csv", 1.0), ("step.csv", 2.1)],
                  **common)
    assert joint.status == "poor"
    assert any(r.startswith("step.csv: residuals 2.1 x the noise") for r in joint.reasons)
    assert not any("ramps.csv" in r for r in joint.reasons)
    # one record: its scale is the fit's, said once
    alone = judge(residual_scale=1.2, records=[("step.csv", 1.2)], **common)
    assert alone.status == "good" and alone.reasons == ()
