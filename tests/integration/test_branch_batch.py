"""Batched cases of a branched line (issue 33 item 3, ``sim.sweeps.branch_batch``): many cases
of one structure run in one compiled call per range of cases, on several threads, and each
is the same case run alone (``simulate_branches``) to round-off: the records and, through the
study, every metric and verdict. Checked on the laminator (three webs into one at a nip) and
the slitter (one web cut into three lanes), in a scenario that moves them."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.model.web_graph import load_branched
from webline.sim.branches.run import simulate_branches
from webline.sim.sweeps.branch_batch import batch_results, build_branch_cases, run_branch_block
from webline.sim.sweeps.branch_study import (
    case_metrics,
    derive_branched,
    run_branch_cases,
    web_status,
)

#: the relative difference a batched case may show from its run alone: the same compiled
#: arithmetic on the same inputs (integer tables frozen alike), so only round-off of a
#: differently inlined loop could separate them (measured: 0, bit for bit)
RTOL = 1e-12

CASES = {
    # the film's EA 103.5 kN lowered and raised; the upset's 30 N step at 2 s moves every zone
    "laminator": ("layer-upset", [{"webs.film.web.ea": v} for v in
                                  ("80 kN", "103.5 kN", "130 kN", "160 kN")]),
    # the web's EA 281.25 kN and a lane span's length, zipped: the lanes' start-up
    "slitter": ("start-up", [{"web.ea": ea, "webs.lane_1.spans.lane_1_span.length": le}
                             for ea, le in (("200 kN", "1.5 m"), ("281.25 kN", "2 m"),
                                            ("350 kN", "2.5 m"))]),
}
SECONDS = 3.0


def _alone(name: str, scenario: str, changes: dict[str, object]):
    line = derive_branched(load_branched(name).with_scenario(scenario), changes)
    return simulate_branches(line, SECONDS, raise_on_failure=False)


@pytest.mark.parametrize("name", list(CASES))
def test_batched_records_equal_each_case_run_alone(name: str) -> None:
    scenario, changes = CASES[name]
    base = load_branched(name).with_scenario(scenario)
    built = build_branch_cases(base, changes, SECONDS, derive_branched)
    assert not built.failed
    outputs = run_branch_block(built, workers=2)
    assert [idx for idx, _ in outputs] == [list(range(len(changes)))]  # one batch: one call
    for j, result in batch_results(built, outputs, SECONDS).items():
        alone = _alone(name, scenario, changes[j])
        assert result.failure == alone.failure is None
        assert result.rec.shape == alone.rec.shape
        scale = np.max(np.abs(alone.rec), axis=0)  # per column: states span decades
        assert np.all(np.abs(result.rec - alone.rec) <= RTOL * scale)
        assert result.settings == alone.settings


@pytest.mark.parametrize("name", list(CASES))
def test_study_rows_are_the_runs_alone(name: str) -> None:
    scenario, changes = CASES[name]
    ds = webline.sweep(name, {p: [c[p] for c in changes] for p in changes[0]}, mode="zip",
                       scenario=scenario, duration=SECONDS, workers=2)
    for c, change in enumerate(changes):
        alone = _alone(name, scenario, change)
        for metric, values in case_metrics(alone).items():
            np.testing.assert_allclose(ds[metric].values[c], values, rtol=RTOL, atol=0,
                                       equal_nan=True, err_msg=f"{name} case {c}: {metric}")
        assert ds.status.values[c] == alone.verdict.status
        assert list(ds.web_status.values[c]) == web_status(alone)
        assert ds.substeps.values[c] == alone.settings["substeps"]


def test_a_case_that_cannot_be_built_fails_alone_in_its_block() -> None:
    # a web of no stiffness is refused by the line's checks (a sweep refuses it before any
    # case runs; a case built from values that fail only together reaches the batch so):
    # that case is one failed row with the reason, the cases beside it in the same block
    # still run (and equal their runs alone)
    ds = run_branch_cases("laminator", [{"webs.film.web.ea": v}
                                        for v in ("103.5 kN", "0 kN", "130 kN")],
                          duration=0.5, workers=2)
    assert list(ds.status.values) == ["ok", "failed", "ok"]
    assert "web.ea: must be > 0" in str(ds.headline.values[1])
    assert np.isnan(ds.tension_rms_error.values[1]).all()
    alone = simulate_branches(derive_branched(load_branched("laminator"),
                                              {"webs.film.web.ea": "130 kN"}), 0.5)
    np.testing.assert_allclose(ds.tension_peak_error.values[2],
                               case_metrics(alone)["tension_peak_error"], rtol=RTOL, atol=0)


def _equal_alone(built, outputs, seconds: float) -> None:
    for j, result in batch_results(built, outputs, seconds).items():
        alone = simulate_branches(built.lines[j], seconds, raise_on_failure=False)
        assert result.failure == alone.failure
        assert result.rec.shape == alone.rec.shape
        scale = np.max(np.abs(alone.rec), axis=0)
        assert np.all(np.abs(result.rec - alone.rec) <= RTOL * scale)


def test_cases_of_other_sample_rates_share_a_batch_with_their_own_ticks() -> None:
    # 1 kHz and 500 Hz: one structure (dt is a per-case number), 300 and 150 ticks into
    # one record buffer sized for the longer; each case stores its own rows only
    base = load_branched("slitter")
    built = build_branch_cases(base, [{"control.sample_rate": r} for r in ("1 kHz", "500 Hz")],
                               0.3, derive_branched)
    assert [p.dt for p in built.plans] == [1e-3, 2e-3] and built.n_ticks == [300, 150]
    outputs = run_branch_block(built, workers=2)
    assert [idx for idx, _ in outputs] == [[0, 1]]
    _equal_alone(built, outputs, 0.3)


def test_cases_of_other_structures_run_in_their_own_batches() -> None:
    # a drive on another controller family is another compiled structure (its family is
    # frozen into the loop): the block runs two batches, each case still its run alone
    from webline.control.select import with_branched_controller

    def derive(base, change):
        return with_branched_controller(base, change["family"]) if change else base

    built = build_branch_cases(load_branched("slitter"), [{}, {"family": "state_feedback"}, {}],
                               0.3, derive)
    outputs = run_branch_block(built, workers=2)
    assert sorted(idx for idx, _ in outputs) == [[0, 2], [1]]
    _equal_alone(built, outputs, 0.3)


def test_one_thread_and_two_give_the_same_study_bit_for_bit(monkeypatch) -> None:
    # blocks of 1, 2 cases (patched): built, run and collected overlapping on two threads,
    # or in turn on one; progress after each block
    import xarray as xr

    from webline.sim.sweeps import blocks

    monkeypatch.setattr(blocks, "FIRST_BLOCK", 1)
    monkeypatch.setattr(blocks, "BLOCK", 2)
    cases = [{"web.ea": v} for v in ("250 kN", "281.25 kN", "300 kN")]
    done: list[int] = []
    two = run_branch_cases("slitter", cases, duration=0.3, workers=2,
                           progress=lambda d, n: done.append(d))
    one = run_branch_cases("slitter", cases, duration=0.3, workers=1)
    assert done == [1, 3]
    xr.testing.assert_identical(one, two)
