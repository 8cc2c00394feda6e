"""The front door's ``load_line``: every line file, built-in line, dict or spec, whatever its
topology (docs/branching.md). A file whose webs branch (``[[webs]]``) is read as a
``BranchedLine``, any other as a ``Line``: the one place that tells them apart by the file's
format. Code above asks the loaded line's ``branched`` attribute, never the file.

A single-path line's load imports none of the branched line's modules (a run's start-up
time, tests/unit/test_startup.py).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from webline.errors import ArgumentError
from webline.line import Line
from webline.spec.load import general_loop, is_branched, parse_text_data, read_any, spec_from_dict
from webline.spec.schema import LineSpec

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine
    from webline.spec.branched.schema import BranchedLineSpec


def load_line(
    source: Line | BranchedLine | LineSpec | BranchedLineSpec | str | Path | dict[str, Any],
) -> Line | BranchedLine:
    """A line from a TOML file path, a built-in line's name (``"hswl"``, ``"laminator"``), a
    dict as read from TOML, a spec, or a line (returned as it is).

    A line whose webs branch (``[[webs]]``: laminators, slitters, lanes on a shaft) is a
    ``BranchedLine``, any other a ``Line``; both say which by ``line.branched``. Raises
    ``LineFileError`` naming the file, key path and problem for malformed input and
    ``ArgumentError`` for a ``source`` of another type."""
    if isinstance(source, Line):
        return source
    if isinstance(source, LineSpec | dict | str | Path) and general_loop():
        return _one_web(source)
    if isinstance(source, LineSpec):
        return Line(source)
    if isinstance(source, dict):
        if is_branched(source):
            from webline.model.web_graph import load_branched

            return load_branched(source)
        return Line(spec_from_dict(source, "<dict>"), "<dict>")
    if isinstance(source, str | Path):
        data, text, label = read_any(source)
        if is_branched(data):  # the file's format: its webs in [[webs]]
            from webline.model.web_graph import branched_from_file

            return branched_from_file(data, text, label)
        return Line(parse_text_data(data, text, label), label)
    from webline.model.web_graph import BranchedLine, load_branched  # (only for its objects)
    from webline.spec.branched.schema import BranchedLineSpec

    if isinstance(source, BranchedLine | BranchedLineSpec):
        return load_branched(source)
    raise ArgumentError(
        f"line: expected a line, a line file path, a built-in line's name, "
        f"a dict or a line spec, got {type(source).__name__}"
    )


def _one_web(source: LineSpec | dict[str, Any] | str | Path) -> BranchedLine:
    """Under issue 33's migration switch: any line source as the general loop runs it."""
    from webline.model.web_graph import general_from_file

    if isinstance(source, LineSpec):
        return general_from_file(source.model_dump(exclude_none=True), None, "<python>")
    if isinstance(source, dict):
        return general_from_file(source, None, "<dict>")
    return general_from_file(*read_any(source))
