"""A study or run that cannot go on ends in one line naming the cause and what to do (issue 22,
item 6): a full disk (files left whole, the sweep resumed once space is back), a damaged saved
chunk, workers that all die, a scheduler address that is no scheduler, mismatched --zip values
and absurdly nested --set values; exit 2 for bad input, 1 for a failed study or run."""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import threading
import time
import uuid
from pathlib import Path

import pytest
import xarray as xr
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import ArgumentError, StudyError

STUDY = ["sweep", "hswl", "--set", "web.ea=normal(9 kN, 5 %)", "--samples", "12", "--seed", "3",
         "-d", "0.05", "--workers", "1", "-q"]


def _one_line_error(output: str) -> str:
    lines = [line for line in output.strip().splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), output
    return lines[0]


def _mount_tmpfs(where: Path, size: str) -> bool:
    """Mount a tmpfs of ``size`` at ``where``; False where this process may not mount."""
    where.mkdir(parents=True, exist_ok=True)
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)],
                          capture_output=True, check=False) if shutil.which("mount") else None
    return done is not None and done.returncode == 0


@pytest.fixture
def small_disk(tmp_path):
    """A ~300 kB file system (a real tmpfs), unmounted after the test; skipped with the
    reason where mounting is not permitted (no root, a container without CAP_SYS_ADMIN)."""
    where = tmp_path / f"disk-{uuid.uuid4().hex[:6]}"
    if not _mount_tmpfs(where, "300k"):
        pytest.skip("cannot mount a 300 kB tmpfs here (mount needs root / CAP_SYS_ADMIN); the "
                    "full-disk behaviour is untested on this machine")
    try:
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], check=False)


def _fill(disk: Path, leave: int) -> Path:
    """Fill ``disk`` but ``leave`` bytes (in whole 4 kB pages, tmpfs's unit)."""
    filler = disk / "filler"
    free = shutil.disk_usage(disk).free
    filler.write_bytes(b"\0" * max(0, free - leave))
    return filler


def _whole_files(folder: Path) -> list[Path]:
    """Every file under ``folder``, each checked to be whole: no temporary file left, each
    PNG ending in its IEND chunk, each JSON and NetCDF file readable."""
    files = [p for p in folder.rglob("*") if p.is_file() and p.name != "filler"]
    for path in files:
        assert not path.name.startswith(".webline-tmp-"), path
        if path.suffix == ".png":
            assert path.read_bytes()[-8:-4] == b"IEND", path
        elif path.suffix == ".json":
            json.loads(path.read_text())
        elif path.suffix == ".nc":
            engine = "scipy" if path.name.startswith("chunk-") else "h5netcdf"
            xr.open_dataset(path, engine=engine).close()
    return files


def test_a_run_on_a_full_disk_ends_in_one_line_exit_1_files_whole(small_disk) -> None:
    result = CliRunner().invoke(app, ["run", "hswl", "-d", "2", "-o", str(small_disk / "run"),
                                      "-q"])
    assert result.exit_code == 1, result.output
    line = _one_line_error(result.output)
    assert "No space left on device" in line and "free some space" in line
    _whole_files(small_disk / "run")


def test_a_sweep_on_a_full_disk_stops_cleanly_and_resumes_once_space_is_back(
        small_disk, monkeypatch) -> None:
    from webline.sim.sweeps import chunks

    monkeypatch.setattr(chunks, "CHUNK", 4)  # 12 cases in 3 chunks of a few kB each
    out = small_disk / "sweep"
    first = CliRunner().invoke(app, [*STUDY, "-o", str(out)])
    size = (out / "chunks" / "chunk-000000.nc").stat().st_size if first.exit_code == 0 else 0
    shutil.rmtree(out)
    assert size, first.output
    filler = _fill(small_disk, 2 * size + 20_000)  # the manifest and about two chunks fit
    full = CliRunner().invoke(app, [*STUDY, "-o", str(out)])
    assert full.exit_code == 1, full.output
    line = _one_line_error(full.output)
    saved = len(list((out / "chunks").glob("chunk-*.nc")))
    assert "No space left on device" in line
    assert f"--resume will continue from {saved} saved chunks of 3" in line
    _whole_files(out)
    filler.unlink()  # space is back
    resumed = CliRunner().invoke(app, [*STUDY, "-o", str(out), "--resume"])
    assert resumed.exit_code == 0, resumed.output
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf")
    assert list(ds.case.values) == list(range(12))


