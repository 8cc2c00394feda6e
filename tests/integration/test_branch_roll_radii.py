"""A scenario's ``unwind_radius`` / ``rewind_radius`` on a branched line: the starting radius
of every unwind / every rewind (docs/branching.md, "Options and scenario keys"), and
``webline.linearize``'s arguments of the same names."""

from __future__ import annotations

import tomllib
from importlib import resources
from typing import Any

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.sim.branches.run import simulate_branches


def _data(name: str) -> dict[str, Any]:
    return tomllib.loads(resources.files("webline.data.lines").joinpath(
        f"{name}.toml").read_text("utf-8"))


def _with_scenario(name: str, **scenario: object) -> dict[str, Any]:
    data = _data(name)
    data["scenarios"] = {"fresh": {"duration": "1 s", **scenario}}
    return data


def test_every_roll_of_a_laminator_starts_at_the_scenarios_radius_with_its_hand_torque():
    line = load_branched(_with_scenario("laminator", unwind_radius="0.2 m",
                                        rewind_radius="0.1 m")).with_scenario("fresh")
    ds = simulate_branches(line, 0.05).dataset.isel(time=0)
    radius = ds["radius"]
    assert float(radius.sel(roll="unwind_film/film")) == 0.2
    assert float(radius.sel(roll="unwind_foil/foil")) == 0.2
    assert float(radius.sel(roll="rewind/laminate")) == 0.1
    tension, omega = ds["tension"], ds["omega"]
    ea, v = 103.5e3, 2.5
    # the film leaves its roll at the wound-in 100 N and meets the nip (2.5 m/s) at 120 N:
    # the span's exact mass balance (E-6.6), v_roll/(EA + 100) = v_nip/(EA + 120)
    assert float(omega.sel(node="unwind_film")) == pytest.approx(
        v * (ea + 100) / (ea + 120) / 0.2, rel=1e-9)
    assert float(omega.sel(node="rewind")) == pytest.approx(v / 0.1, rel=1e-3)  # strain < 3e-4
    # torque balance of each roll at constant speed (B4): the unwind brakes its first span's
    # pull, r T - b ω; the rewind drives its last span, r T + b ω (b = 0.05 N m s). The roll's
    # own acceleration as its radius changes (J dω/dt <= 0.02 N m here) is left out: 0.05 N m
    torque = ds["torque_cmd"]
    t_film, w_film = float(tension.sel(span="film[0]")), float(omega.sel(node="unwind_film"))
    assert t_film == pytest.approx(120.0 - 1e-4 * v / 0.05**2, abs=0.01)  # guide's drag
    assert float(torque.sel(drive="unwind_film")) == pytest.approx(
        -(0.2 * t_film - 0.05 * w_film), abs=0.05)
    t_last, w_rewind = float(tension.sel(span="laminate[1]")), float(omega.sel(node="rewind"))
    assert float(torque.sel(drive="rewind")) == pytest.approx(
        0.1 * t_last + 0.05 * w_rewind, abs=0.05)
    # against the file's 0.3 m unwinds the unwind torque falls by 0.1 m x ~120 N = ~12 N m
    base = simulate_branches(load_branched("laminator"), 0.05).dataset.isel(time=0)
    drop = float(torque.sel(drive="unwind_film") - base["torque_cmd"].sel(drive="unwind_film"))
    assert drop == pytest.approx(0.1 * t_film, rel=0.02)


def test_every_shaft_of_the_slitter_starts_at_the_rewind_radius():
    line = load_branched(_with_scenario("slitter", rewind_radius="0.15 m")).with_scenario(
        "fresh")
    ds = simulate_branches(line, 0.02).dataset.isel(time=0)
    rolls = [str(r) for r in ds["roll"].values]
    rewinds = [r for r in rolls if not r.startswith("unwind")]
    assert len(rewinds) == 3  # three lanes on two rewinds (a shaft of two, one alone)
    np.testing.assert_array_equal(ds["radius"].sel(roll=rewinds).values, 0.15)
    assert float(ds["radius"].sel(roll="unwind/base")) == 0.4  # the file's unwind untouched


def test_a_scenarios_set_picks_one_roll_after_the_radii():
    line = load_branched(_with_scenario(
        "laminator", unwind_radius="0.2 m",
        set={"rollers.unwind_foil.radius": "0.25 m"})).with_scenario("fresh")
    radii = {r.name: r.radius for r in line.spec.rollers}
    assert radii["unwind_film"] == 0.2 and radii["unwind_foil"] == 0.25
    assert radii["rewind"] == 0.08  # no rewind_radius: the file's


@pytest.mark.parametrize(("scenario", "key", "words"), [
    ({"unwind_radius": "50 mm"}, "scenarios.fresh.unwind_radius", "above the core radius"),
    ({"rewind_radius": "-1 m"}, "scenarios.fresh.rewind_radius", "must be > 0"),
    ({"unwind_radius": "fast"}, "scenarios.fresh.unwind_radius", ""),
])
def test_a_bad_roll_radius_is_refused_naming_the_scenarios_key(scenario, key, words, tmp_path):
    data = _with_scenario("laminator", **scenario)
    with pytest.raises(LineFileError, match=key.replace(".", r"\.")) as err:
        load_branched(data)
    assert words in str(err.value)
    import tomli_w

    path = tmp_path / "bad.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2 and len(result.stderr.strip().splitlines()) == 1
    assert key in result.stderr and "Traceback" not in result.output


def test_linearize_takes_the_roll_radii_of_a_branched_line():
    system = webline.linearize("laminator", unwind_radius=0.2, rewind_radius=0.1)
    line = load_branched("laminator").replace({"rollers.unwind_film.radius": 0.2,
                                               "rollers.unwind_foil.radius": 0.2,
                                               "rollers.rewind.radius": 0.1})
    same = webline.linearize(line)
    np.testing.assert_array_equal(system.A, same.A)  # the same line, the same matrix
    assert not np.allclose(system.A, webline.linearize("laminator").A)
    with pytest.raises(webline.ArgumentError, match="unwind_radius"):
        webline.linearize("laminator", unwind_radius=0.05)  # inside the 76.2 mm core
