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
