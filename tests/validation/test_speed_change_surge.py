"""Thesis Fig. 4.5 (Sec. 4.1): the span-1 surge and slow return of the 200 -> 1000 ft/min ramp,
against the built-in scenarios' descriptions and the study's reading of the figure."""

from __future__ import annotations

import pytest

import webline
from webline.studies import speed_change_surge as study


def _measure(scenario: str, duration: float, changes: dict | None = None) -> dict:
    line = webline.load_line("hswl").with_scenario(scenario)
    if changes:
        line = line.replace({study.UNWIND + k: v for k, v in changes.items()})
    return study.measure(line, duration)


def test_builtin_speed_change_has_no_surge():
    """hswl's speed-change description: span 1 within 0.4 % (0.06 lbf) of its 14.35 lbf
    reference throughout; the study's reading of Fig. 4.5 (surge >= 10 %, return >= 5 s) is
    not met."""
    m = _measure("speed-change", 20.0)
    assert m["surge_lbf"] < 0.06 and m["deficit_lbf"] < 0.06
    assert max(m["surge_lbf"], m["deficit_lbf"]) < 0.004 * 14.35
    assert not study.reproduces(m)


def test_surge_scenario_matches_its_description_and_the_figure():
    """hswl's speed-change-surge description: span 1 surges 61 % above its reference (8.7 lbf
    over 14.35 lbf), at the start of the ramp (the unwind lags), and returns within 2 % 15 s
    after the ramp."""
    m = _measure("speed-change-surge", 30.0)
    assert m["surge_lbf"] == pytest.approx(8.7, abs=0.05)
    assert m["surge_pct"] == pytest.approx(61.0, abs=0.5)
    assert 2.0 < m["surge_time_s"] < 3.0
    assert m["return_time_s"] == pytest.approx(15.0, abs=0.5)
    assert study.reproduces(m)


def test_inertia_compensation_removes_most_of_the_surge():
    """The mechanism: with the acceleration torque fed forward the same slow loops surge less
    than a fifth as much."""
    slow = {"controller.speed_bandwidth": 2.0, "controller.tension_bandwidth": 0.5}
    plain = _measure("speed-change", 14.0, slow)
    comp = _measure("speed-change", 14.0, {**slow, "winder": {"inertia_compensation": True}})
    assert comp["surge_lbf"] < 0.2 * plain["surge_lbf"]


def test_surge_grows_as_the_unwind_speed_loop_slows():
    """At a fixed 8 rad/s tension loop the surge rises monotonically from the 40 rad/s loop to
    the 1 rad/s loop, by more than two decades."""
    surges = [_measure("speed-change", 10.0, {"controller.speed_bandwidth": w})["surge_lbf"]
              for w in (40.0, 10.0, 4.0, 1.0)]
    assert surges == sorted(surges)
    assert surges[-1] > 100 * surges[0]


def test_study_quick_states_the_thesis_beside_each_case(tmp_path):
    """The study's quick run: a table row per case, the thesis's statement in the summary, the
    default tuning not reproducing the figure and the slowest grid case reproducing it."""
    from webline.studies import STUDIES

    result = STUDIES["speed-change-surge"](tmp_path, quick=True)
    rows = {r["case"]: r for r in result.table}
    assert len(rows) == 6 and "increases drastically" in result.summary
    assert rows["speed 40 rad/s, tension 8 rad/s"]["reproduces_fig_4_5"] is False
    assert rows["speed 2 rad/s, tension 0.5 rad/s"]["reproduces_fig_4_5"] is True
    assert all(p.stat().st_size > 1000 for p in result.figures)
    assert f"{sum(r['reproduces_fig_4_5'] for r in rows.values())} of 6 cases" in result.summary
