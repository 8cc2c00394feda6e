"""Modes across the rolls of a branched line (docs/branching.md, "Modes across the rolls"):
every unwind and rewind along its course (A1), the closed loop linearized at each point with
the controllers as the run has them; ``webline analyze --across-roll``."""

from __future__ import annotations

import json
import math
import tomllib
from importlib import resources
from itertools import pairwise

import numpy as np
import pytest
from typer.testing import CliRunner

from webline.analysis.branch_across_roll import (
    branch_roll_course,
    branch_roll_modes,
    modes_across_rolls,
)
from webline.analysis.modes import modes_of
from webline.cli import app
from webline.model.web_graph import load_branched
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.loop import layout as B
from webline.sim.branches.plan import compile_branches

#: the laminate's density, kept by its mass per length (docs/branching.md, Topology)
RHO_LAMINATE = (1390 * 23e-6 + 2700 * 9e-6) / 32e-6  # [kg/m³]
CORE = 0.0762  # [m] every roll's core on the laminator


def _laminator(fixed_gains: bool = False) -> dict:
    data = tomllib.loads(resources.files("webline.data.lines").joinpath(
        "laminator.toml").read_text("utf-8"))
    data.pop("scenarios")
    if fixed_gains:  # speed gains designed at the start and held (no inertia adaptation)
        for roller in data["rollers"]:
            if roller["type"] in ("unwind", "rewind"):
                roller["controller"]["inertia_adaptive"] = False
    return data


def test_the_course_follows_each_roll_by_its_own_web_and_starts_at_analyze():
    line = load_branched("laminator")
    course = modes_across_rolls(line, 5)
    assert course.rolls == ("unwind_film/film", "unwind_foil/foil", "rewind/laminate")
    # (A1) independently: the film (23 µm) empties first, after s = π (R0² - Rc²) / h; by
    # then the foil (9 µm) is down to R² = R0² - h_foil s / π and the laminate (32 µm)
    # is wound up to R² = R0² + h_lam s / π; each roll passes the same length s
    s = math.pi * (0.3**2 - CORE**2) / 23e-6
    assert course.length[-1] == pytest.approx(s, rel=1e-12)
    expected = [CORE, math.sqrt(0.3**2 - 9e-6 * s / math.pi),
                math.sqrt(0.08**2 + 32e-6 * s / math.pi)]
    np.testing.assert_allclose(course.radius[-1], expected, rtol=1e-12)
    # the first point is the line as `webline analyze` sees it: the same eigenvalues to
    # round-off (both from the same matrix at the same operating point)
    plan = compile_branches(line)
    plain = modes_of(branch_linear_model(plan, operating_point(plan), "closed").a,
                     branch_linear_model(plan, operating_point(plan), "closed").states)
    first = np.array(sorted(course.eigenvalues[0], key=lambda v: (abs(v), v.imag)))
    listed = np.array(sorted((m.eigenvalue for m in plain), key=lambda v: (abs(v), v.imag)))
    np.testing.assert_allclose(first, listed, rtol=1e-9)


@pytest.mark.parametrize(("scenario", "at", "new"), [("roll-change", 5.0, 0.3),
                                                     ("flying-splice", 2.0, 0.3)])
def test_the_course_renews_an_unwind_at_its_roll_change_or_splice(scenario, at, new):
    # the foil (roll-change) or film (flying-splice) unwind starts at 0.1 m and is renewed
    # at 0.3 m; before and after, (A1) from its own start: R² = R_0² - h s / π, s at 150 m/min
    line = load_branched("laminator").with_scenario(scenario)
    duration = float(line.spec.scenarios[scenario].duration)
    time, length, radius = branch_roll_course(line, 11, duration)
    j = 1 if scenario == "roll-change" else 0
    h = (9e-6 if j else 23e-6) / math.pi
    for t, s, r in zip(time, length, radius[:, j], strict=True):
        expected = 0.1**2 - h * s if t < at else new**2 - h * (s - 2.5 * at)
        assert r == pytest.approx(math.sqrt(expected), rel=1e-9), t


