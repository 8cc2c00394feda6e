"""``webline sweep`` (issue 14): a grid and a Monte Carlo study from the command line write a
results file with one row per case and an HTML report; bad input is one line, exit 2."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from webline.cli import app

LBF = 4.4482216152605  # [N]


def test_grid_writes_results_and_report(tmp_path) -> None:
    result = CliRunner().invoke(app, [
        "sweep", "hswl", "--set", "web.ea=1800 lbf:2200 lbf:3",
        "--set", "rollers.process.controller.tension_bandwidth=4,8", "-d", "0.5",
        "--out", str(tmp_path), "--workers", "1"])
    assert result.exit_code == 0, result.output
    ds = xr.open_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    # the file holds the grid as webline.sweep returns it: a dimension per path
    assert ds.tension_rms_error.dims[:2] == ("web.ea",
                                             "rollers.process.controller.tension_bandwidth")
    assert ds.status.shape == (3, 2)
    # start:stop:n includes both ends, in the unit written
    np.testing.assert_allclose(ds["web.ea"].values, [1800 * LBF, 2000 * LBF, 2200 * LBF],
                               rtol=1e-9)
    html = (tmp_path / "report.html").read_text()
    assert 'id="sweep-status"' in html and 'id="fig-sweep-heatmap"' in html


def test_monte_carlo_report_has_histogram(tmp_path) -> None:
    result = CliRunner().invoke(app, [
        "sweep", "hswl", "--set", "web.ea=normal(2000 lbf, 10 %)", "--samples", "8",
        "--seed", "4", "-d", "0.3", "--out", str(tmp_path), "-q"])
    assert result.exit_code == 0, result.output
    assert 'id="fig-sweep-hist"' in (tmp_path / "report.html").read_text()


def test_bad_distribution_is_one_line_exit_2(tmp_path) -> None:
    result = CliRunner().invoke(app, [
        "sweep", "hswl", "--set", "web.ea=gauss(1, 2)", "--samples", "3", "--out",
        str(tmp_path)])
    assert result.exit_code == 2
    assert result.output.strip().count("\n") == 0 and "web.ea" in result.output


def test_samples_out_of_range_are_one_line_exit_2_before_running(tmp_path) -> None:
    result = CliRunner().invoke(app, [
        "sweep", "hswl", "--set", "web.ea=normal(9 kN, 60 %)", "--samples", "50", "--seed", "1",
        "-d", "0.3", "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert result.output.strip().count("\n") == 0
    assert "web.ea: the samples of normal(9 kN, 60 %)" in result.output
    assert not (tmp_path / "sweep.nc").exists()


def test_resume_reuses_the_stored_chunks(tmp_path) -> None:
    args = ["sweep", "hswl", "--set", "web.ea=1900 lbf,2100 lbf", "-d", "0.3", "--out",
            str(tmp_path), "-q"]
    assert CliRunner().invoke(app, args).exit_code == 0
    first = xr.load_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 2 and "--resume" in again.output
    chunk = tmp_path / "chunks" / "chunk-000000.nc"
    stamp = chunk.stat().st_mtime_ns
    assert CliRunner().invoke(app, [*args, "--resume"]).exit_code == 0
    assert chunk.stat().st_mtime_ns == stamp  # nothing recomputed
    second = xr.load_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    np.testing.assert_array_equal(first.tension_rms_error.values,
                                  second.tension_rms_error.values)


def test_output_folder_is_listed_and_a_foreign_folder_refused(tmp_path) -> None:
    """The sweep's folder is managed as a run's (report.outputs): results, report and the
    chunk store in its manifest; a non-empty folder webline did not write is refused (exit 2,
    nothing written) unless --force, which leaves the user's files alone."""
    args = ["sweep", "hswl", "--set", "web.ea=1900 lbf,2100 lbf", "-d", "0.2", "-q"]
    assert CliRunner().invoke(app, [*args, "--out", str(tmp_path / "a")]).exit_code == 0
    listed = json.loads((tmp_path / "a" / ".webline-manifest.json").read_text())["files"]
    assert listed == ["chunks/chunk-000000.nc", "chunks/study.json", "report.html", "sweep.nc"]

    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("keep me")
    refused = CliRunner().invoke(app, [*args, "--out", str(foreign)])
    assert refused.exit_code == 2 and "webline did not write it" in refused.output
    assert sorted(p.name for p in foreign.iterdir()) == ["notes.txt"]
    assert CliRunner().invoke(app, [*args, "--out", str(foreign), "--force"]).exit_code == 0
    assert (foreign / "notes.txt").read_text() == "keep me"
    assert (foreign / "sweep.nc").exists()


