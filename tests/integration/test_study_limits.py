"""A study's size and work are bounded before anything runs (issue 22, item 5): the case count
before anything is allocated, each case by `run`'s own budget, the whole study by a documented
limit that can be lifted; distributions and ranges are read as strictly as line files, and a
relative spread means one thing however it is written."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import ArgumentError, LineFileError
from webline.sim.distributions import parse_distribution

SRC = str(Path(__file__).resolve().parents[2] / "src")


#: Runs ``webline ARGS`` with its address space capped at 4 GB (a study that tries to
#: allocate gigabytes fails instead of taking the machine) and prints its exit status, CPU
#: time [s] and peak resident memory [kB]. A small launcher, because a child's peak counts
#: the memory of the process it was forked from until its exec: measured from the test
#: process (300 MB after other tests), every command would look 300 MB large.
LAUNCH = """
import resource, subprocess, sys
cap = "import resource; resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30)); "
code = subprocess.call([sys.executable, "-c", cap + "from webline.cli import main; main()",
                        *sys.argv[1:]], stdout=subprocess.DEVNULL)
used = resource.getrusage(resource.RUSAGE_CHILDREN)
print(code, used.ru_utime + used.ru_stime, used.ru_maxrss)
"""


def _webline(args: list[str], cwd: Path, timeout: float = 60) -> tuple[int, str, float, float]:
    """(exit status, stderr, CPU seconds, peak resident MB) of `webline ARGS` in its own
    process (``LAUNCH``)."""
    env = {**os.environ, "PYTHONPATH": SRC}
    try:
        done = subprocess.run([sys.executable, "-c", LAUNCH, *args], cwd=cwd, env=env,
                              capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        pytest.fail(f"webline {' '.join(args)} still ran after {timeout} s")
    code, cpu, peak = done.stdout.split()
    return int(code), done.stderr, float(cpu), float(peak) / 1024


@pytest.mark.parametrize("args", [
    ["--samples", "1e9", "--set", "web.ea=normal(9 kN, 5 %)"],
    ["--samples", "1000000000", "--set", "web.ea=normal(9 kN, 5 %)"],
    ["--set", "web.ea=1 kN:2 kN:1000000000"],
], ids=["samples-1e9", "samples-int", "range"])
def test_a_billion_cases_are_refused_at_once_in_little_memory(tmp_path, args) -> None:
    code, err, cpu, rss = _webline(["sweep", "hswl", *args, "-o", str(tmp_path / "out")],
                                   tmp_path)
    assert code == 2, err
    assert err.strip().count("\n") == 0 and "1e+09 cases" in err, err
    # the bound: under a second and 200 MB. CPU time, not wall time: the shared
    # 2-core test machine can stretch the wall clock of a 0.4 s start-up several times.
    assert cpu < 1.0, cpu
    assert rss < 200, rss
    assert not (tmp_path / "out").exists()  # refused before the output folder is made


@pytest.mark.parametrize("value", ["normal(9**9**9 N, 5 %)", "uniform(1 kN, 9**9**9 N)"])
def test_an_exponent_tower_in_a_distribution_is_refused_not_evaluated(tmp_path, value) -> None:
    code, err, _, _ = _webline(["sweep", "hswl", "--samples", "4", "--set", f"web.ea={value}",
                                "-o", str(tmp_path / "out")], tmp_path, timeout=30)
    assert code == 2 and "9**9**9" in err and "no commas or expressions" in err, err


def test_an_exponent_tower_in_a_range_is_refused_not_evaluated(tmp_path) -> None:
    code, err, _, _ = _webline(["sweep", "hswl", "--set", "web.ea=9**9**9 N:2 kN:3", "-o",
                                str(tmp_path / "out")], tmp_path, timeout=30)
    assert code == 2 and "no commas or expressions" in err, err


@pytest.mark.parametrize("word", ["%", "percent", "pct", " PERCENT"])
def test_every_percent_word_is_the_same_relative_spread(word) -> None:
    # 5 % of 9 kN is 450 N (the docs' example), exactly: 9000 * 0.05
    assert parse_distribution(f"normal(9 kN, 5 {word})") == ("normal", 9000.0, 450.0)
    _, low, high = parse_distribution(f"uniform(9 kN, 10 {word})")
    assert (low, high) == pytest.approx((8100.0, 9900.0), rel=1e-15)


@pytest.mark.parametrize("word", ["ppm", "permille"])
def test_another_ratio_word_as_a_spread_is_refused(word) -> None:
    with pytest.raises(ValueError, match="relative spread in %"):
        parse_distribution(f"normal(9 kN, 5 {word})")


def test_a_range_reads_its_stop_in_the_unit_of_its_start() -> None:
    from webline.cli_sweep import parse_range

    lbf = 4.4482216152605  # [N] per lbf, exact by definition (0.45359237 kg x 9.80665 m/s2)
    values = parse_range("web.ea", "1800 lbf:2 kN:2")
    assert values[0] == "1800.0 lbf"
    assert float(values[1].split()[0]) == pytest.approx(2000 / lbf, rel=1e-12)
    with pytest.raises(ArgumentError, match="not of one kind"):
        parse_range("web.ea", "1 kN:2 m:3")


def test_a_case_run_would_refuse_is_refused_before_the_study_runs(monkeypatch) -> None:
    """With run's bound lowered below one 0.3 s case of hswl, `run` refuses it: so must the
    sweep, naming the same key, before any case runs (``run_batch`` is never called)."""
    from webline.sim import batch, budget, sweep

    monkeypatch.setattr(budget, "MAX_RK4_STEPS", 10)
    with pytest.raises(LineFileError) as by_run:
        webline.simulate("hswl", 0.3)

    def never(*args, **kwargs):
        raise AssertionError("a case ran")

    monkeypatch.setattr(batch, "run_batch", never)
    monkeypatch.setattr(sweep, "run_batch", never)
    with pytest.raises(LineFileError) as by_sweep:
        webline.sweep("hswl", {"web.ea": ["8 kN", "9 kN"]}, duration=0.3, workers=1)
    assert by_sweep.value.key == by_run.value.key


def test_each_built_case_is_held_to_runs_budget(monkeypatch) -> None:
    """A case is checked again when it is built (a combination of values no probe saw)."""
    from webline.sim import budget
    from webline.sim.cases import build_cases

    monkeypatch.setattr(budget, "MAX_RK4_STEPS", 10)
    with pytest.raises(LineFileError, match="RK4 steps"):
        build_cases(webline.load_line("hswl"), [{"web.ea": "8 kN"}], 0.3)


def test_the_study_limit_refuses_and_can_be_lifted(monkeypatch) -> None:
    from webline.sim import budget

    one = webline.sweep("hswl", {"web.ea": ["8 kN"]}, duration=0.2, workers=1)
    steps = int(one.substeps[0]) * round(0.2 * 1000)  # hswl's controllers tick at 1 kHz
    monkeypatch.setattr(budget, "MAX_STUDY_RK4_STEPS", 3 * steps)  # 3 cases fit, 4 do not
    values = {"web.ea": ["8 kN", "8.5 kN", "9 kN", "9.5 kN"]}
    with pytest.raises(ArgumentError, match=r"4 cases .* more than the study limit .*"
                                            r"\(--no-work-limit"):
        webline.sweep("hswl", values, duration=0.2, workers=1)
    ds = webline.sweep("hswl", values, duration=0.2, workers=1, work_limit=False)
    assert ds.status.size == 4  # a grid: the cases over its dimensions


def test_the_cli_names_the_override(tmp_path, monkeypatch) -> None:
    from webline.sim import budget

    monkeypatch.setattr(budget, "MAX_STUDY_RK4_STEPS", 10)
    args = ["sweep", "hswl", "--set", "web.ea=8 kN,9 kN", "-d", "0.1", "--workers", "1", "-q"]
    refused = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "a")])
    assert refused.exit_code == 2 and "--no-work-limit" in refused.output
    assert refused.output.strip().count("\n") == 0
    lifted = CliRunner().invoke(app, [*args, "--no-work-limit", "-o", str(tmp_path / "b")])
    assert lifted.exit_code == 0, lifted.output


def test_a_grid_is_counted_before_its_combinations_are_built(monkeypatch) -> None:
    """A grid of 2 x 2000 x 2000 values is 8e6 cases: refused from the product of the counts
    (the itertools product is never listed)."""
    from webline.sim import sweep

    def never(*args, **kwargs):
        raise AssertionError("the combinations were built")

    monkeypatch.setattr(sweep.itertools, "product", never)
    values = {"web.ea": ["8 kN", "9 kN"], "rollers.idler.friction": list(np.linspace(1e-5, 1e-4,
                                                                                     2000)),
              "rollers.idler.inertia": list(np.linspace(0.01, 0.02, 2000))}
    with pytest.raises(ArgumentError, match=r"the grid: a study of 8e\+06 cases"):
        webline.sweep("hswl", values, duration=0.1)


def test_monte_carlo_bounds_n_before_drawing(monkeypatch) -> None:
    from webline.sim import sweep

    def never(*args, **kwargs):
        raise AssertionError("samples were drawn")

    monkeypatch.setattr(sweep, "draw", never)
    with pytest.raises(ArgumentError, match=r"n \(--samples\): a study of 1e\+09 cases"):
        webline.monte_carlo("hswl", {"web.ea": "normal(9 kN, 5 %)"}, 10**9, seed=0)
