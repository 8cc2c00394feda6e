"""A study is its inputs (issue 22): the study record holds a hash of the resolved line and
webline's version, so ``--resume`` of a line edited since (or of a study of another webline)
is refused naming what changed, and ``--restart`` starts the study again on purpose."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import ArgumentError
from webline.spec.load import dump_spec

FRICTION = "rollers.process.friction"


def sweep_args(line_file, out) -> list[str]:
    return ["sweep", str(line_file), "--set", "web.ea=1900 lbf,2100 lbf", "-d", "0.2",
            "--out", str(out), "-q", "--workers", "1"]


@pytest.fixture
def line_file(tmp_path):
    path = tmp_path / "line.toml"
    path.write_text(dump_spec(webline.load_line("hswl").spec), encoding="utf-8")
    return path


def edit_friction(line_file, factor: float) -> None:
    """Scale the process roller's bearing friction in the file by ``factor``."""
    line = webline.load_line(line_file)
    friction = line.spec.rollers[2].friction * factor
    line_file.write_text(dump_spec(line.replace({FRICTION: friction}).spec), encoding="utf-8")


def test_resume_after_editing_the_line_file_is_refused_naming_the_file_and_key(
        line_file, tmp_path) -> None:
    out = tmp_path / "study"
    first = CliRunner().invoke(app, sweep_args(line_file, out))
    assert first.exit_code == 0, first.output
    record = json.loads((out / "chunks" / "study.json").read_text())
    assert record["webline_version"] == webline.__version__ and len(record["line_sha256"]) == 64
    before = {p.name: p.read_bytes() for p in (out / "chunks").iterdir()}

    edit_friction(line_file, 2.0)
    resumed = CliRunner().invoke(app, [*sweep_args(line_file, out), "--resume"])
    assert resumed.exit_code == 2, resumed.output
    said = resumed.output.strip()
    assert said.count("\n") == 0 and "Traceback" not in said  # one line
    assert str(line_file) in said and "changed" in said and FRICTION in said
    assert "--restart" in said
    # nothing of the study was touched
    assert {p.name: p.read_bytes() for p in (out / "chunks").iterdir()} == before

    # asked for, a new study of the edited line replaces it
    restarted = CliRunner().invoke(app, [*sweep_args(line_file, out), "--restart"])
    assert restarted.exit_code == 0, restarted.output
    new = json.loads((out / "chunks" / "study.json").read_text())
    assert new["line_sha256"] != record["line_sha256"]
    got = xr.load_dataset(out / "sweep.nc", engine="h5netcdf")
    want = webline.sweep(line_file, {"web.ea": ["1900 lbf", "2100 lbf"]}, duration=0.2,
                         workers=1)
    # the restarted study is the edited line's, case for case (the same compiled batch)
    np.testing.assert_array_equal(got.tension_rms_error.values, want.tension_rms_error.values)


def test_resume_with_the_same_line_in_other_words_goes_on(line_file, tmp_path) -> None:
    """Comments and layout are not the line: only the resolved values are hashed."""
    out = tmp_path / "study"
    assert CliRunner().invoke(app, sweep_args(line_file, out)).exit_code == 0
    line_file.write_text("# a comment\n" + line_file.read_text(), encoding="utf-8")
    resumed = CliRunner().invoke(app, [*sweep_args(line_file, out), "--resume"])
    assert resumed.exit_code == 0, resumed.output


def test_resume_of_a_study_from_another_webline_is_refused_naming_both_versions(
        tmp_path, monkeypatch) -> None:
    from webline.sim.sweeps import study_record

    values = {"web.ea": ["1900 lbf", "2100 lbf"]}
    webline.sweep("hswl", values, duration=0.2, workers=1, store=tmp_path)
    monkeypatch.setattr(study_record, "__version__", "99.0")
    with pytest.raises(ArgumentError, match=rf"webline {webline.__version__}.*99\.0"):
        webline.sweep("hswl", values, duration=0.2, workers=1, store=tmp_path, resume=True)


def test_resume_with_another_scenario_is_refused(tmp_path) -> None:
    """The scenario is part of the resolved line (and of the settings)."""
    values = {"web.ea": ["1900 lbf", "2100 lbf"]}
    webline.sweep("hswl", values, duration=0.2, workers=1, store=tmp_path,
                  scenario="tension-step")
    with pytest.raises(ArgumentError, match="scenario"):
        webline.sweep("hswl", values, duration=0.2, workers=1, store=tmp_path,
                      scenario="speed-change", resume=True)
