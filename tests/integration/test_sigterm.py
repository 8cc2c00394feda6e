"""A batch scheduler's stop (issue 23, item 5): SIGTERM during ``webline run`` is handled as
Ctrl-C is (tests/integration/test_run_outputs.py): what was computed is written whole, with
status interrupted, and the command exits 143 (128 + SIGTERM, as a shell reports a job killed
by it; Ctrl-C keeps 130)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import webline
from webline.files import TEMP_PREFIX

# serial: each test times a signal sent after a run has started (seconds of wall time)
pytestmark = [pytest.mark.skipif(os.name != "posix", reason="sends SIGTERM"),
              pytest.mark.serial]
ROOT = Path(__file__).resolve().parents[2]
HSWL = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")


def test_sigterm_during_a_run_writes_partial_results_and_exits_143(tmp_path) -> None:
    """Three hours of the HSWL at 10 kHz control (~20 s of wall time or more) stopped by
    ``kill -TERM`` after its first chunks: exit 143, the verdict says SIGTERM stopped it, a
    readable results.nc with status interrupted and less time than asked, the report
    written, no temporary file left."""
    webline.simulate("hswl", 0.01)  # the numba cache is warm for the subprocess
    line = tmp_path / "slow.toml"
    line.write_text(HSWL.replace('sample_rate = "1 kHz"', 'sample_rate = "10 kHz"', 1),
                    encoding="utf-8")
    out = tmp_path / "run"
    proc = subprocess.Popen(
        [sys.executable, "-c", "import sys; from webline.cli import main; "
         "sys.argv[0] = 'webline'; main()", "run", str(line), "-d", "3 h", "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "NUMBA_NUM_THREADS": "1", "PYTHONPATH": str(ROOT / "src")})
    assert proc.stderr is not None
    assert proc.stderr.readline().startswith("Simulating")  # the simulation is starting
    time.sleep(6.0)  # loading the compiled loop and the first chunks on a busy machine
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 143, stderr
    lines = stderr.strip().splitlines()
    assert any(t.startswith("verdict: interrupted: stopped by SIGTERM") for t in lines), stderr
    assert lines[-1] == f"what was computed until then is in {out}"
    assert "Traceback" not in stderr
    assert Path(stdout.strip().splitlines()[-1]) == (out / "report.html").resolve()
    with xr.open_dataset(out / "results.nc") as ds:
        assert ds.attrs["status"] == "interrupted"
        assert 0.0 < float(ds.time[-1]) < 3 * 3600.0
        assert np.isfinite(ds.tension.values).all()
    assert not [p for p in out.rglob("*") if p.name.startswith(TEMP_PREFIX)]


def _webline(*args: str, **popen: object) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-c", "import sys; from webline.cli import main; "
         "sys.argv[0] = 'webline'; main()", *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT / "src")}, **popen)


def test_sigterm_during_a_sweep_keeps_its_chunks_and_it_resumes(tmp_path) -> None:
    """``kill -TERM`` once a sweep's first chunk (256 cases) is stored: one line, exit 143,
    the chunk kept whole; ``--resume`` runs only the other two chunks and writes all 768
    cases."""
    from webline.sim.sweeps.chunks import chunk_path

    out = tmp_path / "sweep"
    args = ("sweep", "hswl", "--set", "web.ea=8 kN:10 kN:768", "-d", "1", "--workers", "1",
            "--out", str(out), "-q")
    webline.sweep("hswl", {"web.ea": ["9 kN"]}, duration=0.01)  # the batch is compiled
    proc = _webline(*args)
    first = chunk_path(out / "chunks", 0)
    deadline = time.monotonic() + 240
    while not first.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert first.exists() and proc.poll() is None, "the first chunk did not appear in time"
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 143, stderr
    # one line that says what --resume continues from (exit 143 says the signal was SIGTERM)
    assert stderr.strip().splitlines() == [
        f"error: interrupted: --resume will continue from 1 saved chunks of 3 in {out / 'chunks'}"]
    assert not chunk_path(out / "chunks", 2).exists()  # stopped before the end
    with xr.open_dataset(first) as chunk:
        assert chunk.sizes["case"] == 256
    stamp = first.stat().st_mtime_ns
    resumed = _webline(*args, "--resume")
    _, stderr = resumed.communicate(timeout=300)
    assert resumed.returncode == 0, stderr
    assert first.stat().st_mtime_ns == stamp  # the stored chunk was not run again
    with xr.open_dataset(out / "sweep.nc") as ds:
        # a grid: its cases over the swept path's dimension
        assert ds.status.size == 768 and set(ds.status.values.astype(str).ravel()) == {"ok"}