def test_a_damaged_chunk_is_named_before_a_resume_runs(tmp_path) -> None:
    from webline.sim.sweeps import chunks

    chunks_kw = {"web.ea": "normal(9 kN, 5 %)"}
    webline.monte_carlo("hswl", chunks_kw, 6, seed=1, duration=0.05, store=tmp_path, workers=1)
    damaged = chunks.chunk_path(tmp_path, 0)
    damaged.write_bytes(damaged.read_bytes()[:300])  # cut short, as a crash of the disk would
    with pytest.raises(StudyError, match=rf"^{damaged}: a saved chunk is damaged .*; delete it "
                                         r"and --resume will compute its 6 cases again$"):
        webline.monte_carlo("hswl", chunks_kw, 6, seed=1, duration=0.05, store=tmp_path,
                            workers=1, resume=True)


def test_zip_of_unequal_lengths_is_one_line_exit_2(tmp_path) -> None:
    result = CliRunner().invoke(app, ["sweep", "hswl", "--set", "web.ea=8 kN,9 kN", "--set",
                                      "rollers.idler.friction=1e-4,2e-4,3e-4", "--zip", "-o",
                                      str(tmp_path / "out")])
    assert result.exit_code == 2
    assert "web.ea: 2, rollers.idler.friction: 3" in _one_line_error(result.output)


@pytest.mark.parametrize("command", [["sweep", "hswl"], ["run", "hswl"]])
def test_values_nested_1000_deep_are_one_line_exit_2(tmp_path, command) -> None:
    nested = "[" * 1000 + "]" * 1000
    result = CliRunner().invoke(app, [*command, "--set", f"web.ea={nested}", "-o",
                                      str(tmp_path / "out"), "-q"])
    assert result.exit_code == 2, result.output
    assert "nested more than 32 deep" in _one_line_error(result.output)


