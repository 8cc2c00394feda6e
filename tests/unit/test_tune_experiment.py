"""Identification experiments (``webline.twin.tuning.experiment``): each test's traces carry what it
claims to identify, within the line's limits."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.twin.tuning.experiment import plan_experiment

LINE = webline.load_line("converter")


def test_tension_step_identifies_the_modulus() -> None:
    """In steady state a span's tension is EA times its draw (v_down - v_up)/v_down (mass
    conservation with the upstream zone's strain small): the steps' ΔT / Δdraw is EA."""
    plan = plan_experiment(LINE, "tension-step")
    frame = webline.simulate(plan.line, plan.duration).to_dataframe()
    t = frame.index.values

    def at(column: str, time: float) -> float:
        return float(frame[column].values[np.searchsorted(t, time)])

    # process_span ramps up at 1 s (between infeed and drum), held 7.5 s (settled in 7.2 s)
    before, after = 0.99, 8.4
    draw = [(at("surface_speed[drum]", x) - at("surface_speed[infeed]", x))
            / at("surface_speed[drum]", x) for x in (before, after)]
    tension = [at("tension[process_span]", x) for x in (before, after)]
    # the upstream strain (T/EA ~ 0.2 %) and the end of settling: 1 %
    assert (tension[1] - tension[0]) / (draw[1] - draw[0]) == pytest.approx(LINE.ea, rel=0.01)


def test_accel_ramps_stay_inside_the_torque_limits() -> None:
    """The ramps are derived for 30 % of the weakest drive's limit: no drive reaches its
    limit, and the largest carries a clear inertial share (> 20 % of its limit)."""
    plan = plan_experiment(LINE, "accel-ramps")
    run = webline.simulate(plan.line, plan.duration)
    limits = np.array([LINE.spec.rollers[i].drive.torque_limit for i in LINE.drives])
    share = np.abs(run.torque).max(axis=0) / limits
    assert share.max() < 1.0 and share.max() > 0.2
    assert run.verdict.status == "ok"


def test_dancer_step_holds_five_carriage_decays() -> None:
    plan = plan_experiment(LINE, "dancer-step")
    dancer = LINE.spec.rollers[1].dancer
    assert plan.duration >= 1.0 + 2 * 5 * 2 * dancer.mass / dancer.damping


def test_cli_experiment_writes_webline_columns(tmp_path) -> None:
    result = CliRunner().invoke(app, ["experiment", "converter", "dancer-step", "--out",
                                      str(tmp_path)])
    assert result.exit_code == 0, result.output
    header = (tmp_path / "results.csv").read_text().splitlines()[0]
    assert "tension[process_span] [N]" in header
    assert "dancer_position[dancer] [m]" in header  # the carriage a dancer test moves


@pytest.mark.parametrize("args, words", [
    (["experiment", "converter", "nosuch"], "no experiment named 'nosuch'"),
    (["experiment", "converter"], "give an experiment NAME or --list"),
    (["tune", "converter", "--out", "OUT", "--free", "rollers.infeed.inertia=2..1"],
     "0 < LOW < HIGH"),
    (["tune", "converter", "--out", "OUT", "--uncertain", "web.modulus"], "PATH=DIST"),
    (["tune", "converter", "--out", "OUT", "--scenario", "nosuch"], "scenario 'nosuch'"),
    (["tune", "converter", "--out", "OUT", "--fit", "no/such/fit.json"], "cannot read"),
])
def test_bad_input_is_one_line_exit_2(tmp_path, args: list[str], words: str) -> None:
    args = [str(tmp_path / "o") if a == "OUT" else a for a in args]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2
    assert words in result.stderr and len(result.stderr.strip().splitlines()) == 1
