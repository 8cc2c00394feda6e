"""The front door refuses nonsense (issue 11, item 3): strict quantity strings, physical
ranges, every error of a file at once with its TOML line, the work estimate before a run,
and a Python API that takes what the CLI takes."""

from __future__ import annotations

import copy
import math
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import ArgumentError, LineFileError
from webline.line import load_line
from webline.sim.linear import budget
from webline.spec.load import spec_from_dict
from webline.spec.locate import key_lines
from webline.spec.schema import CascadedPISpec, LineSpec
from webline.units import to_si, ureg

HSWL_TEXT = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")
HSWL: dict[str, Any] = tomllib.loads(HSWL_TEXT)


def hswl(**changes: Any) -> dict[str, Any]:
    """The HSWL dict with dotted-path changes: hswl(**{"web.thickness": "1 m"})."""
    data = copy.deepcopy(HSWL)
    for path, value in changes.items():
        node: Any = data
        parts = [int(p) if p.isdigit() else p for p in path.split(".")]
        for part in parts[:-1]:
            node = node[part]
        node[parts[-1]] = value
    return data


# --- quantity strings --------------------------------------------------------------------------


@pytest.mark.parametrize("text", ["1,5 m", "1.2.3 m", "{{7*7}} m", "1 m\x07", "1\tm", "m 3",
                                  "3 m m/", "9**9**9 m", "1 m**999", "(1) m"])
def test_a_quantity_is_a_number_and_a_unit_and_nothing_else(text: str) -> None:
    with pytest.raises(ValueError, match="cannot read"):
        to_si(text, "length")


def test_an_angle_is_not_a_ratio_but_a_percentage_is() -> None:
    with pytest.raises(ValueError, match="expected a dimensionless"):
        to_si("3 deg", "dimensionless")
    assert to_si("5 %", "dimensionless") == pytest.approx(0.05, rel=1e-15)
    assert to_si("0.5", "dimensionless") == 0.5


def test_pint_quantities_are_accepted() -> None:
    assert to_si(ureg.Quantity(2, "min"), "time") == 120.0
    assert to_si(ureg.Quantity(500, "ft/min"), "speed") == pytest.approx(2.54, rel=1e-15)
    with pytest.raises(ValueError, match="expected a length"):
        to_si(ureg.Quantity(2, "s"), "length")


def test_six_hertz_bandwidth_means_the_same_in_docs_and_code() -> None:
    # docs/line-file.md: '"6 Hz" as 2π·6 = 37.7 rad/s' for a bandwidth
    doc = (Path(__file__).resolve().parents[2] / "docs" / "line-file.md").read_text("utf-8")
    assert '`"6 Hz"` as\n  2π·6 = 37.7 rad/s' in doc
    pi = CascadedPISpec(speed_bandwidth="6 Hz")
    assert pi.speed_bandwidth == pytest.approx(2 * math.pi * 6, rel=1e-15)
    assert round(pi.speed_bandwidth, 1) == 37.7


# --- physical ranges -------------------------------------------------------------------------


@pytest.mark.parametrize(("key", "value", "shown"), [
    ("web.thickness", "1 m", "1 m is outside the physical range 1e-07 .. 0.02 m"),
    ("spans.0.length", "1 nm", "1e-09 m is outside the physical range 0.001 .. 1000 m"),
    ("control.sample_rate", "1 GHz", "1e+09 Hz is outside the physical range 1 .. 1e+06 Hz"),
    ("rollers.1.inertia", 1e300, "1e+300 kg*m**2 is outside the physical range"),
    ("speed", "3000 ft/s", "914.4 m/s is outside the physical range 0 .. 200 m/s"),
])
def test_a_value_outside_its_hard_range_is_an_error(key: str, value: object, shown: str) -> None:
    with pytest.raises(LineFileError) as info:
        spec_from_dict(hswl(**{key: value}), "line.toml")
    dotted = key.replace(".0.", "[0].").replace(".1.", "[1].")
    assert info.value.key == dotted
    assert info.value.problem.startswith(shown)


@pytest.mark.parametrize("seed", [10**400, -1, 2**60])
def test_a_huge_integer_is_a_clean_range_error(seed: int) -> None:
    data = hswl(disturbances=[{"type": "measurement_noise", "seed": seed}])
    with pytest.raises(LineFileError) as info:
        spec_from_dict(data, "line.toml")
    assert info.value.key == "disturbances[0].seed"
    assert "outside the physical range 0 .. 9.007e+15" in info.value.problem


