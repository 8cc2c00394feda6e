"""The line file's [checks] on a branched line (docs/branching.md, "Winder states in the
verdict"): a web's or lane's zone off its set tension, a diameter calculator off its roll's
true diameter and a dancer on its end stop, each for the table's time, with the table's
thresholds; the numbers checked against the run's own trace."""

from __future__ import annotations

from importlib import resources
from typing import Any

import numpy as np
import pytest
from test_branch_dancers import dancer_laminator
from typer.testing import CliRunner

import webline
from webline.model.web_graph import load_branched
from webline.sim.branches.result import BranchResult

DURATION = 12.0  # [s]: the slitter's lanes drift ~30 % apart by then (thickness-profile)


def _slitter(checks: dict[str, Any]) -> BranchResult:
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    data["checks"] = checks
    return webline.simulate(load_branched(data), DURATION, scenario="thickness-profile")


@pytest.fixture(scope="module")
def drift():
    """The slitter's thickness-profile: lane_1 1 % thicker than lane_2 on the shared shaft,
    its roll grows faster and the two lanes' tensions drift apart from their 100 N; the
    shaft's loop holds their sum. Default checks (20 %, 1 s)."""
    return _slitter({})


def _error(result: BranchResult, span: str) -> np.ndarray:
    """|T - T_set| / T_set of a lane's loadcell span at each record (its set tension is
    100 N, no taper or ramp on the slitter)."""
    return np.abs(result.dataset["tension"].sel(span=span).values - 100.0) / 100.0


def _sustained(time: np.ndarray, error: np.ndarray, duration: float) -> float:
    """The largest e such that error > e holds over some interval of ``duration`` [s]: the
    largest over the windows of that length of the smallest error in the window."""
    n = round(duration / (time[1] - time[0]))
    return float(np.lib.stride_tricks.sliding_window_view(error, n + 1).min(axis=1).max())


def _found(result: BranchResult, kind: str) -> dict[str, Any]:
    return {f.where: f for f in result.verdict.findings if f.kind == kind}


def test_a_lane_off_its_set_tension_is_found_with_the_tolerance_it_exceeds(drift):
    """With 20 % and 1 s both lanes are found from the first record their error exceeds
    20 % (the error grows steadily, so that interval lasts to the end), lane_3 (its own
    rewind) and the unwind zone are not; the finding's numbers are the trace's."""
    t = drift.time
    found = _found(drift, "tension_off_set")
    assert sorted(found) == ["lane_1", "lane_2"]
    for lane in ("lane_1", "lane_2"):
        error = _error(drift, f"{lane}_span")
        over = error > 0.2
        start = int(np.argmax(over))
        assert np.all(over[start:]) and t[-1] - t[start] >= 1.0
        finding = found[lane]
        # the records' own times: exact
        assert finding.details["first_s"] == t[start]
        assert finding.details["total_s"] == pytest.approx(t[-1] - t[start], abs=1e-12)
        assert finding.details["largest_error_N"] == pytest.approx(100 * error.max(), rel=1e-12)
        assert finding.details["source"] == "measured (loadcell)"
        assert "measured tension stayed more than 20% off" in finding.message


def test_a_tolerance_above_the_lanes_error_or_held_too_briefly_finds_nothing(drift):
    """The trace's largest error e_max and the largest held for 1 s, e_1 < e_max: a
    tolerance between them is exceeded, but not for 1 s: nothing; one above e_max:
    nothing; one below e_1: found (the tolerance from the file, in its words)."""
    t = drift.time
    errors = [_error(drift, f"{lane}_span") for lane in ("lane_1", "lane_2")]
    peak = max(float(e.max()) for e in errors)
    held = max(_sustained(t, e, 1.0) for e in errors)
    assert 0.25 < held < peak  # (the drift still grows at 12 s)
    between = _slitter({"tension_tolerance": 0.5 * (held + peak)})
    assert not _found(between, "tension_off_set")
    assert not _found(_slitter({"tension_tolerance": 1.01 * peak}), "tension_off_set")
    below = _found(_slitter({"tension_tolerance": 0.98 * held}), "tension_off_set")
    assert below and f"more than {0.98 * held:.0%} off" in next(iter(below.values())).message
    # a shorter min_duration finds the brief excess the 1 s one does not
    short = _found(_slitter({"tension_tolerance": 0.5 * (held + peak),
                             "min_duration": "0 s"}), "tension_off_set")
    assert short


def _laminator_calculator(checks: dict[str, Any]) -> BranchResult:
    """The laminator's rewind with a thickness calculator started 2 % above the true
    diameter (0.1632 m for 0.16 m): thickness integration never corrects it."""
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    data["rollers"][6]["diameter"] = {"method": "thickness", "initial": "0.1632 m"}
    data["checks"] = checks
    return webline.simulate(load_branched(data), 3.0)


def test_a_calculator_off_its_rolls_diameter_by_more_than_the_tolerance_is_found():
    """The error stays 2 % of the diameter (both radii grow by h per turn): a 1 % tolerance
    finds it from the start with its largest signed error, 3 % does not."""
    result = _laminator_calculator({"diameter_tolerance": 0.01, "min_duration": "2 s"})
    ds = result.dataset
    error = 2 * (ds["control_radius"].sel(drive="rewind").values
                 - ds["radius"].sel(roll="rewind/laminate").values)
    assert np.all(np.abs(error / (2 * ds["radius"].values[:, -1]) - 0.02) < 1e-3)
    found = _found(result, "diameter_error")
    assert list(found) == ["rewind"]
    assert found["rewind"].details["first_s"] == 0.0
    assert found["rewind"].details["largest_error_m"] == pytest.approx(np.abs(error).max(),
                                                                       rel=1e-12)
    assert "off the true one of roll rewind/laminate (largest +3.2 mm)" in (
        found["rewind"].message)
    assert not _found(_laminator_calculator({"diameter_tolerance": 0.03}), "diameter_error")


def test_a_dancer_on_its_stop_for_less_than_end_stop_time_is_not_found():
    """The film dancer set 0.5 mm below its end runs onto its stop after the layer upset
    (2 s) for a few ms (the stop's 1e6 N/m throws it back): the time on it, read from the
    trace (records on the stop, each until the next record), is found with end_stop_time
    half of it and not with 1.5 x it."""
    def run(end_stop_time: float) -> tuple[dict[str, Any], BranchResult]:
        data = dancer_laminator(position="0.1995 m")
        data["checks"] = {"end_stop_time": end_stop_time}
        result = webline.simulate(load_branched(data), 4.0, scenario="layer-upset")
        return _found(result, "dancer_end_stop"), result

    found, result = run(0.0)
    t = result.time
    on = np.flatnonzero(result.dataset["dancer_position"].values[:, 0] >= 0.2)
    assert len(on) and np.all(np.diff(on) == 1)  # one touch
    touch = float(t[on[-1] + 1] - t[on[0]])
    assert found["film"].details["longest_s"] == pytest.approx(touch, abs=1e-12)
    assert "film" in run(0.5 * touch)[0]
    assert not run(1.5 * touch)[0]


def test_bad_checks_on_the_cli_are_one_line_and_exit_2(tmp_path):
    from webline.cli import app

    text = resources.files("webline.data.lines").joinpath("laminator.toml").read_text("utf-8")
    bad = tmp_path / "bad.toml"
    bad.write_text(text + '\n[checks]\ndiameter_tolerance = -0.1\n', encoding="utf-8")
    result = CliRunner().invoke(app, ["validate", str(bad)])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "checks.diameter_tolerance" in lines[0], lines
