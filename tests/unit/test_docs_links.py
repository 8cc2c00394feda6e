"""Every relative link of the guides in docs/ names a file that exists (the site's build
reports links that leave docs/, such as those to the sources, only as information), or a page
that the build generates: the gallery's (docs/hooks/gallery.py, one per script of examples/)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
GENERATED = {DOCS / "gallery" / "index.md",
             *(DOCS / "gallery" / f"{p.stem}.md" for p in (ROOT / "examples").glob("*.py"))}


def test_relative_links_of_docs_exist() -> None:
    missing, checked = [], 0
    for page in sorted(DOCS.rglob("*.md")):
        text = re.sub(r"```.*?```|`[^`]*`", "", page.read_text(encoding="utf-8"), flags=re.S)
        for target in re.findall(r"\]\(((?![a-z]+:)[^)#\s]+)", text):
            checked += 1
            path = page.parent / target
            if not (path.exists() or path.resolve() in GENERATED):
                missing.append(f"{page.relative_to(DOCS)} -> {target}")
    assert missing == []
    assert checked > 30  # the guides link to each other and to images: the pattern finds them