def test_an_unusual_value_is_a_warning_on_the_line() -> None:
    line = load_line(hswl(**{"control.sample_rate": "50 kHz"}))
    assert line.warnings == ("control.sample_rate: 5e+04 Hz is unusual (usual range 50 .. "
                             "2e+04 Hz): drive controllers sample at 0.1-20 kHz",)
    assert load_line("hswl").warnings == ()


def test_validate_prints_warnings_and_exits_0(tmp_path: Path) -> None:
    path = tmp_path / "fast.toml"
    path.write_text(HSWL_TEXT.replace('sample_rate = "1 kHz"', 'sample_rate = "50 kHz"'))
    assert 'sample_rate = "1 kHz"' in HSWL_TEXT
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 0, result.output
    assert f"warning: {path}: control.sample_rate: 5e+04 Hz is unusual" in result.output
    assert "; 1 warnings" in result.output


# --- all the errors of a file at once ------------------------------------------------------


def test_every_error_with_its_line_and_a_suggestion(tmp_path: Path) -> None:
    text = (HSWL_TEXT.replace('length = "33 ft"', 'length = "1,5 m"')
            .replace("torque_limit =", "torque_limt =", 1)
            .replace('thickness = "12.7 um"', 'thickness = "1 m"'))
    path = tmp_path / "line.toml"
    path.write_text(text)
    lines = key_lines(text)
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2
    errors = result.output.splitlines()
    assert errors == [
        f"error: {path}:{lines['web.thickness']}: web.thickness: 1 m is outside the physical "
        "range 1e-07 .. 0.02 m",
        f"error: {path}:{lines['rollers[0].drive']}: rollers[0].drive.torque_limt: unknown "
        "key; did you mean 'torque_limit'?",
        f"error: {path}:{lines['spans[1].length']}: spans[1].length: cannot read '1,5 m' as a "
        "length: write a number and a unit, e.g. '1.5 m' (a decimal point, no commas or "
        "expressions)",
    ]  # and no "torque_limit: required key is missing"


def test_toml_lines_are_located() -> None:
    lines = key_lines(HSWL_TEXT)
    text = HSWL_TEXT.splitlines()
    for key, start in [("web.thickness", "thickness ="), ("rollers[2].name", "name ="),
                       ("rollers[2].drive.torque_limit", "drive = {"),
                       ("spans[1].length", "length ="),
                       ("scenarios.roll-change.unwind_radius", "unwind_radius =")]:
        assert text[lines[key] - 1].startswith(start), key
    assert text[lines["rollers[2].name"] - 1] == 'name = "process"'


def test_many_errors_are_capped_at_20() -> None:
    data = hswl()
    for i in range(30):
        data[f"unknown{i}"] = 1
    with pytest.raises(LineFileError) as info:
        spec_from_dict(data, "x.toml")
    assert len(info.value.problems) == 30
    assert str(info.value).splitlines()[-1] == "x.toml: and 10 more problems"
    assert len(str(info.value).splitlines()) == 21


def test_with_scenario_does_not_revalidate_the_line(monkeypatch: pytest.MonkeyPatch) -> None:
    # validating N scenarios used to re-validate the whole line (all N scenarios) N times;
    # only a scenario that sets values by path (a 'set' table) validates its changed line
    data = hswl()
    data["scenarios"] = {k: v for k, v in data["scenarios"].items() if "set" not in v}
    data["scenarios"].update({f"s{i}": {"duration": 1 + i % 5} for i in range(300)})
    line = load_line(data)
    calls = []
    monkeypatch.setattr(LineSpec, "model_validate",
                        classmethod(lambda cls, *a, **k: calls.append(1)))
    for name in line.spec.scenarios:
        assert list(line.with_scenario(name).spec.scenarios) == [name]
    assert calls == []


# --- work estimate ---------------------------------------------------------------------------


def test_a_run_beyond_the_budget_names_the_key_behind_the_fastest_mode() -> None:
    line = load_line(hswl(**{"rollers.1.drive.torque_lag": "1 us"}))
    with pytest.raises(LineFileError) as info:
        webline.simulate(line, "1 h")
    assert info.value.key == "rollers[1].drive.torque_lag"
    assert "more than 2e+09" in info.value.problem


