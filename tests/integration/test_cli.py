"""Every `webline` command: what it prints, its exit status, and bad input (exit 2, one line,
no traceback)."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app, progress_bar
from webline.units import display_factor

HSWL = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")
LBF_PER_N = display_factor("force", "imperial")[0]


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def assert_one_line_error(result, code: int, *fragments: str) -> None:
    """Exit ``code``, stderr is one 'error: ...' line holding ``fragments``, no traceback."""
    assert result.exit_code == code, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("error: ")
    for fragment in fragments:
        assert fragment in lines[0]
    assert "Traceback" not in result.output
    assert not isinstance(result.exception, Exception) or isinstance(result.exception,
                                                                       SystemExit)


def write(tmp_path: Path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return str(path)


BROKEN = {  # file name -> (file text, the key and the problem the message must name)
    "syntax.toml": ('name = "x"\n[web\n', ["(syntax)"]),
    "unknown_key.toml": (HSWL.replace('name = "hswl"', 'name = "hswl"\ncolour = "red"', 1),
                         ["colour", "unknown key"]),
    "negative_length.toml": (HSWL.replace('length = "33 ft"', 'length = "-3 m"', 1),
                             ["spans[1].length", "must be > 0"]),
    "bad_unit.toml": (HSWL.replace('length = "20 ft"', 'length = "20 lbf"', 1),
                      ["spans[0].length", "expected a length"]),
}


# --- version, lines, validate, show, analyze --------------------------------------------------


def test_version_prints_the_package_version():
    result = invoke("--version")
    assert result.exit_code == 0
    assert result.stdout.strip() == f"webline {webline.__version__}"


def test_no_arguments_shows_help_and_exits_2():
    result = invoke()
    assert result.exit_code == 2
    for command in ("run", "validate", "lines", "show", "analyze"):
        assert command in result.output


def test_lines_lists_hswl_and_its_scenarios():
    result = invoke("lines")
    assert result.exit_code == 0
    assert "hswl" in result.stdout
    for scenario in ("startup", "speed-change", "disturbance", "roll-change"):
        assert scenario in result.stdout


def test_validate_accepts_builtin_and_file(tmp_path):
    for source in ("hswl", write(tmp_path, "good.toml", HSWL)):
        result = invoke("validate", source)
        assert result.exit_code == 0, result.output
        assert result.stdout.startswith("ok: ")
        assert "5 rollers, 4 spans, 4 drives, 3 tension zones" in result.stdout


def test_show_imperial_shows_imperial_units_only():
    result = invoke("show", "hswl", "--units", "imperial")
    assert result.exit_code == 0
    out = result.stdout
    for text in ("14.35 lbf", "20 ft", "500 ft/min", "8 lb·ft²", "0.5 lbf·ft·s", "2000 lbf"):
        assert text in out
    assert " N·m" not in out and "m/s" not in out and " kg·m²" not in out
    for section in ("Rollers", "Spans", "Drives and controllers", "Tension zones", "Scenarios"):
        assert section in out


def test_show_si_is_the_default():
    out = invoke("show", "hswl").stdout
    assert "63.83 N" in out and "2.54 m/s" in out and "6.096 m" in out
    assert "lbf" not in out


def test_analyze_json_operating_point_and_modes():
    result = invoke("analyze", "hswl", "--json", "--units", "imperial")
    assert result.exit_code == 0
    data = json.loads(result.stdout)
    op = data["operating_point"]
    assert op["units"]["force"] == "lbf" and op["units"]["speed"] == "ft/min"
    assert op["line_speed"] == pytest.approx(500.0)
    for span in ("span1", "span2", "span3b"):  # the loadcell spans sit at their reference
        assert op["tension"][span] == pytest.approx(14.35, rel=1e-9)
    assert op["nodes"]["idler"]["torque"] is None
    assert op["nodes"]["unwind"]["torque"] < 0 < op["nodes"]["rewind"]["torque"]  # unwind brakes
    modes = data["closed_loop_modes"]
    order = webline.linearize("hswl").A.shape[0]
    assert sum(2 if m["eigenvalue_imag"] > 0 else 1 for m in modes) == order
    for m in modes:
        lam = complex(m["eigenvalue_real"], m["eigenvalue_imag"])
        assert m["natural_frequency_rad_s"] == pytest.approx(abs(lam))
        assert m["natural_frequency_hz"] == pytest.approx(abs(lam) / (2 * math.pi))
        assert m["damping_ratio"] == pytest.approx(-lam.real / abs(lam))
        assert 0 < m["damping_ratio"] <= 1  # the tuned line is stable


def test_analyze_table_has_hz_and_rad_s_and_damping():
    result = invoke("analyze", "hswl")
    assert result.exit_code == 0
    for header in ("ωn [rad/s]", "fn [Hz]", "ζ", "equilibrium motor torque [N·m]"):
        assert header in result.stdout


def test_analyze_startup_from_rest_is_analysed_at_line_speed():
    data = json.loads(invoke("analyze", "hswl", "-s", "startup", "--json").stdout)
    assert data["operating_point"]["time_s"] == pytest.approx(11.0)  # end of the ramp
    assert data["operating_point"]["line_speed"] == pytest.approx(2.54)


# --- bad input --------------------------------------------------------------------------------


@pytest.mark.parametrize("command", ["validate", "show", "analyze", "run"])
@pytest.mark.parametrize("name", sorted(BROKEN))
def test_broken_line_file_exits_2_with_one_line(tmp_path, command, name):
    text, fragments = BROKEN[name]
    result = invoke(command, write(tmp_path, name, text))
    assert_one_line_error(result, 2, name, *fragments)


@pytest.mark.parametrize("command", ["validate", "show", "analyze", "run"])
def test_missing_file_exits_2(tmp_path, command):
    missing = str(tmp_path / "nowhere.toml")
    assert_one_line_error(invoke(command, missing), 2, "nowhere.toml", "no such file")


def test_unknown_builtin_line_exits_2():
    assert_one_line_error(invoke("show", "no-such-line"), 2, "no-such-line",
                          "built-in: converter, hswl, laminator, rockwell, slitter")


@pytest.mark.parametrize("command", ["run", "show", "analyze"])
def test_unknown_scenario_exits_2(command):
    result = invoke(command, "hswl", "--scenario", "nope")
    assert_one_line_error(result, 2, "scenarios.nope", "no such scenario", "speed-change")


@pytest.mark.parametrize("value", ["-3", "0", "3 parsecs", "5 lbf"])
def test_bad_duration_exits_2(value, tmp_path):
    result = invoke("run", "hswl", "--duration", value, "--out", str(tmp_path / "o"))
    assert_one_line_error(result, 2, "--duration")


def test_bad_choice_exits_2():
    for args in (["run", "--units", "metric"], ["run", "--format", "xlsx"],
                 ["show", "hswl", "-u", "cgs"]):
        result = invoke(*args)
        assert result.exit_code == 2
        assert "Traceback" not in result.output


def test_output_folder_that_is_a_file_exits_2(tmp_path):
    blocker = tmp_path / "blocker"
    blocker.write_text("")
    for out in (blocker, blocker / "sub"):
        result = invoke("run", "hswl", "-d", "0.1", "--out", str(out))
        assert_one_line_error(result, 2, str(out), "cannot write to the output folder")


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0,
                    reason="root may write into read-only folders")
def test_read_only_output_folder_exits_2(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        result = invoke("run", "hswl", "-d", "0.1", "--out", str(locked))
        assert_one_line_error(result, 2, "cannot write", "Permission denied")
    finally:
        locked.chmod(0o700)


def test_console_script_prints_no_traceback(tmp_path):
    script = Path(sys.executable).with_name("webline")
    if not script.exists():
        pytest.skip("webline console script not installed next to this Python")
    bad = write(tmp_path, "negative_length.toml", BROKEN["negative_length.toml"][0])
    done = subprocess.run([str(script), "validate", bad], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2
    assert done.stdout == ""
    assert done.stderr.strip().count("\n") == 0
    assert "spans[1].length: must be > 0" in done.stderr


# --- run ---------------------------------------------------------------------------------------


def test_run_quiet_csv_prints_only_the_report_path(tmp_path):
    out = tmp_path / "run"
    result = invoke("run", "hswl", "-d", "1", "--format", "csv", "--out", str(out), "-q")
    assert result.exit_code == 0, result.output
    assert result.stderr == ""
    lines = result.stdout.strip().splitlines()
    assert len(lines) == 1
    report = Path(lines[0])
    assert report.is_absolute() and report == (out / "report.html").resolve()
    assert report.stat().st_size > 10_000
    header = (out / "results.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "time [s]" and "tension[span1] [N]" in header
    data = np.loadtxt(out / "results.csv", delimiter=",", skiprows=1)
    assert data[-1, 0] == pytest.approx(1.0)
    assert not (out / "results.nc").exists()


def test_run_that_fails_keeps_partial_results_and_exits_1(tmp_path):
    # an unwind roll holding ~4.8 m of web empties after ~1.9 s at 500 ft/min
    almost_empty = HSWL.replace('radius = "1.25 ft"', 'radius = "3.005 in"', 1)
    out = tmp_path / "fail"
    result = invoke("run", write(tmp_path, "empty.toml", almost_empty), "-d", "5",
                    "--out", str(out))
    assert result.exit_code == 1
    said = result.stderr.strip().splitlines()
    verdict = next(line for line in said if line.startswith("verdict: "))
    assert verdict.startswith("verdict: failed: the unwind roll ran out of web (reached its "
                              "core) at t = ")
    assert said[-1] == f"what was computed until then is in {out}"
    assert "Traceback" not in result.output
    assert result.stdout.strip().splitlines()[-1] == str((out / "report.html").resolve())
    assert "Span tension" in result.stdout  # the summary is still printed
    written = json.loads((out / "summary.json").read_text())
    summary = written["summary"]
    assert summary["status"] == "failed"  # never reported as another failure:
    assert [f["kind"] for f in written["verdict"]["findings"] if f["level"] == "failed"] == [
        "unwind_empty"]
    assert 1.0 < summary["duration_s"] < 3.0
    import xarray as xr

    with xr.open_dataset(out / "results.nc") as ds:
        assert ds.attrs["status"] == "failed"
        assert float(ds.time[-1]) == pytest.approx(summary["duration_s"])
    assert "run stopped early" in (out / "report.html").read_text().lower()


def test_progress_bar_reports_fractions_or_is_off():
    with progress_bar(False, "x") as callback:
        assert callback is None
    with progress_bar(True, "x") as callback:
        assert callback is not None
        for fraction in (0.0, 0.5, 1.0):
            callback(fraction)


def test_imperial_summary_equals_si_times_factor(runs):
    """`run --units imperial` prints and stores the same summary as SI, in lbf and ft/min."""
    si, imperial = (json.loads((runs[u].out / "summary.json").read_text())["summary"]
                    for u in ("si", "imperial"))
    assert imperial["units"] == {"tension": "lbf", "speed": "ft/min", "torque": "lbf*ft"}
    for span, stats in si["spans"].items():
        for key, value in stats.items():
            assert imperial["spans"][span][key] == pytest.approx(value * LBF_PER_N, rel=1e-12)
    fpm = display_factor("speed", "imperial")[0]
    assert imperial["drives"]["master"]["max_abs_error"] == pytest.approx(
        si["drives"]["master"]["max_abs_error"] * fpm, rel=1e-12)
    assert imperial["spans"]["span1"]["reference"] == pytest.approx(14.35, rel=1e-9)
    printed_si, printed_imperial = runs["si"].stdout, runs["imperial"].stdout
    assert "[lbf]" in printed_imperial and "[ft/min]" in printed_imperial
    assert "[N]" not in printed_imperial and "[m/s]" not in printed_imperial
    assert "[N]" in printed_si and "[m/s]" in printed_si


def test_run_reports_progress_on_stderr(runs):
    assert "Simulated 2 s of hswl" in runs["si"].stderr
