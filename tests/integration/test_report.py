"""The HTML report of `webline run`: self-contained, its figures and tables, units, embedded
inputs, and how it renders in headless Chromium."""

from __future__ import annotations

import base64
import io
import os
import re
from pathlib import Path

import matplotlib.image as mpimg
import numpy as np
import pytest
import xarray as xr
from chromium import check_page, find_chromium

import webline
from webline.units import display_factor

FIGURES = ("schematic", "tension", "speed", "torque", "rolls", "poles")
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def inline_pngs(html: str) -> list[bytes]:
    return [base64.b64decode(data) for data in
            re.findall(r'<img [^>]*src="data:image/png;base64,([A-Za-z0-9+/=]+)"', html)]


def visible(html: str) -> str:
    """The report without its inlined images and its (SI by design) resolved TOML."""
    html = re.sub(r"<img [^>]*>", "", html)
    return html.split('<section id="resolved-line-file">')[0]


def table(html: str, key: str) -> str:
    match = re.search(rf'<table id="{key}">(.*?)</table>', html, re.S)
    assert match, f"no table {key}"
    return match.group(1)


def test_report_holds_every_figure_inline(runs):
    html = runs["si"].report.read_text(encoding="utf-8")
    images = inline_pngs(html)
    assert len(images) == len(FIGURES) >= 4
    assert all(image.startswith(PNG_MAGIC) for image in images)
    for key in FIGURES:
        assert f'id="fig-{key}"' in html
        png = runs["si"].out / "figures" / f"{key}.png"
        assert png.read_bytes() in images  # the inlined figure is the written PNG
        svg = (runs["si"].out / "figures" / f"{key}.svg").read_text(encoding="utf-8")
        assert svg.lstrip().startswith("<?xml") and "<svg" in svg


def test_report_is_self_contained(runs):
    html = runs["si"].report.read_text(encoding="utf-8")
    assert "http://" not in html and "https://" not in html
    assert "<script" not in html
    references = re.findall(r'(?:src|href)\s*=\s*"([^"]*)"', html)
    assert references and all(ref.startswith("data:") for ref in references)
    assert "@import" not in html and "url(" not in html


def test_report_summary_table_has_every_span(runs):
    html = runs["si"].report.read_text(encoding="utf-8")
    spans = table(html, "summary-spans")
    for name in ("span1", "span2", "span3a", "span3b"):
        assert f"<td class=\"text\">{name}</td>" in spans
    for header in ("mean [N]", "std [N]", "largest |error| [N]"):
        assert header in spans
    drives = table(html, "summary-drives")
    assert all(name in drives for name in ("unwind", "master", "process", "rewind"))


def test_report_summary_numbers_match_the_result(runs):
    """The report's span1 mean equals the mean tension stored in results.nc."""
    with xr.open_dataset(runs["si"].out / "results.nc") as ds:
        mean = float(ds.tension.sel(span="span1").mean())
        assert ds.attrs["webline_version"] == webline.__version__
        assert 'name = "hswl"' in ds.attrs["line_spec_toml"]
    row = re.search(r'<td class="text">span1</td>(.*?)</tr>',
                    table(runs["si"].report.read_text(encoding="utf-8"), "summary-spans"))
    cells = re.findall(r"<td>([^<]*)</td>", row.group(1))
    assert float(cells[1]) == pytest.approx(mean, rel=5e-4)  # 4 significant digits
    lbf = display_factor("force", "imperial")[0]
    row = re.search(r'<td class="text">span1</td>(.*?)</tr>',
                    table(runs["imperial"].report.read_text(encoding="utf-8"), "summary-spans"))
    cells = re.findall(r"<td>([^<]*)</td>", row.group(1))
    assert float(cells[1]) == pytest.approx(mean * lbf, rel=5e-4)


def test_imperial_report_uses_lbf_and_ft_per_min_throughout(runs):
    html = runs["imperial"].report.read_text(encoding="utf-8")
    for text in ("[lbf]", "[ft/min]", "[lbf·ft]", "[ft]", "[lb·ft²]", "14.35 lbf", "500 ft/min"):
        assert text in html
    for text in ("[N]", "[m/s]", "[N·m]", "[kg·m²]", " N<", " m/s<", " m<"):
        assert text not in visible(html)
    si = visible(runs["si"].report.read_text(encoding="utf-8"))
    assert "[N]" in si and "[m/s]" in si and "63.83 N" in si
    assert "lbf" not in si and "[ft]" not in si