def test_the_model_at_each_point_carries_the_rolls_inertia():
    """The rewind's inertia in the linear model at each point of the course is the roll's
    (6.2) at the radius (A1) gives: J = J_rot + (π/2) w ρ (R⁴ - Rc⁴), read back from the
    open loop's motor-torque column n/J (the torque a state behind its lag)."""
    line = load_branched("laminator")
    plan = compile_branches(line)
    _, _, radius = branch_roll_course(line, 4)
    rewind = line.node_index["rewind"]
    for radii in radius:
        model = branch_linear_model(plan, operating_point(plan, radii=radii), "open")
        row = model.states.index("rewind_omega")
        column = model.states.index("rewind_torque")
        r = radii[2]
        inertia = 0.3 + math.pi / 2 * 1.0 * RHO_LAMINATE * (r**4 - CORE**4)
        # n = 1: the entry is 1/J; linear in the torque, so the central difference is exact
        # but for round-off (1e-9)
        assert model.a[row, column] == pytest.approx(1.0 / inertia, rel=1e-9), (r, rewind)


def test_the_slowest_mode_is_the_line_loaded_with_those_rolls():
    """At every point the closed loop is the line with rolls of those radii (their inertia
    (6.2) and arms) and the gains the run keeps: loading the rolls in the file at the radii
    of the point before the course's end (at the end the film unwind is at its core, which
    a file refuses), with the plan's gains written in, gives the same slowest mode. Along
    the course the laminator's rewind fills (0.3 -> 42 kg·m²) and the film unwind empties
    (18 -> 0.5 kg·m²); with the speed gains held the slowest mode (the laminate zone's
    tension loop) slows from 2.72 to 1.99 rad/s as the rewind's inertia weighs on it. (The
    bonded layers' strain differences, which no loadcell feels, are slower still, -v/L of
    their spans, but no loop's and the same at every radius: the loops' slowest is taken.)"""
    data = _laminator(fixed_gains=True)
    line = load_branched(data)
    plan = compile_branches(line)
    time, length, radius = branch_roll_course(line, 4)
    course = branch_roll_modes(plan, time, radius, length)
    slowest = [complex(values[list(loops).index(True)])
               for values, loops in zip(course.eigenvalues, course.loop, strict=True)]
    assert abs(slowest[0]) == pytest.approx(2.722, abs=1e-3)  # analyze's at t = 0
    assert abs(slowest[-1]) == pytest.approx(1.985, abs=1e-3)
    assert all(abs(a) > abs(b) for a, b in pairwise(slowest))  # monotone
    # the same line, its rolls loaded at the radii of the point before the end (at the end
    # the film unwind is at its core, which a line file refuses), the plan's gains pinned
    end = dict(zip(("unwind_film", "unwind_foil", "rewind"), radius[-2], strict=True))
    for roller in data["rollers"]:
        if roller["name"] in end:
            roller["radius"] = f"{float(end[roller['name']])!r} m"
        if "controller" in roller:
            d = plan.line.drives.index(plan.line.node_index[roller["name"]])
            row = plan.df[d]
            roller["controller"].update(speed_kp=float(row[B.D_KPS]),
                                        speed_ki=float(row[B.D_KIS]))
            if row[B.D_KPT] > 0.0:
                roller["controller"].update(tension_kp=float(row[B.D_KPT]),
                                            tension_ki=float(row[B.D_KIT]))
    loaded = compile_branches(load_branched(data))
    model = branch_linear_model(loaded, operating_point(loaded), "closed")
    values = np.linalg.eigvals(model.a)
    nearest = values[np.argmin(np.abs(values - slowest[-2]))]
    # one matrix built two ways (radii put in at the operating point, or loaded from the
    # file): equal to the root finder's and the differences' round-off
    assert abs(nearest - slowest[-2]) < 1e-7 * abs(slowest[-2])


