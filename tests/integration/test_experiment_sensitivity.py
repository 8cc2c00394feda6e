"""The sensitivity check before an experiment runs (issue 36 item 7): which requested
parameters the planned test can identify, from finite-difference sensitivities of the
signals it logs at the rate it states."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.line import load_line
from webline.twin.tuning.experiment import plan_experiment
from webline.twin.tuning.experiment_sensitivity import check_plan

LINE = load_line("hswl")
FRICTION = ["rollers.master.friction", "rollers.master.coulomb_friction=0 .. 2 N*m"]


def test_one_speed_cannot_separate_viscous_from_coulomb_friction():
    """At one line speed the master's friction torque is b ω + c with ω constant (a tension
    step moves the speeds by the draw, ~T/EA ~ 1e-3 of them): the record sees only their
    sum, so b and c are perfectly anticorrelated and neither is identified; the process
    roller's inertia (its ramps) and EA (the draw) are."""
    check = check_plan(plan_experiment(LINE, "tension-step"),
                       [*FRICTION, "rollers.process.inertia", "web.ea"])
    assert list(check.identifiable) == [False, False, True, True]
    # their two columns are parallel: one direction of the scaled sensitivities is ~1e-3
    # of the largest (correlation -1.000)
    assert all("near-zero singular direction" in check.reasons[i] for i in (0, 1))
    assert check.condition > 1e3


def test_three_speeds_separate_them():
    """accel-ramps holds at v/3, 2v/3 and v: b ω changes with ω, c does not (its sign flips
    only with the speed's): both identified, the condition number near 1."""
    check = check_plan(plan_experiment(LINE, "accel-ramps"), FRICTION)
    assert all(check.identifiable) and check.condition < 10
    assert check.half_width[0] < 0.01 * check.value[0]


def test_cli_says_so_before_it_runs(tmp_path):
    result = CliRunner().invoke(app, ["experiment", "hswl", "tension-step", "-o",
                                      str(tmp_path), "--identify", ",".join(FRICTION)])
    assert result.exit_code == 0, result.output
    first = result.output.splitlines()
    assert first[0].startswith("sensitivity check of tension-step on hswl")
    assert "warning: tension-step cannot identify rollers.master.friction" in result.output
    data = json.loads((tmp_path / "experiment.json").read_text())
    assert [p["identifiable"] for p in data["sensitivity"]["parameters"]] == [False, False]


@pytest.mark.parametrize("args, words", [
    (["--identify", "rollers.nosuch.inertia"], "identify rollers.nosuch.inertia: matches no"),
    (["--identify", "rollers.master.coulomb_friction"], "give bounds as PATH=LOW..HIGH"),
])
def test_bad_identify_is_one_line_exit_2(tmp_path, args, words):
    result = CliRunner().invoke(app, ["experiment", "hswl", "tension-step", "-o",
                                      str(tmp_path / "o"), *args])
    assert result.exit_code == 2, result.output
    assert words in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()  # said before anything was run or written


def test_the_same_physics_on_a_branched_line():
    """The laminator's tension step (one speed) cannot separate the nip's viscous from its
    Coulomb friction either; the film's EA it identifies."""
    from webline.twin.tuning.experiment_branched import PLANNERS

    check = check_plan(PLANNERS["tension-step"](webline.load_line("laminator")),
                       ["webs.film.web.ea", "rollers.nip.friction",
                        "rollers.nip.coulomb_friction=0 .. 2 N*m"])
    assert list(check.identifiable) == [True, False, False]
    assert all("near-zero singular direction" in check.reasons[i] for i in (1, 2))
