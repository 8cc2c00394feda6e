"""CITATION.cff (issue 37, item 5): valid YAML in the Citation File Format naming webline and,
as a reference, the thesis it implements; the README's "How to cite" points to it."""

from __future__ import annotations

from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]


def test_citation_file_parses_and_names_webline_and_the_thesis() -> None:
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert cff["cff-version"] == "1.2.0"
    assert cff["type"] == "software" and cff["title"].startswith("webline")
    assert cff["license"] == "MIT" and cff["authors"]
    from webline.version import __version__

    assert cff["version"] == __version__
    (thesis,) = [ref for ref in cff["references"] if ref["type"] == "thesis"]
    assert thesis["thesis-type"].startswith("Ph.D.")
    assert thesis["institution"]["name"] == "Oklahoma State University"
    assert thesis["authors"] and thesis["title"]


def test_readme_says_how_to_cite() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## How to cite")[1].split("\n## ")[0]
    assert "CITATION.cff" in section and "thesis" in section
