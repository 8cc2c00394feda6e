"""Every relative link of the guides in docs/ names a file that exists (the site's build
reports links that leave docs/, such as those to the sources, only as information)."""

from __future__ import annotations

import re
from pathlib import Path

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_relative_links_of_docs_exist() -> None:
    missing, checked = [], 0
    for page in sorted(DOCS.rglob("*.md")):
        text = re.sub(r"```.*?```|`[^`]*`", "", page.read_text(encoding="utf-8"), flags=re.S)
        for target in re.findall(r"\]\(((?![a-z]+:)[^)#\s]+)", text):
            checked += 1
            if not (page.parent / target).exists():
                missing.append(f"{page.relative_to(DOCS)} -> {target}")
    assert missing == []
    assert checked > 30  # the guides link to each other and to images: the pattern finds them