def _serve(answer: bytes | None) -> tuple[socket.socket, str]:
    """A local TCP service that accepts and then sends ``answer`` (None: says nothing)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held: list[socket.socket] = []

    def accept() -> None:
        while True:
            try:
                conn, _ = server.accept()
            except OSError:
                return
            held.append(conn)
            if answer is not None:
                conn.sendall(answer)

    threading.Thread(target=accept, daemon=True).start()
    return server, f"tcp://127.0.0.1:{server.getsockname()[1]}"


@pytest.mark.parametrize("answer, why", [
    (None, "nothing answered as a Dask scheduler within 2 s"),
    (b"HTTP/1.1 400 Bad Request\r\n\r\n", "a service that is not a Dask scheduler: its first "
                                          "message announces"),
], ids=["silent-port", "web-server"])
def test_a_service_that_is_no_scheduler_is_refused_in_seconds(tmp_path, monkeypatch, answer,
                                                              why) -> None:
    from webline.sim.sweeps import scheduler

    monkeypatch.setattr(scheduler, "CONNECT_SECONDS", 1.0)
    monkeypatch.setattr(scheduler, "HANDSHAKE_SECONDS", 1.0)
    server, address = _serve(answer)
    outcome: list[BaseException | None] = []

    def study() -> None:
        try:
            webline.sweep("hswl", {"web.ea": ["8 kN"]}, duration=0.05, scheduler=address,
                          store=tmp_path)
            outcome.append(None)
        except BaseException as exc:  # handed to the test's thread
            outcome.append(exc)

    started = time.monotonic()
    thread = threading.Thread(target=study, daemon=True)
    thread.start()
    thread.join(60)  # distributed's own time-outs would be 30 s; a hang is for ever
    server.close()
    assert outcome, "the study still waited on the service after 60 s"
    assert isinstance(outcome[0], ArgumentError), outcome[0]
    assert why in str(outcome[0]) and "tcp://host:8786" in str(outcome[0])
    assert time.monotonic() - started < 30


class _Future:
    def __init__(self, value: object) -> None:
        self.value = value

    def result(self) -> object:
        if isinstance(self.value, BaseException):
            raise self.value
        return self.value


class _Client:
    """A client whose chunk 1 has killed its worker on every try, as distributed reports it
    (``KilledWorker``) once ``retries`` are spent; chunk 0 is done first."""

    def submit(self, task, *args, key, retries, pure):
        from distributed import KilledWorker

        k = int(key.rsplit("-", 1)[1])
        return _Future(KilledWorker(key, None, retries) if k == 1 else f"chunk {k}")


def test_workers_that_all_die_end_in_one_line_with_the_resume_count(monkeypatch) -> None:
    """Not distributed's KilledWorker traceback: a StudyError that says how many chunks are
    saved for --resume (the chunks saved before the failure count)."""
    import distributed

    from webline.sim.sweeps import dask_run

    monkeypatch.setattr(distributed, "as_completed", lambda futures: list(futures))
    saved: list[int] = []
    with pytest.raises(StudyError, match=r"^the Dask workers died running chunk 1 \(4 tries, "
                                         r".*\); --resume will continue from 1 saved chunks "
                                         r"of 2 in S$"):
        dask_run.run_on_dask((_Client(), None), print, {0: (), 1: ()},
                             lambda k, ds: saved.append(k), 3,
                             lambda: f"--resume will continue from {len(saved)} saved chunks "
                                     "of 2 in S")
    assert saved == [0]


def test_ctrl_c_while_a_chunk_is_written_waits_for_it_and_says_how_to_resume(
        tmp_path, monkeypatch) -> None:
    """Ctrl-C raised inside xarray's write left its file lock held, and the close of the file
    then waited on it for ever (the hang of one Ctrl-C in three with --scheduler local): the
    signal now waits for the write, the chunk is saved whole and counted."""
    import signal

    from webline.files import atomic_write as real_write
    from webline.sim.sweeps import chunks

    def write_then_ctrl_c(path, write):
        def interrupted_write(tmp):
            os.kill(os.getpid(), signal.SIGINT)  # arrives while the chunk is being written
            write(tmp)
        return real_write(path, interrupted_write)

    monkeypatch.setattr(chunks, "atomic_write", write_then_ctrl_c)
    with pytest.raises(KeyboardInterrupt, match=r"^interrupted: --resume will continue from 1 "
                                                r"saved chunks of 2 in "):
        chunks.run_chunked(chunks_run_cases(), "hswl", [{"web.ea": "8 kN"}, {"web.ea": "9 kN"}],
                           store=tmp_path, chunk=1, duration=0.05, workers=1)
    assert [p.name for p in chunks.store_files(tmp_path)] == ["chunk-000000.nc", "study.json"]
    _whole_files(tmp_path)


def chunks_run_cases():
    from webline.sim.sweeps.sweep import run_cases

    return run_cases


@pytest.mark.serial  # timed: needs the CPU to itself
def test_ctrl_c_on_a_local_cluster_stops_within_seconds(tmp_path) -> None:
    """The user's Ctrl-C reaches the whole process group: the command and its workers."""
    import signal
    import sys

    src = str(Path(__file__).resolve().parents[2] / "src")
    out = tmp_path / "out"
    proc = subprocess.Popen(
        [sys.executable, "-c", "from webline.cli import main; main()", "sweep", "hswl", "--set",
         "web.ea=normal(9 kN, 5 %)", "--samples", "2000", "-d", "10", "--scheduler", "local",
         "--workers", "2", "-q", "-o", str(out)],  # 4 tasks of 500 cases (chunks.task_chunk)
        env={**os.environ, "PYTHONPATH": src}, stderr=subprocess.PIPE, start_new_session=True)
    deadline = time.monotonic() + 180
    while not list((out / "chunks").glob("chunk-*.nc")) and time.monotonic() < deadline:
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGINT)
    sent = time.monotonic()
    try:
        proc.wait(30)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        pytest.fail("the study still ran 30 s after Ctrl-C")
    # a few seconds: the cluster's processes are killed, not waited for
    assert time.monotonic() - sent < 10
    assert proc.returncode == 130
    err = proc.stderr.read().decode() if proc.stderr else ""
    assert "--resume will continue from" in err.strip().splitlines()[-1], err
