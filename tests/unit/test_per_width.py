"""Tension per width of web (issue 15 item 8): N/m, N/cm and pli in line files, converted with
``web.width``; per-width display (``--units si-per-width`` / ``imperial-per-width``)."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import LineFileError
from webline.report.text.display import Display
from webline.units import per_width_to_si

LBF, INCH = 4.4482216152605, 0.0254  # N, m (exact definitions)
PLI = LBF / INCH  # 175.1268 N/m
HSWL = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")


def test_one_pli_on_a_one_metre_web_is_175_newtons(hswl):
    line = hswl.replace({"web.width": "1 m", "spans.span2.tension": "1 pli"})
    assert line.spec.spans[1].tension == pytest.approx(175.127, abs=5e-4)
    assert line.spec.spans[1].tension == pytest.approx(PLI, rel=1e-12)
    assert per_width_to_si("2 N/cm") == pytest.approx(200.0)
    assert per_width_to_si("14.35 lbf") is None  # a force is not a force per width
    assert per_width_to_si(3.0) is None  # nor is a plain number (newtons)


def test_every_tension_key_takes_a_width(hswl):
    """On hswl's 6 in web: span references (a profile too), wound-in tension, the tension
    limit, EA; each equals the force given in newtons times the width."""
    w = hswl.spec.web.width
    line = hswl.replace({
        "spans.span1.tension": {"type": "steps", "initial": "2 pli",
                                "steps": [{"time": 1.0, "value": "300 N/m"}]},
        "rollers.unwind.wound_in_tension": "1.5 N/cm",
        "web.tension_limit": "10 pli", "web.modulus": None, "web.ea": "58 kN/m"})
    ref = line.spec.spans[0].tension
    assert ref.initial == pytest.approx(2 * PLI * w, rel=1e-12)
    assert ref.steps[0].value == pytest.approx(300 * w, rel=1e-12)
    assert line.unwind.wound_in_tension == pytest.approx(150 * w, rel=1e-12)
    assert line.spec.web.tension_limit == pytest.approx(10 * PLI * w, rel=1e-12)
    assert line.ea == pytest.approx(58e3 * w, rel=1e-12)


def test_dancer_load_per_width():
    rockwell = webline.load_line("rockwell")
    line = rockwell.replace({"rollers.dancer.dancer.load": "3 pli"})
    assert line.spec.rollers[1].dancer.load == pytest.approx(  # type: ignore[union-attr]
        3 * PLI * rockwell.spec.web.width, rel=1e-12)


def test_per_width_reference_gives_the_newton_trajectory(hswl):
    """hswl's references are 14.35 lbf on a 6 in web: 14.35/6 pli."""
    line = hswl.with_scenario("tension-step")
    per_width = line.replace({
        "spans.span1.tension": f"{14.35 / 6!r} pli",
        "spans.span2.tension": {"type": "steps", "initial": f"{14.35 / 6!r} pli",
                                "steps": [{"time": 2.0, "value": f"{18 / 6!r} pli"}]}})
    a, b = webline.simulate(line, 3.0), webline.simulate(per_width, 3.0)
    # the same newtons up to the last bits of the unit conversion
    np.testing.assert_allclose(b.tension_ref[:, :2], a.tension_ref[:, :2], rtol=1e-13)
    np.testing.assert_allclose(b.tension, a.tension, rtol=1e-9, atol=1e-9)
    assert np.abs(a.tension[:, 1].max() - 18 * LBF) < 0.05 * 18 * LBF  # the step happened


def test_display_shows_tension_per_width(hswl):
    w = hswl.spec.web.width  # 6 in
    assert Display("si-per-width", w).text(100.0, "force") == f"{100 / w:.4g} N/m"
    imperial = Display("imperial-per-width", w)
    assert imperial.text(14.35 * LBF, "force") == "2.392 pli"  # 14.35 lbf / 6 in
    assert imperial.unit("speed") == "ft/min"  # other kinds stay imperial
    assert Display("si", w).text(100.0, "force") == "100 N"
    with pytest.raises(ValueError, match="width"):
        Display("si-per-width")


def test_cli_shows_tensions_per_width():
    runner = CliRunner()
    shown = runner.invoke(app, ["show", "hswl", "--units", "imperial-per-width"])
    assert shown.exit_code == 0, shown.output
    assert "2.392 pli" in shown.stdout
    analyzed = runner.invoke(app, ["analyze", "hswl", "--units", "si-per-width", "--json"])
    assert analyzed.exit_code == 0, analyzed.output
    assert '"N/m"' in analyzed.stdout


def test_per_width_without_a_width_is_a_clear_error(tmp_path):
    text = HSWL.replace('tension = "14.35 lbf"', 'tension = "2.4 pli"', 1)
    text = "\n".join(line for line in text.splitlines() if not line.startswith("width"))
    path = tmp_path / "no-width.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(LineFileError) as info:
        webline.load_line(path)
    message = str(info.value)
    assert "web.width: required key is missing" in message
    assert "spans[0].tension: '2.4 pli' is a force per width of web, and no web width" in message
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "spans[0].tension" in result.stderr


def test_per_width_where_a_length_is_wanted_is_refused(hswl):
    with pytest.raises(LineFileError, match=r"spans\[1\].length: expected a length"):
        hswl.replace({"spans.span2.length": "3 pli"})
