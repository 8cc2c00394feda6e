"""Three mistakes the parser alone answers obscurely get a hint (issue 37): an unquoted
``--set web.ea=9 kN``, a distribution without ``--samples``, ``lbs`` for a force. Each is one
line and exit 2, before anything runs."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from webline.cli import app

SRC = str(Path(__file__).resolve().parents[2] / "src")


def _one_line(result) -> str:
    assert result.exit_code == 2, result.output
    lines = [line for line in result.stderr.strip().splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    return lines[0]


def test_an_unquoted_value_with_a_space_says_to_quote_it(tmp_path: Path) -> None:
    for args in (["--set", "web.ea=9", "kN"], ["--set=web.ea=9", "kN"]):
        line = _one_line(
            CliRunner().invoke(
                app, ["run", "hswl", *args, "-d", "0.01", "--out", str(tmp_path / "run")]
            )
        )
        assert line == (
            "error: --set web.ea=9 kN: the shell split this value at its space(s) "
            "and 'kN' became an extra argument; quote it: --set \"web.ea=9 kN\""
        )
    assert not (tmp_path / "run").exists()
    # an extra argument that is no part of a --set value keeps the parser's own message
    other = CliRunner().invoke(app, ["run", "hswl", "extra"])
    assert other.exit_code == 2 and "unexpected extra argument" in other.stderr


def test_the_command_as_installed_says_it_and_ends(tmp_path: Path) -> None:
    """Through ``main`` (whose ``run`` forks the report's process before parsing): the hint,
    exit 2, and the process ends (the unused copy is ended, not waited for)."""
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            "from webline.cli import main; main()",
            "run",
            "hswl",
            "--set",
            "web.ea=9",
            "kN",
            "--out",
            str(tmp_path / "run"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        env={"PYTHONPATH": SRC, "PATH": "/usr/bin:/bin"},
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines()[-1].endswith('quote it: --set "web.ea=9 kN"')


def test_a_distribution_without_samples_asks_for_them(tmp_path: Path) -> None:
    line = _one_line(
        CliRunner().invoke(
            app,
            [
                "sweep",
                "hswl",
                "--set",
                "web.ea=normal(9 kN, 5 %)",
                "-d",
                "0.01",
                "--out",
                str(tmp_path / "sweep"),
            ],
        )
    )
    assert line == (
        "error: --set web.ea=normal(9 kN, 5 %): a distribution needs --samples N "
        "(a Monte Carlo study of N cases); without it --set takes a list of values "
        "and would split this one at its comma"
    )


def test_pounds_of_mass_for_a_force_suggest_lbf(tmp_path: Path) -> None:
    line = _one_line(
        CliRunner().invoke(
            app,
            [
                "run",
                "hswl",
                "--set",
                "web.ea=2000 lbs",
                "-d",
                "0.01",
                "--out",
                str(tmp_path / "run"),
            ],
        )
    )
    assert line.endswith(
        "expected a force (e.g. N), got '2000 lbs': did you mean '2000 lbf'? "
        "(lb and kg are masses; lbf and kgf are forces)"
    ), line
    assert "web.ea" in line
