"""Every study writes a report, in the units asked for (issue 23 item 3): ``webline sweep
--units`` shows the report's quantities as ``run --units`` does while ``sweep.nc`` stays SI,
and the report lists the cases with their parameters and statuses."""

from __future__ import annotations

import re

import numpy as np
import xarray as xr
from typer.testing import CliRunner

from webline.cli import app

LBF = 4.4482216152605  # [N]


def _sweep(tmp_path, *extra: str):
    return CliRunner().invoke(app, [
        "sweep", "hswl", "--set", "web.ea=1800 lbf,2200 lbf",
        "--set", "rollers.process.controller.tension_bandwidth=4,8", "-d", "0.3",
        "--out", str(tmp_path), "--workers", "1", *extra])


def test_sweep_units_imperial_shows_lbf_and_keeps_the_file_si(tmp_path) -> None:
    result = _sweep(tmp_path, "--units", "imperial")
    assert result.exit_code == 0, result.output
    html = (tmp_path / "report.html").read_text()
    # the parameter column and the metric in lbf; the web.ea values as written (1800 lbf),
    # to the 4 significant digits the table shows
    assert "web.ea [lbf]" in html and "RMS tension error [lbf]" in html
    assert ">1800<" in html and ">2200<" in html
    ds = xr.open_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    assert ds["web.ea"].attrs["units"] == "N" and ds.tension_rms_error.attrs["units"] == "N"
    np.testing.assert_allclose(ds["web.ea"].values, np.array([1800, 2200]) * LBF, rtol=1e-12)
    # the terminal's metrics table in lbf too
    assert "lbf" in result.output


def test_the_report_lists_every_case_with_its_parameters_and_status(tmp_path) -> None:
    result = _sweep(tmp_path)
    assert result.exit_code == 0, result.output
    html = (tmp_path / "report.html").read_text()
    table = html.split('id="sweep-cases"')[1].split("</table>")[0]
    rows = re.findall(r"<tr>(.*?)</tr>", table, flags=re.S)[1:]  # the header row first
    assert len(rows) == 4  # the 2 x 2 grid, in case order, each with its status
    cells = [re.findall(r"<td[^>]*>(.*?)</td>", row) for row in rows]
    assert [c[0] for c in cells] == ["0", "1", "2", "3"]
    assert [c[2] for c in cells] == ["4", "8", "4", "8"]  # the last path varies fastest
    assert all(c[3] == "ok" for c in cells)
    assert "web.ea [N]" in table  # SI by default


def test_per_width_units_of_a_study_that_changes_the_width_are_refused(tmp_path) -> None:
    result = CliRunner().invoke(app, [
        "sweep", "hswl", "--set", "web.width=0.2 m,0.3 m", "-d", "0.3", "--out",
        str(tmp_path), "--units", "si-per-width"])
    assert result.exit_code == 2
    assert "web.width" in result.output and "Traceback" not in result.output


def test_a_named_study_writes_a_report_with_its_findings_table_and_figures(tmp_path) -> None:
    import json

    folder = tmp_path / "sm"
    result = CliRunner().invoke(app, ["study", "solid-motion", "--quick", "--out", str(folder)])
    assert result.exit_code == 0, result.output
    html = (folder / "report.html").read_text()
    summary = (folder / "summary.txt").read_text().strip()
    assert summary.splitlines()[0] in html  # its findings, as summary.txt says them
    rows = (folder / "table.csv").read_text().strip().count("\n")  # rows below the header
    assert html.split('id="study-table"')[1].split("</table>")[0].count("<tr>") == rows + 1
    figures = sorted(p.name for p in folder.glob("*.png"))
    assert figures and html.count("src=\"data:image/png;base64,") == len(figures)
    listed = json.loads((folder / ".webline-manifest.json").read_text())["files"]
    assert "report.html" in listed  # webline's file: a rerun may replace it
