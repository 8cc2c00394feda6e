"""Every script in examples/ runs (DESIGN: examples are tests) and prints what it claims."""

from __future__ import annotations

import itertools
import re
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def run_example(name: str) -> str:
    done = subprocess.run([sys.executable, str(EXAMPLES / name)], capture_output=True,
                          text=True, timeout=600, check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_every_example_is_covered() -> None:
    assert {p.name for p in EXAMPLES.glob("*.py")} == {
        "own_line.py", "gain_sweep.py", "compare_controllers.py", "bode.py",
        "fit_converter.py"}


def test_fit_converter_recovers_both_values() -> None:
    """The fitted intervals hold the values the recording was made with (issue 24)."""
    out = run_example("fit_converter.py")
    assert "time offset 12 s removed" in out
    assert out.count("inside the 95 % interval") == 2, out


def test_own_line() -> None:
    out = run_example("own_line.py")
    assert "verdict: ok" in out
    assert len(re.findall(r"mean +\d", out)) == 3  # one row per span


def test_gain_sweep_faster_tension_loop_tracks_better() -> None:
    """During the speed change, a faster tension loop keeps the RMS error of span2 smaller:
    the rows must decrease with the bandwidth (2, 4, 8, 16 rad/s)."""
    out = run_example("gain_sweep.py")
    rms = [float(m) for m in re.findall(r"rad/s +([\d.]+)", out)]
    assert len(rms) == 4
    assert all(a > b for a, b in itertools.pairwise(rms)), out


def test_compare_controllers_prints_each_family() -> None:
    out = run_example("compare_controllers.py")
    for family in ("cascaded_pi", "state_feedback", "adaptive"):
        assert re.search(rf"^{family} +[\d.]+ +[\d.]+ +[\d.]+ ", out, re.M), out


def test_bode_has_unit_dc_gain() -> None:
    """The tension loop's integral action makes the closed-loop gain from a zone's tension
    reference to its loadcell tension exactly 1 (0 dB) at low frequency; 0.1 rad/s is far
    below the 8 rad/s loop, so |gain| is within 0.01 dB of it."""
    out = run_example("bode.py")
    match = re.search(r"span2_tension: (-?[\d.]+) dB at", out)
    assert match is not None, out
    assert float(match.group(1)) == pytest.approx(0.0, abs=0.01)
