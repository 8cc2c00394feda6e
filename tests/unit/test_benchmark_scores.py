"""The benchmark's metrics on synthetic traces against hand numbers, its ranking rule on
hand-made outcomes, and the standard set's version and hash (docs/benchmark.md)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from webline.sim.results.metrics import SETTLE_BAND
from webline.studies.benchmark.records import CaseRun, case_ranks, ranking_table
from webline.studies.benchmark.scores import (
    METRICS,
    effort_scores,
    robustness_scores,
    speed_scores,
    tension_scores,
)
from webline.studies.benchmark.standard_set import (
    BENCHMARK_VERSION,
    CASES,
    Case,
    cases,
    set_hash,
)

DT = 1e-3  # [s] a controller tick, as the built-in lines record


def test_tension_iae_and_peak_of_known_errors() -> None:
    """A ramp error a·t (which the trapezoid rule integrates exactly): IAE = a T²/2; a
    second span's sinusoid A sin(2π f t) over whole periods: IAE = 2 A T / π, to the
    trapezoid rule's error bound T dt² max|e''| / 12 (|sin| is smooth between its zeros,
    which lie on the grid); the span without a
    loadcell (reference NaN) is left out; peaks are the largest |error|."""
    time = np.arange(0.0, 4.0 + DT / 2, DT)
    ref = np.column_stack([np.full_like(time, 100.0), np.full_like(time, 200.0),
                           np.full_like(time, np.nan)])
    a, amp = 0.5, 3.0
    tension = ref.copy()
    tension[:, 0] += a * time
    tension[:, 1] -= amp * np.sin(2 * np.pi * time)
    tension[:, 2] = 1e6  # no loadcell: must not count
    got = tension_scores(time, tension, ref)
    ramp, sine = a * 4.0**2 / 2, 2 * amp * 4.0 / np.pi
    bound = 4.0 * DT**2 * amp * (2 * np.pi) ** 2 / 12  # [N·s], the trapezoid rule's
    assert abs(got["tension_iae"] - (ramp + sine)) <= bound
    assert abs(got["tension_iae_rel"] - 100 * (ramp / 100 + sine / 200)) <= 100 * bound / 200
    # the peak: the sine's A = 3 N (t = 0.25 s is a record); in % the ramp's 2 N of 100 N
    assert got["tension_peak"] == pytest.approx(amp, rel=1e-12)
    assert got["tension_peak_pct"] == pytest.approx(100 * a * 4.0 / 100, rel=1e-12)


def test_settling_of_a_first_order_step_is_the_analytic_time() -> None:
    """T = T_ref + ΔT e^{-(t - t0)/τ} after a step at t0 leaves the 2 % band at
    t0 + τ ln(ΔT / (0.02 T_ref)); the metric is the last sample outside, so it lies within
    one record (dt) before the analytic time."""
    t0, tau, tref, step = 2.0, 0.3, 100.0, 25.0
    time = np.arange(0.0, 6.0 + DT / 2, DT)
    tension = np.where(time >= t0, tref + step * np.exp(-(time - t0) / tau), tref)
    got = tension_scores(time, tension[:, None], np.full((len(time), 1), tref), onset=t0)
    analytic = tau * math.log(step / (SETTLE_BAND * tref))
    assert analytic - DT <= got["settling_time"] <= analytic


def test_settling_is_zero_inside_and_inf_when_never_back() -> None:
    time = np.arange(0.0, 1.0 + DT / 2, DT)
    ref = np.full((len(time), 1), 100.0)
    assert tension_scores(time, ref + 1.0, ref)["settling_time"] == 0.0  # 1 % < 2 %
    assert tension_scores(time, ref + 5.0, ref)["settling_time"] == math.inf
    # an excursion before the onset does not count
    early = ref + np.where(time < 0.5, 10.0, 0.0)[:, None]
    assert tension_scores(time, early, ref, onset=0.5)["settling_time"] == 0.0


def test_energy_of_constant_torque_at_constant_speed() -> None:
    """Two drives, τ = 10 and -4 N·m at 50 and 30 rad/s for 4 s: ∫|τ ω| dt = (500 + 120)
    x 4 = 2480 J (a constant integrates exactly); no torque changes: torque RMS 0."""
    time = np.arange(0.0, 4.0 + DT / 2, DT)
    torque = np.column_stack([np.full_like(time, 10.0), np.full_like(time, -4.0)])
    speed = np.column_stack([np.full_like(time, 50.0), np.full_like(time, 30.0)])
    got = effort_scores(time, torque, speed)
    assert got["energy"] == pytest.approx(2480.0, rel=1e-12)
    assert got["torque_rms"] == 0.0


def test_torque_rms_of_a_sinusoidal_deviation() -> None:
    """One drive τ = τ0 + B sin(2π t) over whole periods, one held: the RMS deviation over
    both drives is √(B²/2 / 2) (sampled at 1 kHz over 2 periods the mean of sin² is 1/2 to
    round-off)."""
    time = np.arange(0.0, 2.0, DT)
    torque = np.column_stack([5.0 + 2.0 * np.sin(2 * np.pi * time), np.full_like(time, 7.0)])
    got = effort_scores(time, torque, np.ones_like(torque))
    assert got["torque_rms"] == pytest.approx(math.sqrt(2.0**2 / 2 / 2), rel=1e-9)


def test_speed_iae() -> None:
    """|v - v_ref| = 0.01 m/s for 3 s: 0.03 m."""
    time = np.arange(0.0, 3.0 + DT / 2, DT)
    got = speed_scores(time, np.full_like(time, 2.51), np.full_like(time, 2.5))
    assert got["speed_iae"] == pytest.approx(0.03, rel=1e-9)


def test_robustness_over_samples() -> None:
    samples = [{"tension_iae_rel": 1.0, "tension_peak_pct": 5.0}, None,
               {"tension_iae_rel": 3.0, "tension_peak_pct": 4.0}]
    got = robustness_scores(samples)  # type: ignore[arg-type]
    assert got == {"tension_iae_rel_mean": 2.0, "tension_iae_rel_worst": 3.0,
                   "tension_iae_rel_spread": pytest.approx(math.sqrt(2.0)),
                   "tension_peak_pct_worst": 5.0, "failures": 1.0}


def test_every_metric_has_a_unit_and_a_definition() -> None:
    for metric in METRICS.values():
        assert metric.unit and len(metric.definition) > 20


def run(contender: str, status: str = "ok", **scores: float) -> CaseRun:
    return CaseRun("c", contender, status, "", dict(scores), 0.0)


def test_ranking_rule() -> None:
    """Per metric: ties (to 9 digits) share the mean place, a failed run takes the last
    place, an n/a contender is left out of the case; the mean rank orders the table."""
    case = Case("c", "hswl", "", 1.0)
    base = {m: 1.0 for m in ("tension_iae_rel", "tension_peak_pct", "settling_time",
                             "speed_iae", "torque_rms", "energy")}
    runs = [run("a", **base), run("b", **{**base, "energy": 1.0 + 1e-13}),
            run("c", **{**base, "energy": 0.5}), run("d", "failed"), run("e", "n/a")]
    ranks = case_ranks(runs, [case])
    energy = dict(ranks[ranks.metric == "energy"][["contender", "rank"]].values)
    assert energy == {"c": 1.0, "a": 2.5, "b": 2.5, "d": 4.0}
    table = ranking_table(runs, [case], "abcde")
    assert list(table.contender) == ["c", "a", "b", "d", "e"]
    assert table.set_index("contender").loc["e", "n/a"] == 1
    assert table.set_index("contender").loc["d", "failed"] == 1
    assert math.isnan(table.set_index("contender").loc["e", "mean_rank"])


def test_set_hash_follows_the_cases() -> None:
    """The hash is of the cases themselves: the same set gives the same hash, any change
    another; the quick subset is a different set (its own hash)."""
    assert BENCHMARK_VERSION == "1"
    assert set_hash(CASES) == set_hash(cases())
    changed = (dataclasses.replace(CASES[0], duration=CASES[0].duration + 1), *CASES[1:])
    assert set_hash(changed) != set_hash(CASES)
    assert set_hash(cases(quick=True)) != set_hash(CASES)
    assert len({c.name for c in CASES}) == len(CASES)
    assert sum(c.monte_carlo for c in CASES) == 1


#: the hash of each published version of the standard set: a change to ``CASES`` changes the
#: hash, and then ``BENCHMARK_VERSION`` must be bumped and the new pair added here
PUBLISHED = {"1": "8e4cb92a9c4c"}


def test_the_set_matches_its_published_version() -> None:
    assert PUBLISHED.get(BENCHMARK_VERSION) == set_hash(CASES), (
        "the standard set changed: bump BENCHMARK_VERSION (docs/benchmark.md, version "
        "policy) and record its hash in PUBLISHED")
