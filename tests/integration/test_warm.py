"""``webline warm`` and ``webline.warm`` (issue 37, item 1): the loops a user will need are
compiled ahead, a first run says what it compiles and roughly how long, and a bad line is one
line with exit 2 before anything is compiled."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

import webline
from webline import compile_ahead
from webline.cli import app

SRC = str(Path(__file__).resolve().parents[2] / "src")


def test_the_cache_is_empty_until_a_compiled_loop_is_in_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(compile_ahead, "cache_folder", lambda: tmp_path / "numba")
    assert compile_ahead.cache_is_empty()  # no folder yet
    (tmp_path / "numba" / "webline_sim_core").mkdir(parents=True)
    assert compile_ahead.cache_is_empty()  # a folder without an index
    (tmp_path / "numba" / "webline_sim_core" / "kernel.loop-255.py311.nbi").write_bytes(b"")
    assert not compile_ahead.cache_is_empty()


def test_the_targets_are_each_line_run_then_the_sweeps_batch_loops() -> None:
    assert compile_ahead.targets() == ["run hswl", "run laminator", "sweep hswl", "sweep laminator"]
    assert compile_ahead.targets(["rockwell"], sweeps=True) == ["run rockwell"]
    assert compile_ahead.targets(["hswl"], sweeps=False) == ["run hswl"]
    # measured 2026-12-02 from empty caches: 28, 49 (31-36 once the branched plant compiles
    # once: benchmarks/bench_first_run.py), 24 and 3.9 CPU-seconds
    assert compile_ahead.first_compile_estimate(compile_ahead.targets()) == 100.0


def test_warm_leaves_the_loop_cached_so_a_later_run_only_loads_it() -> None:
    """After ``warm``, a fresh process running the line loads its compiled loop from the
    cache (numba's cache hit) and compiles nothing (no cache miss)."""
    done = webline.warm(["hswl"], sweeps=False)
    assert [item.what for item in done] == ["run hswl"]
    assert not compile_ahead.cache_is_empty()
    code = (
        "import webline; from webline.sim.core.kernel import compiled_loop; "
        "from webline.sim.core.plan import compile_plan; line = webline.load_line('hswl'); "
        "webline.simulate(line, 0.01); loop = compiled_loop(compile_plan(line)); "
        "print(sum(loop.stats.cache_hits.values()), sum(loop.stats.cache_misses.values()))"
    )
    ran = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, "PYTHONPATH": SRC},
    )
    assert ran.stdout.split() == ["1", "0"]


def test_the_first_run_says_what_it_compiles_and_roughly_how_long(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(compile_ahead, "cache_is_empty", lambda: True)
    done = CliRunner().invoke(app, ["warm", "hswl", "--no-sweeps"])
    assert done.exit_code == 0, done.output
    lines = done.stderr.strip().splitlines()
    assert lines[0].startswith(
        "First run of this webline version: compiling its simulation loops (run hswl) into "
    )
    assert "about 30 CPU-seconds" in lines[0]
    assert lines[1] == "  run hswl ..."
    assert lines[-1].startswith("Compiled loops ready (1 targets, ")


def test_a_line_that_is_not_there_is_one_line_and_exit_2_before_compiling() -> None:
    done = CliRunner().invoke(app, ["warm", "hswl", "no-such-line"])
    assert done.exit_code == 2
    assert done.stderr.strip().splitlines() == [
        "error: no-such-line: (name): no such file or built-in line (built-in: converter, "
        "hswl, laminator, rockwell, slitter)"
    ]
