"""The verdict's rules (status, exit code, headline) and the interval statistics of events."""

from __future__ import annotations

import json

import numpy as np
import pytest

from webline.sim.results.events import EventStats, intervals
from webline.verdict import Finding, Verdict, combine

SLACK = Finding("warning", "slack", "span2", "span2 went slack 3 times", 1.5)
LIMIT = Finding("warning", "torque_limit", "master", "master sat at its torque limit", 0.5)
MODE = Finding("unstable", "unstable_mode", "process_twist", "a mode grows")
EMPTY = Finding("failed", "unwind_empty", "unwind", "the unwind ran out of web", 9.0)
RUNAWAY = Finding("failed", "diverged", "span3", "span3 stretch reached 0.6 x EA", 2.0)
STOPPED = Finding("interrupted", "interrupted", "line", "stopped by the user", 3.0)


@pytest.mark.parametrize(("findings", "status", "code"), [
    ((), "ok", 0),
    ((SLACK, LIMIT), "warning", 0),
    ((SLACK, MODE), "unstable", 3),
    ((SLACK, MODE, EMPTY), "failed", 1),
    ((SLACK, RUNAWAY), "failed", 3),
    ((SLACK, MODE, STOPPED), "interrupted", 130),
    ((STOPPED, EMPTY), "failed", 1),
])
def test_status_is_the_worst_level_and_sets_the_exit_code(findings, status, code):
    verdict = Verdict.of(findings)
    assert verdict.status == status
    assert verdict.exit_code == code
    assert verdict.headline.startswith(f"{status}:")


def test_findings_are_ordered_worst_first_then_by_time_and_the_headline_names_the_worst():
    verdict = Verdict.of([SLACK, LIMIT, MODE, RUNAWAY])
    assert [f.kind for f in verdict.findings] == ["diverged", "unstable_mode", "torque_limit",
                                                  "slack"]
    assert verdict.headline == ("failed: span3 stretch reached 0.6 x EA; a mode grows "
                                "(and 2 more findings)")


def test_combine_and_json():
    verdict = combine(Verdict.of([SLACK]), Verdict.of([MODE]), Verdict.of([]))
    assert verdict.status == "unstable" and len(verdict.findings) == 2
    data = json.loads(json.dumps(verdict.as_dict(), allow_nan=False))
    assert data["exit_code"] == 3
    assert data["findings"][1] == {"level": "warning", "kind": "slack", "where": "span2",
                                   "message": SLACK.message, "time_s": 1.5, "details": {}}


def test_intervals_of_a_hand_made_pattern():
    """Records every 0.1 s: True at 1-2, 5, and 8-9 (open at the end) give three intervals
    ending at the first record without the condition, the last one at the last record."""
    time = np.arange(10) * 0.1
    mask = np.zeros(10, bool)
    mask[[1, 2, 5, 8, 9]] = True
    got = intervals(time, mask)
    np.testing.assert_allclose(got, [[0.1, 0.3], [0.5, 0.6], [0.8, 0.9]])
    stats = EventStats("slack", "span1", got, duration=0.9)
    assert stats.count == 3
    assert stats.first == pytest.approx(0.1)
    assert stats.total == pytest.approx(0.2 + 0.1 + 0.1)
    assert stats.longest == pytest.approx(0.2)
    assert stats.fraction == pytest.approx(0.4 / 0.9)
    assert stats.sentence() == ("span1 went slack 3 times, first at t = 0.1 s, 0.4 s in all "
                                "(44.4% of the run), longest 0.2 s")
    assert intervals(time, np.zeros(10, bool)).shape == (0, 2)


@pytest.mark.serial  # timed: needs the CPU to itself
def test_a_thousand_intervals_cost_no_python_loop():
    """1e6 records with 250 000 intervals: counted exactly, in well under a second."""
    import time as clock

    n = 1_000_000
    time = np.arange(n) * 1e-3
    mask = (np.arange(n) % 4) == 1  # one record in four, each an interval of 1 ms
    started = clock.perf_counter()
    got = intervals(time, mask)
    assert clock.perf_counter() - started < 1.0
    assert got.shape == (n // 4, 2)
    np.testing.assert_allclose(got[:, 1] - got[:, 0], 1e-3, rtol=1e-9)
