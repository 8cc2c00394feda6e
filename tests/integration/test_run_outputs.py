"""`webline run` writes safely and wholly (issue 11, item 4): default folders from sanitised
names, TeX-like names in every figure, NetCDF-4 with CF attributes, reruns without stale files,
links and foreign folders refused, Ctrl-C (exit 130) with readable partial results."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.files import TEMP_PREFIX
from webline.report.outputs import MANIFEST
from webline.spec.load import spec_from_dict

HSWL = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")
FIGURES = {"schematic", "tension", "speed", "torque", "rolls", "poles"}


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def renamed(line_name: str) -> str:
    """hswl with the line, the master roller and the first span renamed (TOML literal strings,
    so backslashes stay as written)."""
    return (HSWL.replace('name = "hswl"', f"name = '{line_name}'", 1)
            .replace('name = "master"', "name = '$m_1^2$'", 1)
            .replace('name = "span1"', "name = '_$a$ 100%'", 1))


def files_in(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file()}


@pytest.mark.parametrize("line_name", ["../../x", "/tmp/x", r"$\frac{$"])
def test_path_like_and_tex_names_write_inside_out_with_every_figure(tmp_path, monkeypatch,
                                                                      line_name):
    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    (work / "line.toml").write_text(renamed(line_name), encoding="utf-8")
    result = invoke("run", "line.toml", "-d", "0.2", "-q", "--svg")
    assert result.exit_code == 0, result.output
    [folder] = list((work / "out").iterdir())
    assert Path(result.stdout.strip()) == (folder / "report.html").resolve()
    assert files_in(tmp_path) - {"a/b/line.toml"} == {
        f"a/b/out/{folder.name}/{name}" for name in files_in(folder)}  # nothing outside out/
    figures = files_in(folder / "figures")
    assert figures == {f"{k}.{ext}" for k in FIGURES for ext in ("png", "svg")}
    svg = (folder / "figures" / "schematic.svg").read_text()
    assert "m_1^2" in svg  # drawn as text, not as mathtext (which would drop the ^ and _)


def test_netcdf_is_compressed_cf_and_keeps_its_inputs(tmp_path):
    out64, out32 = tmp_path / "f64", tmp_path / "f32"
    assert invoke("run", "hswl", "-d", "2", "-q", "--out", str(out64)).exit_code == 0
    result = invoke("run", "hswl", "-d", "2", "-q", "--out", str(out32), "--precision", "float32")
    assert result.exit_code == 0, result.output
    with xr.open_dataset(out64 / "results.nc") as d64, xr.open_dataset(out32 / "results.nc") as d32:
        assert d64.attrs["Conventions"].startswith("CF-") and d64.attrs["title"]
        assert d64.attrs["history"] and d64.attrs["source"].startswith("webline")
        assert d64.attrs["webline_version"] == webline.__version__
        spec = spec_from_dict(tomllib.loads(d64.attrs["line_spec_toml"]))
        assert spec == webline.load_line("hswl").spec  # the embedded line round-trips
        assert d64.time.attrs["standard_name"] == "time" and d64.time.attrs["units"] == "s"
        for name, var in d64.data_vars.items():
            assert var.attrs["long_name"], name
            assert "units" in var.attrs or "flag_meanings" in var.attrs, name
        assert d64.tension.encoding["zlib"] or d64.tension.encoding.get("compression")
        assert d64.tension.dtype == np.float64 and d32.tension.dtype == np.float32
        assert d32.time.dtype == np.float64  # time keeps full precision
        # float32 keeps ~7 significant digits of a tension of ~64 N
        np.testing.assert_allclose(d32.tension, d64.tension, rtol=1e-6, atol=0)
    assert (out32 / "results.nc").stat().st_size < (out64 / "results.nc").stat().st_size


def test_rerun_replaces_previous_files_and_leaves_no_stale_ones(tmp_path):
    out = tmp_path / "run"
    assert invoke("run", "hswl", "-d", "0.2", "-q", "--out", str(out)).exit_code == 0
    first = files_in(out)
    assert "results.nc" in first and MANIFEST in first
    (out / "my-notes.txt").write_text("kept")  # not webline's: never removed
    result = invoke("run", "hswl", "-d", "0.2", "-q", "--out", str(out), "--format", "csv")
    assert result.exit_code == 0, result.output
    assert files_in(out) == (first - {"results.nc"}) | {"results.csv", "my-notes.txt"}
    assert not any(name.startswith(TEMP_PREFIX) for name in os.listdir(out))


def test_foreign_non_empty_folder_needs_force(tmp_path):
    (tmp_path / "thesis.tex").write_text("mine")
    result = invoke("run", "hswl", "-d", "0.2", "-q", "--out", str(tmp_path))
    assert result.exit_code == 2 and "--force" in result.stderr
    assert os.listdir(tmp_path) == ["thesis.tex"]
    result = invoke("run", "hswl", "-d", "0.2", "-q", "--out", str(tmp_path), "--force")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "thesis.tex").read_text() == "mine"


@pytest.mark.skipif(os.name != "posix", reason="symbolic links")
def test_symlinked_folder_or_file_is_refused(tmp_path):
    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "link").symlink_to(real)
    result = invoke("run", "hswl", "-d", "0.2", "-q", "--out", str(tmp_path / "link"))
    assert result.exit_code == 2 and "symbolic link" in result.stderr
    assert list(real.iterdir()) == []
    out = tmp_path / "run"
    assert invoke("run", "hswl", "-d", "0.2", "-q", "--out", str(out)).exit_code == 0
    victim = tmp_path / "victim"
    victim.write_text("keep")
    (out / "results.nc").unlink()
    (out / "results.nc").symlink_to(victim)
    result = invoke("run", "hswl", "-d", "0.2", "-q", "--out", str(out))
    assert result.exit_code == 2, result.output
    assert "symbolic link" in result.stderr and "Traceback" not in result.output
    assert victim.read_text() == "keep"


@pytest.mark.skipif(os.name != "posix", reason="sends SIGINT")
@pytest.mark.serial  # timed: needs the CPU to itself
def test_sigint_during_a_long_run_writes_partial_results_and_exits_130(tmp_path):
    """Three hours of the HSWL at 10 kHz control (~20 s of wall time or more), interrupted
    after its first chunks: exit 130, a readable results.nc with status interrupted and less
    time than asked, no temporary file left."""
    webline.simulate("hswl", 0.01)  # the numba cache is warm for the subprocess
    line = tmp_path / "slow.toml"
    assert 'sample_rate = "1 kHz"' in HSWL
    line.write_text(HSWL.replace('sample_rate = "1 kHz"', 'sample_rate = "10 kHz"', 1),
                    encoding="utf-8")
    assert webline.load_line(str(line)).spec.control.sample_rate == 10000
    out = tmp_path / "run"
    script = Path(sys.executable).with_name("webline")
    if not script.exists():
        pytest.skip("webline console script not installed next to this Python")
    proc = subprocess.Popen(
        [str(script), "run", str(line), "-d", "3 h", "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "NUMBA_NUM_THREADS": "1"})
    assert proc.stderr is not None
    assert proc.stderr.readline().startswith("Simulating")  # the simulation is starting
    time.sleep(3.0)  # loading the compiled loop and the first chunks
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 130, stderr
    lines = stderr.strip().splitlines()
    assert any(t.startswith("verdict: interrupted: interrupted by the user") for t in lines)
    assert lines[-1] == f"what was computed until then is in {out}"
    assert "Traceback" not in stderr
    assert Path(stdout.strip().splitlines()[-1]) == (out / "report.html").resolve()
    with xr.open_dataset(out / "results.nc") as ds:
        assert ds.attrs["status"] == "interrupted"
        assert 0.0 < float(ds.time[-1]) < 3 * 3600.0
        assert set(ds.data_vars) >= {"tension", "speed", "torque"}
        assert np.isfinite(ds.tension.values).all()
    assert not [p for p in out.rglob("*") if p.name.startswith(TEMP_PREFIX)]


def _run_files(folder: Path) -> dict[str, bytes]:
    """Every file of a run folder but the results (their HDF5 header holds its write time),
    the report's footer time blanked."""
    out = {}
    for path in sorted(folder.rglob("*")):
        if path.is_file() and path.name != "results.nc":
            data = path.read_bytes()
            if path.name == "report.html":
                data = re.sub(rb"generated \d{4}-\d\d-\d\d \d\d:\d\d UTC", b"generated", data)
            out[str(path.relative_to(folder))] = data
    return out


