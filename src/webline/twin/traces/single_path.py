"""The twin's traces belong to a single-path line: a branched line is refused in one line."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.lines import load_line


def single_path_line(line: Line | str | Path | Any, what: str) -> Line:
    """``line`` loaded by the front door (``webline.load_line``) where it is a single-path
    line; ``ArgumentError`` naming ``what`` (the function) and the reason where its webs branch
    (docs/branching.md)."""
    loaded = load_line(line)
    if loaded.branched:
        raise ArgumentError(
            f"line: {what} of {loaded.name!r}: not yet supported for a branched "
            "line ([[webs]]): a twin's traces drive and are matched to a "
            "single-path line's signals (docs/branching.md)"
        )
    return loaded