@pytest.mark.parametrize("extra, message", [
    (["--samples", "0"], "--samples"), (["--workers", "0"], "--workers"),
    (["-d", "-1"], "--duration: must be > 0 s"), (["-d", "0"], "--duration: must be > 0 s")])
def test_no_case_no_thread_or_no_time_is_exit_2_before_anything_is_written(
        tmp_path, extra, message) -> None:
    result = CliRunner().invoke(app, ["sweep", "hswl", "--set", "web.ea=uniform(8 kN, 9 kN)",
                                      "--samples", "2", "--out", str(tmp_path / "o"), *extra])
    assert result.exit_code == 2 and message in result.output
    assert not (tmp_path / "o").exists()


def test_duration_reads_as_runs_does(tmp_path) -> None:
    """A plain number is seconds, scientific notation included (it was once refused as 'not
    a time')."""
    result = CliRunner().invoke(app, ["sweep", "hswl", "--set", "web.ea=8 kN", "-d", "2e-1",
                                      "-q", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert xr.load_dataset(tmp_path / "sweep.nc", engine="h5netcdf").attrs["duration"] == 0.2


def test_a_grid_with_a_choice_plots_a_line_per_choice_in_the_parameters_units(tmp_path) -> None:
    """One numeric parameter and a choice: the metric against the number, one line per
    choice (not the choices' cases joined into one zig-zag line, nor a histogram); the axis
    and the results file carry the parameter's unit from the line file's range table."""
    result = CliRunner().invoke(app, [
        "sweep", "hswl", "--set", "rollers.process.controller.tension_bandwidth=4,8",
        "--set", "rollers.unwind.drive.feedback=load,motor", "-d", "0.2", "-q",
        "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    html = (tmp_path / "report.html").read_text()
    assert 'id="fig-sweep-metric"' in html and 'id="fig-sweep-hist"' not in html
    assert "a line per value of rollers.unwind.drive.feedback" in html
    ds = xr.load_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    assert ds["rollers.process.controller.tension_bandwidth"].attrs["units"] == "rad/s"
    assert "units" not in ds["rollers.unwind.drive.feedback"].attrs


def test_values_are_toml_where_they_can_be(tmp_path) -> None:
    """--set PATH=v1,v2 reads each value as run's --set does: inline tables (their commas do
    not split), booleans, quoted strings; numbers and quantities as before."""
    from webline.cli_sweep import parse_values

    assert parse_values("x", '{type = "adaptive", leakage = 0.1},{type = "state_feedback"}') == [
        {"type": "adaptive", "leakage": 0.1}, {"type": "state_feedback"}]
    assert parse_values("x", '8000, 9 kN,true,"a,b"') == [8000.0, "9 kN", True, "a,b"]
    result = CliRunner().invoke(app, [
        "sweep", "hswl", "--set",
        'rollers.process.controller={type="state_feedback"},{type="adaptive"}', "-d", "0.2",
        "-q", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    ds = xr.load_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    labels = ds["rollers.process.controller"].values
    assert 'type = "state_feedback"' in labels[0] and 'type = "adaptive"' in labels[1]


def test_monte_carlo_verdict_shares_carry_their_exact_interval() -> None:
    """0 failures in 10 draws is not a probability of 0: the table gives 0.0 % to 30.8 %
    (1 - 0.025^(1/10)); a grid sweep, which samples nothing, gives shares only."""
    from webline.report.sweep_report import status_table

    ds = xr.Dataset({"status": ("case", np.array(["ok"] * 9 + ["warning"]))},
                    attrs={"mode": "monte_carlo"})
    rows = {row[0]: row for row in status_table(ds).rows}
    assert rows["unstable or failed"] == ("unstable or failed", "0", "0.0%", "0.0% to 30.8%")
    assert rows["warning"][1:3] == ("1", "10.0%")
    grid = status_table(ds.assign_attrs(mode="grid"))
    assert len(grid.columns) == 3 and "unstable or failed" not in {r[0] for r in grid.rows}
