"""The chain's command-line options on a branched line (docs/branching.md, "Options and
scenario keys"): ``--set PATH=VALUE`` on run, show and analyze, ``run --format`` and
``--precision``."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from webline.cli import app
from webline.model.web_graph import load_branched

FILM_140 = "webs.film.spans.film_zone.tension=140 N"


def _run(*args: str):
    return CliRunner().invoke(app, list(args))


def test_run_set_a_zones_tension_holds_it_at_steady_state(tmp_path):
    import xarray as xr

    out = tmp_path / "run"
    result = _run("run", "laminator", "-d", "3", "--set", FILM_140, "-o", str(out))
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text("utf-8"))
    film = summary["webs"][0]["spans"]["film_zone"]
    # the film zone's loadcell now holds 140 N (its file says 120 N): its PI loop's integral
    # removes any steady error, so 3 s after the start the tension is 140 N to 0.1 N
    assert film["final_N"] == pytest.approx(140.0, abs=0.1)
    foil = summary["webs"][1]["spans"]["foil_zone"]
    assert foil["final_N"] == pytest.approx(60.0, abs=0.1)  # the other layer keeps its 60 N
    with xr.open_dataset(out / "results.nc") as ds:  # the run's file embeds the changed line
        assert "140 N" in ds.attrs["line_spec_toml"] or "140.0" in ds.attrs["line_spec_toml"]
        final = float(ds["tension"].sel(span="film_zone").isel(time=-1))
    assert final == pytest.approx(140.0, abs=0.1)


def test_run_set_applies_after_the_scenario(tmp_path):
    """layer-upset steps the film zone to 150 N at 2 s; a --set after it replaces the step."""
    out = tmp_path / "run"
    result = _run("run", "laminator", "-s", "layer-upset", "-d", "3", "--set",
                  "webs.film.spans.film_zone.tension=130 N", "-o", str(out))
    assert result.exit_code == 0, result.output
    film = json.loads((out / "summary.json").read_text("utf-8"))["webs"][0]["spans"]
    # a constant 130 N from the start: no step, the tension stays within 0.5 N of it
    assert film["film_zone"]["min_N"] > 129.5 and film["film_zone"]["max_N"] < 130.5


def test_show_set_changes_a_layers_stiffness_and_the_laminates_sum():
    result = _run("show", "laminator", "--set", "webs.film.web.ea=50 kN")
    assert result.exit_code == 0, result.output
    rows = {line.split("│")[1].strip(): line for line in result.output.splitlines()
            if line.count("│") > 5}
    assert "5e+04" in rows["film"]
    # a laminate's EA is the sum of its layers': 50 kN + 630 kN
    assert "6.8e+05" in rows["laminate"]


def test_analyze_set_moves_the_operating_point():
    result = _run("analyze", "laminator", "--json", "--set", FILM_140,
                  "--set", "rollers.unwind_film.radius=0.2 m")
    assert result.exit_code == 0, result.output
    payload = json.loads(result.output)
    spans = {r["span"]: r["tension"] for r in payload["operating_point"]["spans"]}
    assert spans["film_zone"] == pytest.approx(140.0, abs=1e-6)
    rollers = {r["roller"]: r for r in payload["operating_point"]["rollers"]}
    # the span equation (6.8) at rest, EA (v2 - v1) = T2 v2 - T1 v1 along the film: it
    # leaves its roll at the wound-in 100 N and reaches the nip (2.5 m/s) at the zone's
    # 140 N, so the roll of 0.2 m turns at 2.5 (EA + 100) / (EA + 140) / 0.2 = 12.49518 rad/s
    # (exact mass conservation, E-6.6; 12.49759 at the file's 120 N)
    ea = 103.5e3
    omega = 2.5 * (ea + 100) / (ea + 140) / 0.2
    assert rollers["unwind_film"]["omega_rad_s"] == pytest.approx(omega, rel=1e-9)


@pytest.mark.parametrize("command", ["run", "show", "analyze"])
@pytest.mark.parametrize(("setting", "words"), [
    ("webs.flim.web.ea=50 kN", ["webs.flim", "film"]),          # a typo: the closest name
    ("webs.film.web.ea=-5 kN", ["webs[0].web.ea"]),            # a value the schema refuses
    ("rollers.nip.radius=fast", ["rollers[4].radius"]),         # not a length
    ("webs.film.web.ea", ["--set", "PATH=VALUE"]),              # no value
    ("rollers.unwind_film.radius=50 mm", ["rollers[0].core_radius", "below the roll radius"]),
])
def test_a_bad_set_is_refused_in_one_line_naming_the_path(command, setting, words, tmp_path):
    args = [command, "laminator", "--set", setting]
    if command == "run":
        args += ["-d", "0.1", "-o", str(tmp_path / "o")]
    result = _run(*args)
    assert result.exit_code == 2, result.output
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    for word in words:
        assert word in result.stderr
    assert "Traceback" not in result.output
    assert not (tmp_path / "o").exists()  # nothing written for a refused run


def test_branched_line_replace_changes_a_value_and_keeps_the_rest():
    line = load_branched("laminator").with_scenario("roll-change")
    changed = line.replace({"webs.film.web.ea": "50 kN"})
    assert changed.materials[0].ea == 50e3 and line.materials[0].ea == 103.5e3
    assert changed.materials[2].ea == pytest.approx(680e3)  # the laminate: layers summed
    assert changed.roll_change == line.roll_change and changed.scenario == "roll-change"
    # a web gives its stiffness one way: modulus replaces the file's ea (E h w = EA)
    by_modulus = line.replace({"webs.film.web.modulus": "2 GPa"})
    assert by_modulus.materials[0].ea == pytest.approx(2e9 * 23e-6 * 1.0)


@pytest.fixture(scope="module")
def precisions(tmp_path_factory):
    """The laminator's layer upset written as float64 NetCDF, float32 NetCDF and CSV."""
    import xarray as xr

    root = tmp_path_factory.mktemp("formats")
    out = {}
    for name, extra in (("f64", []), ("f32", ["--precision", "float32"]),
                        ("csv", ["--format", "csv"])):
        result = _run("run", "laminator", "-s", "layer-upset", "-d", "2.5", "-q",
                      "-o", str(root / name), *extra)
        assert result.exit_code == 0, result.output
        out[name] = root / name
    with xr.open_dataset(out["f64"] / "results.nc") as f64, \
            xr.open_dataset(out["f32"] / "results.nc") as f32:
        yield f64.load(), f32.load(), out


