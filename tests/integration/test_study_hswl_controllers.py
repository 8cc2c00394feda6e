"""Study ``hswl-controllers`` (quick): files, table facts and the adaptive estimates."""

from __future__ import annotations

import csv
import math

import pytest

from webline.studies import STUDIES, run_study
from webline.studies.hswl_controllers import CASES, SPEEDS_FPM


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("hswl-controllers")
    return out, run_study("hswl-controllers", out, quick=True)


def rows_of(result, controller, **match):
    return [r for r in result.table if r["controller"] == controller
            and all(r[k] == v for k, v in match.items())]


def test_registry_and_files(study):
    out, result = study
    assert STUDIES["hswl-controllers"] is not None and result.name == "hswl-controllers"
    names = {p.name for p in result.figures}
    assert {f"{c.key}_500fpm.png" for c in CASES} | {"summary.png"} <= names
    assert all(p.exists() and p.stat().st_size > 10_000 for p in result.figures)
    with (out / "table.csv").open() as f:
        assert len(list(csv.DictReader(f))) == len(result.table)
    assert "reduction of RMS tension error" in (out / "summary.txt").read_text()


def test_table_covers_every_case_speed_and_drive(study):
    _, result = study
    assert len(result.table) == len(CASES) * len(SPEEDS_FPM) * 4
    for row in result.table:
        for key in ("rms_speed_error_m_s", "peak_speed_error_m_s", "rms_torque_variation_N_m"):
            assert math.isfinite(row[key]) and row[key] > 0, (row, key)
        if row["span"]:
            assert 0 < row["rms_tension_error_N"] <= row["peak_tension_error_N"] < math.inf
        else:  # the master regulates no zone
            assert math.isnan(row["rms_tension_error_N"])


def test_tension_errors_bounded(study):
    """Disturbances of 1 lbf and noise: the tuned controllers keep every zone within 2 N
    (3 % of the 63.8 N reference); even the state feedback with a 50 %-low friction model,
    which has no integral action, stays within 25 N at 1500 ft/min."""
    _, result = study
    for row in result.table:
        if row["span"]:
            loose = ("state_feedback_wrong_friction", "state_feedback_thesis_gains",
                     "mrac_thesis_gains")  # no integral action / unrealisable gains (§4)
            limit = 25.0 if row["controller"] in loose else 2.0
            assert row["peak_tension_error_N"] < limit, row


def test_adaptive_estimates_move_to_true_friction(study):
    """Estimates start 50 % low. After the quick run's 20 s, the master's has converged
    (< 1 %) and the process roller's and rewind's are closer to the truth than they started
    (they swing past it in the first seconds and settle over a minute, under noise); the
    unwind's overshoots most (to ~9x in the first second at 500 ft/min, see
    docs/decentralized.md) and is still below 4x the true value after 20 s."""
    _, result = study
    for row in rows_of(result, "adaptive"):
        true, final = row["friction_true_N_m_s"], row["friction_final_N_m_s"]
        start_error = 0.5 * true
        if row["drive"] == "master":
            assert abs(final - true) < 0.01 * true
        elif row["drive"] in ("process", "rewind"):
            assert abs(final - true) < start_error, row
        else:
            assert 0 < final < 4 * true


def test_reductions_are_relative_to_pi(study):
    _, result = study
    for row in rows_of(result, "cascaded_pi"):
        if row["span"]:
            assert row["reduction_vs_pi"] == 0.0
    for row in result.table:
        if row["span"]:
            pi = rows_of(result, "cascaded_pi", speed_fpm=row["speed_fpm"], drive=row["drive"])
            ratio = row["rms_tension_error_N"] / pi[0]["rms_tension_error_N"]
            assert row["reduction_vs_pi"] == pytest.approx(1 - ratio)


def test_summary_states_what_the_estimates_did(study):
    """The sentence on the estimates is the table's: how many ended closer to the truth than
    they started, and the worst one's final and initial error."""
    _, result = study
    adaptive = rows_of(result, "adaptive")

    def error(row, key):
        return abs(row[key] / row["friction_true_N_m_s"] - 1)

    closer = sum(error(r, "friction_final_N_m_s") < error(r, "friction_initial_N_m_s")
                 for r in adaptive)
    worst = max(adaptive, key=lambda r: error(r, "friction_final_N_m_s"))
    assert f"{closer} of {len(adaptive)} end closer" in result.summary
    assert (f"the worst, {worst['drive']} at {worst['speed_fpm']:.0f} ft/min, ends "
            f"{error(worst, 'friction_final_N_m_s'):.0%} off") in result.summary
    final, start = error(worst, "friction_final_N_m_s"), error(worst, "friction_initial_N_m_s")
    verb = "closer to" if final < start else "farther from"
    assert f"({verb} the truth than its start, {start:.0%} off)" in result.summary
    assert result.verdict is not None and result.verdict.status in ("ok", "warning")
