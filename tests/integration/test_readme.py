"""The README's promises: two set-up commands, a Python quickstart that runs, links that exist."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_setup_is_make_run_and_make_test():
    setup = README.split("## Set up")[1].split("\n## ")[0]
    block = re.search(r"```sh\n(.*?)```", setup, re.S).group(1)
    commands = [line.split("#")[0].strip() for line in block.splitlines() if line.strip()]
    assert commands == ["make run", "make test"]
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert re.search(r"^run:", makefile, re.M) and re.search(r"^test:", makefile, re.M)


def test_local_links_and_images_exist():
    targets = re.findall(r"\]\(((?!https?:)[^)#]+)\)", README)
    assert "docs/line-file.md" in targets
    assert any(t.startswith("docs/img/") for t in targets)
    assert "docs/errata.md" in targets
    missing = [t for t in targets if not (ROOT / t).exists()]
    assert missing == []


def test_python_quickstart_runs(tmp_path, monkeypatch):
    code = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    report = tmp_path / "out" / "mine" / "report.html"
    assert "lbf" in report.read_text(encoding="utf-8")
    assert (tmp_path / "speed-change.nc").stat().st_size > 0


#: the README's Python example on the built-in laminator: its names for the hswl's
LAMINATOR_NAMES = {
    '"hswl"': '"laminator"',
    '"speed-change"': '"layer-upset"',
    '["span1"]': '["film_zone"]',
    'span="span2"': 'span="foil_zone"',
    '"rollers.process.controller.tension_bandwidth"':
        '"rollers.rewind.controller.tension_bandwidth"',
    '"web.ea": "9 kN"': '"webs.film.web.ea": "90 kN"',
    '"spans.span2.length"': '"webs.film.spans.film_zone.length"',
}
#: what the example does that a branched line still refuses, one line each (issue 33)
LAMINATOR_REFUSED = {
    "op = webline.operating_point(softer)": "operating_point of 'laminator': not yet supported "
                                            "for a branched line",
}


def test_python_quickstart_runs_on_the_laminator(tmp_path, monkeypatch):
    """The same example on a branched line (issue 33): the same calls, with the laminator's
    names; each statement it still refuses raises its one-line ``ArgumentError`` (listed in
    ``LAMINATOR_REFUSED``) and the lines that use its value are skipped."""
    import pytest

    import webline

    code = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    for hswl, laminator in LAMINATOR_NAMES.items():
        assert hswl in code, hswl  # (the README changed: update the names)
        code = code.replace(hswl, laminator)
    for statement, refusal in LAMINATOR_REFUSED.items():
        assert statement in code
        name = statement.split(" = ")[0]
        kept = [line for line in code.splitlines() if not re.search(rf"\b{name}\.", line)]
        code = "\n".join(kept).replace(
            statement, f"with _raises(_Error, match={refusal!r}):\n    {statement}")
    monkeypatch.chdir(tmp_path)
    namespace = {"_raises": pytest.raises, "_Error": webline.ArgumentError}
    exec(compile(code, "README.md (laminator)", "exec"), namespace)
    assert type(namespace["result"]).__name__ == "BranchResult"
    assert namespace["result"].status in ("ok", "warning")
    report = tmp_path / "out" / "mine" / "report.html"
    assert "lbf" in report.read_text(encoding="utf-8")
    assert (tmp_path / "speed-change.nc").stat().st_size > 0
