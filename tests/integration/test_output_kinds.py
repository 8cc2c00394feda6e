"""Folders belong to one kind of output (issue 22): ``webline run`` into a sweep's folder
does not delete the study, nor a sweep a run's files, without ``--force``; and ``--force``
never touches a file webline did not write (one its manifest does not list)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from webline.cli import app
from webline.files import OutputError
from webline.report.outputs import MANIFEST, OutputFolder

SWEEP = ["sweep", "hswl", "--set", "web.ea=1900 lbf,2100 lbf", "-d", "0.1", "-q",
         "--workers", "1"]
RUN = ["run", "hswl", "-d", "0.1", "-q"]


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def contents(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (relative path: bytes)."""
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def test_a_run_into_a_sweeps_folder_leaves_the_study_whole(tmp_path) -> None:
    out = tmp_path / "study"
    assert invoke(*SWEEP, "--out", str(out)).exit_code == 0
    before = contents(out)
    result = invoke(*RUN, "--out", str(out))
    assert result.exit_code == 2, result.output
    said = result.output.strip()
    assert said.count("\n") == 0 and "webline sweep" in said and "--force" in said
    assert contents(out) == before  # not a byte of the study changed

    # --force: the run takes the folder over and removes the study's files, which the
    # manifest lists as webline's (docs/sweeps.md says so)
    forced = invoke(*RUN, "--out", str(out), "--force")
    assert forced.exit_code == 0, forced.output
    assert not (out / "sweep.nc").exists() and not list((out / "chunks").glob("*"))
    manifest = json.loads((out / MANIFEST).read_text())
    assert manifest["kind"] == "run" and "results.nc" in manifest["files"]


def test_a_sweep_into_a_runs_folder_leaves_the_run_whole(tmp_path) -> None:
    out = tmp_path / "run"
    assert invoke(*RUN, "--out", str(out)).exit_code == 0
    before = contents(out)
    result = invoke(*SWEEP, "--out", str(out))
    assert result.exit_code == 2, result.output
    assert "webline run" in result.output and "--force" in result.output
    assert contents(out) == before


@pytest.mark.parametrize(("command", "theirs"), [(RUN, "report.html"), (SWEEP, "sweep.nc")])
def test_force_never_overwrites_a_file_webline_did_not_write(tmp_path, command,
                                                             theirs) -> None:
    """A user's file with the name of one webline writes: refused up front (exit 2, nothing
    written), also with --force, which writes beside the user's other files."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / theirs).write_text("my own file")
    (out / "notes.txt").write_text("keep me")
    before = contents(out)
    result = invoke(*command, "--out", str(out), "--force")
    assert result.exit_code == 2, result.output
    assert theirs in result.output and "did not write" in result.output
    assert contents(out) == before


def test_a_file_the_manifest_does_not_list_is_never_overwritten(tmp_path) -> None:
    """In a run's own folder the user drops a results.csv; a rerun that would write one
    refuses (the manifest lists results.nc, not it) and leaves it as it was."""
    out = tmp_path / "run"
    assert invoke(*RUN, "--out", str(out)).exit_code == 0
    (out / "results.csv").write_text("my measurements")
    result = invoke(*RUN, "--out", str(out), "--format", "csv", "--force")
    assert result.exit_code == 2, result.output
    assert "results.csv" in result.output
    assert (out / "results.csv").read_text() == "my measurements"


def test_each_kind_of_output_keeps_to_its_folder(tmp_path) -> None:
    """run, sweep and each named study are kinds of their own; a folder of another kind is
    refused before anything is written, and taken over only with force."""
    folder = OutputFolder.open(tmp_path / "f", kind="study robustness")
    folder.claim("table.csv").write_text("x")
    folder.finish()
    for other in ("run", "sweep", "study belt-step"):
        with pytest.raises(OutputError, match="webline study robustness"):
            OutputFolder.open(tmp_path / "f", kind=other)
    OutputFolder.open(tmp_path / "f", kind="study robustness")  # its own kind: fine
    taken = OutputFolder.open(tmp_path / "f", kind="run", force=True)
    assert [p.name for p in taken.finish()] == ["table.csv"]  # webline's file, removed