def test_a_run_beyond_the_budget_by_its_ticks_names_the_sample_rate() -> None:
    line = load_line(hswl(**{"control.sample_rate": "1 MHz"}))
    with pytest.raises(LineFileError) as info:
        webline.simulate(line, "1 h")
    assert info.value.key == "control.sample_rate"


def test_records_beyond_the_budget_name_record_interval() -> None:
    work = budget.estimate(ticks=10**9, substeps=1, every=1, columns=30)
    assert work.record_bytes == (10**9 + 2) * 30 * 8 > budget.MAX_RECORD_BYTES
    with pytest.raises(LineFileError, match="record_interval"):
        budget.check_work(load_line("hswl"), work, 1e-3)


@pytest.mark.parametrize(("key", "expected"), [
    ("rollers.1.drive.torque_lag", "rollers[1].drive.torque_lag"),
    ("spans.0.length", "spans[0].length"),
])
def test_the_fastest_mode_maps_to_its_key(key: str, expected: str) -> None:
    value = "1 us" if "lag" in key else "1 mm"
    assert budget.fastest_mode_key(load_line(hswl(**{key: value})))[0] == expected


# --- the Python API takes what the CLI takes -------------------------------------------------


def test_simulate_takes_units_and_quantities() -> None:
    plain = webline.simulate("hswl", 0.2, sample_rate=500.0, record_interval=0.01)
    texts = webline.simulate("hswl", "200 ms", sample_rate="500 Hz", record_interval="10 ms")
    quantity = webline.simulate(load_line("hswl"), ureg.Quantity(0.2, "s"),
                                sample_rate=ureg.Quantity(0.5, "kHz"))
    assert plain.settings == texts.settings
    assert plain.time[-1] == texts.time[-1] == quantity.time[-1] == pytest.approx(0.2)


def test_operating_point_and_linearize_take_units() -> None:
    line = load_line("hswl")
    a = webline.operating_point(line, "1 s")
    b = webline.operating_point("hswl", 1.0)
    assert a.time == b.time == 1.0
    assert list(a.torque) == list(b.torque) and list(a.tension) == list(b.tension)
    assert webline.linearize("hswl", "1 s").nstates == webline.linearize(line, 1.0).nstates


@pytest.mark.parametrize(("call", "name"), [
    (lambda: webline.simulate("hswl", "2 parsecs"), "duration"),
    (lambda: webline.simulate("hswl", -1.0), "duration"),
    (lambda: webline.simulate("hswl", 1.0, sample_rate="1 GHz"), "sample_rate"),
    (lambda: webline.simulate("hswl", 1.0, record_interval=[1]), "record_interval"),
    (lambda: webline.simulate(3), "line"),  # type: ignore[arg-type]
    (lambda: webline.linearize("hswl", "soon"), "t"),
    (lambda: webline.linearize("hswl", loop="half"), "loop"),  # type: ignore[arg-type]
    (lambda: webline.operating_point("hswl", "-1 s"), "t"),
    # no RK4 step, or a fraction of one, once ran a frozen line to an "ok" verdict
    (lambda: webline.simulate("hswl", 0.1, substeps=0), "substeps"),
    (lambda: webline.simulate("hswl", 0.1, substeps=-2), "substeps"),
    (lambda: webline.simulate("hswl", 0.1, substeps=1.5), "substeps"),
])
def test_a_wrong_argument_raises_argument_error_naming_it(call: Any, name: str) -> None:
    with pytest.raises(ArgumentError, match=rf"^{name}: "):
        call()
    assert ArgumentError.exit_code == 2


def test_a_bound_and_a_kind_read_as_english() -> None:
    with pytest.raises(ArgumentError, match=r"^t: must be >= 0, got '-1 s'$"):
        webline.operating_point("hswl", "-1 s")
    with pytest.raises(LineFileError, match=r"expected an angular frequency \(e\.g\. rad/s\)"):
        load_line("hswl").replace({"rollers.process.controller.tension_bandwidth": "5 m"})


def test_a_result_pickles_with_its_line_and_numbers() -> None:
    """README: a ``Result`` travels to another process whole (the report's process receives
    one): the same records, line and verdict come back."""
    import pickle

    import numpy as np

    import webline

    result = webline.simulate(webline.load_line("hswl").with_scenario("tension-step"), 0.2)
    back = pickle.loads(pickle.dumps(result))
    assert np.array_equal(back.states, result.states) and np.array_equal(back.time, result.time)
    assert back.line.spec == result.line.spec and back.status == result.status
