"""``--set PATH=VALUE`` on run, analyze and show: nested paths with units, bad ones named."""

from __future__ import annotations

import json

from typer.testing import CliRunner

from webline.cli import app


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def test_show_applies_sets_with_units() -> None:
    out = invoke("show", "hswl", "--set", "web.ea=9 kN", "--set", "spans.span2.length=12").stdout
    assert "9000 N" in out and "12 m" in out


def test_analyze_sees_a_set_speed() -> None:
    """--set speed: the operating point moves to the new line speed (800 ft/min = 4.064 m/s)."""
    result = invoke("analyze", "hswl", "--json", "--set", "speed=800 ft/min")
    assert result.exit_code == 0, result.output
    speed = json.loads(result.stdout)["operating_point"]["line_speed"]
    assert abs(speed - 4.064) < 1e-12  # exact up to the unit conversion's rounding


def test_set_after_scenario_wins(tmp_path) -> None:
    """A --set changes the line as the scenario leaves it: the tension-step scenario's step
    profile of span2 is replaced by a constant, so span2 keeps 63.83 N (14.35 lbf)."""
    out = tmp_path / "run"
    result = invoke("run", "hswl", "--scenario", "tension-step", "--duration", "4 s", "--quiet",
                    "--out", str(out), "--set", "spans.span2.tension=14.35 lbf")
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text())
    assert abs(summary["summary"]["spans"]["span2"]["mean"] - 63.83) < 0.01


def test_bad_sets_are_one_line_errors() -> None:
    for args, fragment in [(["--set", "no-equals"], "--set: expected PATH=VALUE"),
                           (["--set", "rollers.proces.radius=1"], "did you mean 'process'"),
                           (["--set", "web.ea=-3 kN"], "web.ea")]:
        result = invoke("show", "hswl", *args)
        assert result.exit_code == 2, result.output
        lines = result.stderr.strip().splitlines()
        assert lines[0].startswith("error: ") and fragment in result.stderr
        assert "Traceback" not in result.stderr


def test_figures_are_png_unless_svg_is_asked(tmp_path) -> None:
    out = tmp_path / "png"
    assert invoke("run", "hswl", "-d", "0.5", "-q", "--out", str(out)).exit_code == 0
    names = {p.suffix for p in (out / "figures").iterdir()}
    assert names == {".png"}