def test_the_torque_lag_mode_follows_the_rewinds_inertia():
    """An independent check of the inertia in the closed loop: the rewind's torque lag
    pole, with its speed gain held, sits where its speed loop's proportional action over
    the roll's mass moves it. Its own section (the laminate zone's spans lumped, 3.5 m, the
    nip held; states δT, δv, δτ, speed and tension integrals):

        L dT/dt = (EA - T) v - v_nip T,  (J/r) dv/dt = n τ - (b/r) v - r T,
        lag dτ/dt = k_pS (k_pT (T_ref - T) + q_T - v) + q_S - τ

    gives it to 1e-3 at every point past the first while J grows 16-fold (the lag pole is far
    from the slow modes the nip's coupling moves: measured 2e-4; at the first point, the
    near-empty core, it sits among the other drives' lag poles at -407 to -417 1/s and
    shares their participation)."""
    data = _laminator(fixed_gains=True)
    line = load_branched(data)
    plan = compile_branches(line)
    time, length, radius = branch_roll_course(line, 5)
    course = branch_roll_modes(plan, time, radius, length)
    row = plan.df[plan.line.drives.index(plan.line.node_index["rewind"])]
    kps, kis, kpt, kit = (row[B.D_KPS], row[B.D_KIS], row[B.D_KPT], row[B.D_KIT])
    ea, span, v, tension, lag, friction = 733.5e3, 3.5, 2.5, 180.0, 2e-3, 0.05
    for p, radii in enumerate(radius[1:], start=1):
        r = radii[2]
        inertia = 0.3 + math.pi / 2 * RHO_LAMINATE * (r**4 - CORE**4)
        section = np.array([
            [-v / span, (ea - tension) / span, 0, 0, 0],
            [-r * r / inertia, -friction / inertia, r / inertia, 0, 0],
            [-kps * kpt / lag, -kps / lag, -1 / lag, 1 / lag, kps / lag],
            [-kis * kpt, -kis, 0, 0, kis],
            [-kit, 0, 0, 0, 0]])
        predicted = min(np.linalg.eigvals(section).real)  # the lag pole: real, fastest
        lag_modes = [complex(value) for value, name in
                     zip(course.eigenvalues[p], course.dominant[p], strict=True)
                     if name == "rewind_torque"]
        assert len(lag_modes) == 1
        assert lag_modes[0].real == pytest.approx(predicted, rel=1e-3), (r, inertia)
    # as the inertia grows, n k_pS r / J shrinks and the pole goes to -1/lag
    assert -1 / lag < predicted < -1 / lag + 5.0


def test_analyze_across_roll_on_a_branched_line_prints_and_maps(tmp_path):
    png = tmp_path / "map.png"
    result = CliRunner().invoke(app, ["analyze", "slitter", "--scenario", "start-up",
                                      "--across-roll", "--points", "4", "--json",
                                      "--figure", str(png)])
    assert result.exit_code == 0, result.output
    payload = json.loads(result.stdout)
    points = payload["modes_across_roll"]["points"]
    assert [p["time_s"] for p in points] == [0.0, 5.0, 10.0, 15.0]
    # the scenario's course: 0 for 1 s, ramped to 5 m/s over 10 s, then 4 s at 5 m/s:
    # s = 25 + 20 = 45 m, so the 50 µm lanes wind on R² = 0.08² + h s / π
    assert points[-1]["web_run"] == pytest.approx(45.0, rel=1e-3)
    lane = points[-1]["diameters"]["rewind_shaft/lane_1"]
    assert lane == pytest.approx(2 * math.sqrt(0.08**2 + 50e-6 * 45.0 / math.pi), rel=1e-3)
    assert payload["verdict"]["status"] == "ok"
    assert png.read_bytes()[:4] == b"\x89PNG"
    table = CliRunner().invoke(app, ["analyze", "slitter", "--across-roll", "--points", "3",
                                     "--units", "imperial"])
    assert table.exit_code == 0, table.output
    assert "Modes across the rolls" in table.output and "unwind/base ⌀ [ft]" in table.output


def test_across_roll_bad_input_is_one_line():
    result = CliRunner().invoke(app, ["analyze", "slitter", "--figure", "x.png"])
    assert result.exit_code == 2 and "--figure" in result.output
    assert "Traceback" not in result.output
    result = CliRunner().invoke(app, ["analyze", "slitter", "--across-roll", "--points", "1"])
    assert result.exit_code == 2 and "--points" in result.output