def test_precision_float32_halves_the_signals_and_equals_float64_rounded(precisions):
    f64, f32, _ = precisions
    assert f32["time"].dtype == np.float64  # time stays float64, as the chain's file
    floats = [name for name in f64.data_vars if f64[name].dtype.kind == "f"]
    assert {"tension", "omega", "radius", "torque_cmd"} <= set(floats)
    for name in floats:
        assert f64[name].dtype == np.float64 and f32[name].dtype == np.float32, name
        # the same run rounded once to float32: equal bit for bit to float64 -> float32
        np.testing.assert_array_equal(f32[name].values, f64[name].values.astype(np.float32))
        assert f32[name].attrs["units"] == f64[name].attrs["units"]
    # every output embeds its inputs
    assert f32.attrs["line_spec_toml"] == f64.attrs["line_spec_toml"]


def test_format_csv_writes_each_signal_as_columns_with_its_unit(precisions):
    f64, _, out = precisions
    folder = out["csv"]
    assert (folder / "results.csv").exists() and not (folder / "results.nc").exists()
    header = (folder / "results.csv").read_text("utf-8").splitlines()[0].split(",")
    table = np.loadtxt(folder / "results.csv", delimiter=",", skiprows=1)
    assert header[0] == "time [s]"
    np.testing.assert_allclose(table[:, 0], f64["time"].values, rtol=1e-8)  # 9 digits
    column = header.index("tension[film_zone] [N]")
    # written with 9 significant digits: equal to the NetCDF's to 1 part in 1e8
    np.testing.assert_allclose(table[:, column],
                               f64["tension"].sel(span="film_zone").values, rtol=1e-8)
    # one column per signal and element (a zero-length dimension gives none)
    assert len(header) == 1 + sum(int(np.prod(f64[n].shape[1:])) for n in f64.data_vars)


def test_format_zarr_is_refused_as_the_chain_refuses_it(tmp_path):
    result = _run("run", "laminator", "-d", "0.1", "--format", "zarr", "-o", str(tmp_path / "o"))
    assert result.exit_code == 2 and "zarr" in result.output
