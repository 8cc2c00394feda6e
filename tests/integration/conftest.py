"""A short `webline run` in SI and in imperial units, shared by the CLI and report tests."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest
from typer.testing import CliRunner

from webline.cli import app


@dataclass(frozen=True)
class Run:
    """A finished `webline run`: what it printed and the folder it wrote."""

    stdout: str
    stderr: str
    out: Path

    @property
    def report(self) -> Path:
        return self.out / "report.html"


@pytest.fixture(scope="session")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Run]:
    """`webline run hswl -s disturbance -d 2 --svg` with --units si and --units imperial."""
    base = tmp_path_factory.mktemp("runs")
    out = {}
    for units in ("si", "imperial"):
        folder = base / units
        result = CliRunner().invoke(app, ["run", "hswl", "-s", "disturbance", "-d", "2",
                                          "-u", units, "--out", str(folder), "--svg"])
        assert result.exit_code == 0, result.output
        out[units] = Run(result.stdout, result.stderr, folder)
    return out