def test_imperial_figures_are_labelled_in_imperial_units(runs):
    svg = (runs["imperial"].out / "figures" / "tension.svg").read_text(encoding="utf-8")
    assert "lbf" in svg and "[N]" not in svg
    svg = (runs["imperial"].out / "figures" / "speed.svg").read_text(encoding="utf-8")
    assert "ft/min" in svg


def test_report_embeds_operating_point_modes_line_file_and_version(runs):
    html = runs["si"].report.read_text(encoding="utf-8")
    for key in ("op-nodes", "op-spans", "modes", "rollers", "spans", "drives"):
        table(html, key)
    modes = table(html, "modes")
    assert "fn [Hz]" in modes and "ωn [rad/s]" in modes and "ζ" in modes
    assert 'name = &quot;hswl&quot;' in html  # the resolved TOML, escaped
    assert "wound_in_ripple" in html  # ... with the scenario applied
    assert f"webline {webline.__version__}" in html


def test_report_of_roll_change_shows_the_roll_emptying(tmp_path):
    """A partial run still gives a full report, with the failure stated and radii changing."""
    from webline.report import write_report

    result = webline.simulate("hswl", 120.0, scenario="roll-change", raise_on_failure=False)
    files = write_report(result, tmp_path, units="imperial", scenario="roll-change")
    html = files.report.read_text(encoding="utf-8")
    # ... and, a run across a roll, the map of its modes along the roll (issue 21)
    assert len(inline_pngs(html)) == len(FIGURES) + 1
    assert "Modes across the roll" in html
    radius, core = result.radius[:, 0], result.line.unwind.core_radius
    assert radius[-1] - core < 0.5 * (radius[0] - core)  # most of the unwind's web is gone
    assert result.inertia[-1, 1] > result.inertia[0, 1]  # the rewind grows


CHROMIUM = find_chromium()
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None and not os.environ.get("CI"),
    reason="chromium not installed (in CI, where CI is set, this test fails instead)")


def non_blank(png: bytes) -> tuple[float, float]:
    """(standard deviation of the grey levels, fraction of pixels that are not near-white)."""
    image = mpimg.imread(io.BytesIO(png), format="png")[..., :3]
    grey = image.mean(axis=2)
    return float(grey.std()), float(np.mean(grey < 0.9))


@needs_chromium
def test_report_renders_in_headless_chromium_without_errors(runs, tmp_path):
    assert CHROMIUM is not None, "CI is set but chromium is missing: install Debian's chromium"
    check = check_page(runs["imperial"].report)
    assert check.errors == []
    (tmp_path / "report.png").write_bytes(check.screenshot)
    spread, inked = non_blank(check.screenshot)
    assert spread > 0.05 and inked > 0.02


@needs_chromium
def test_chromium_check_sees_console_errors(tmp_path):
    """The check above is not vacuous: it catches an error, an exception and a missing file."""
    assert CHROMIUM is not None
    page = Path(tmp_path / "bad.html")
    page.write_text('<html><body><img src="missing.png"><script>console.error("boom");'
                    "undefinedFunction();</script></body></html>")
    errors = check_page(page).errors
    assert any("boom" in e for e in errors)
    assert any("undefinedFunction" in e for e in errors)
    assert any("missing.png" in e for e in errors)


@pytest.mark.parametrize(("line", "controller", "extra"), [
    ("rockwell", None, "dancer"),  # a winder figure (the unwind's dancer)
    ("hswl", "mrac", "mrac"),  # the MRAC's adapted gains
])
def test_every_written_figure_is_in_the_report(tmp_path, line, controller, extra):
    """Every figure the report writes is also shown in it, the line-specific ones included
    (winder figures were written but left out of the page once)."""
    from webline.control.select import with_controller
    from webline.report import write_report

    subject = webline.load_line(line)
    if controller:
        subject = with_controller(subject, controller)
    files = write_report(webline.simulate(subject, 1.0), tmp_path)
    html = files.report.read_text(encoding="utf-8")
    written = sorted(p.stem for p in files.figures)
    assert extra in written
    for key in written:
        assert f'id="fig-{key}"' in html, key
    assert sorted(inline_pngs(html)) == sorted(p.read_bytes() for p in files.figures)