@pytest.mark.serial  # xdist's worker runs an I/O thread: can_fork() is False there
def test_the_report_process_writes_what_the_command_writes_itself(tmp_path, monkeypatch) -> None:
    """``webline run`` hands its report to a copy forked when it starts (report.early); the
    files, the manifest included, are byte for byte those it writes without the copy."""
    from webline.report import early

    if not early.can_fork():
        pytest.skip("no fork, or one core: the command writes its report itself")
    replies = []
    collect = early.Reporter.collect

    def spy(self, folder):
        replies.append(collect(self, folder))
        return replies[-1]

    monkeypatch.setattr(early.Reporter, "collect", spy)
    args = ("run", "hswl", "-s", "tension-step", "-d", "2.5", "-q", "--out")
    assert invoke(*args, str(tmp_path / "copy")).exit_code == 0
    assert len(replies) == 1 and replies[0] is not None, "the copy wrote the report"
    monkeypatch.setattr(early, "can_fork", lambda: False)
    assert invoke(*args, str(tmp_path / "here")).exit_code == 0
    copy, here = _run_files(tmp_path / "copy"), _run_files(tmp_path / "here")
    assert set(copy) == set(here) and len(copy) >= 9  # 6 figures, summary, report, manifest
    assert copy == here


def test_a_failing_report_process_leaves_the_report_to_the_command(tmp_path, monkeypatch) -> None:
    """Whatever goes wrong in the copy (here it dies at once), the command writes the report
    itself: nothing is lost, and no process is left behind, also when the run never starts."""
    import multiprocessing

    from webline.report import early

    monkeypatch.setattr(early, "_serve", lambda conn, parent_end: os._exit(3))
    assert invoke("run", "hswl", "-d", "1", "-q", "--out", str(tmp_path / "run")).exit_code == 0
    names = set(_run_files(tmp_path / "run"))
    assert {"report.html", "summary.json"} | {f"figures/{f}.png" for f in FIGURES} <= names
    monkeypatch.undo()
    bad = invoke("run", "hswl", "--set", "web.ea=-3 N", "--out", str(tmp_path / "bad"))
    assert bad.exit_code == 2
    assert not multiprocessing.active_children()
