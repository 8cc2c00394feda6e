"""The sub-step rule and record interval, defined once (``sim.linear.steps``)."""

from __future__ import annotations

import pytest

from webline.sim.linear.steps import (
    MAX_RECORDS,
    MAX_SUBSTEPS,
    STEP_LIMIT,
    record_every,
    substeps_for,
    too_stiff,
)


@pytest.mark.parametrize(
    "rate, expected",
    [
        (500.0, 1),  # h·λ = 0.5 exactly: one step
        (500.000000002, 1),  # the branched eigen-solve's rounding of hswl's 500 1/s (issue 33)
        (500.0 * (1 + 2e-6), 2),  # beyond the slack: 0.500001 is a real excess
        (1e-3, 1),
        (0.0, 1),  # a slow (or no) mode still takes one step
        (1499.0, 3),
        (1500.0, 3),
        (1501.0, 4),
    ],
)
def test_substeps_keep_h_lambda_at_the_step_limit(rate, expected):
    """ceil(dt·λ / 0.5) up to a relative 1e-6: with dt = 1 ms, 500 1/s is one step."""
    assert substeps_for(rate, 1e-3) == expected
    # and the chosen step keeps h·λ within the limit, up to the slack
    assert 1e-3 / expected * rate <= STEP_LIMIT * (1 + 1e-6)


def test_too_stiff_is_more_than_max_substeps():
    dt = 1e-3
    limit = MAX_SUBSTEPS * STEP_LIMIT / dt  # 1e5 1/s: exactly MAX_SUBSTEPS steps
    assert not too_stiff(limit, dt)
    assert too_stiff(limit * 1.001, dt)


def test_record_every_caps_the_records_or_follows_the_interval():
    assert record_every(MAX_RECORDS - 1, 1e-3) == 1  # with t = 0: MAX_RECORDS records
    assert record_every(MAX_RECORDS, 1e-3) == 2
    assert record_every(10, 1e-3, 0.0104) == 10  # an interval rounds to whole ticks
    assert record_every(10, 1e-3, 1e-5) == 1  # (at least one)
