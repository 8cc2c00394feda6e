"""A single-path line loaded as a line of one web (``spec.one_web``; issue 33): a
``BranchedLine`` that the general loop runs as the chain's loop runs the single-path line."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.lines import load_line
from webline.model.web_graph import BranchedLine, general_from_file, one_web_line
from webline.spec.branched.schema import BranchedLineSpec
from webline.spec.load import is_branched, read_any
from webline.spec.schema import LineSpec


def load_one_web(source: Line | LineSpec | str | Path | dict[str, Any]) -> BranchedLine:
    """The single-path line ``source`` (a line, its spec, a dict as read from TOML, a line
    file path or a built-in line's name) as a line of one web (``spec.one_web``), labelled
    as ``source`` is. Raises ``LineFileError`` naming the file and the key the single-path
    file gives each problem (a problem of the line, or a feature the line of webs does not
    run), ``ArgumentError`` for a ``source`` of another type."""
    text = None
    if isinstance(source, str | Path):
        data, text, label = read_any(source)
        return one_web_line(data, text, label)
    if isinstance(source, BranchedLine) and source.single_path is not None:
        return source
    if isinstance(source, Line):
        data, label = source.spec.model_dump(exclude_none=True), source.source
    elif isinstance(source, LineSpec):
        data, label = source.model_dump(exclude_none=True), "<python>"
    elif isinstance(source, dict):
        data, label = source, "<dict>"
    else:
        raise ArgumentError(f"line: expected a single-path line, its spec, a dict, a line "
                            f"file path or a built-in line's name, got {type(source).__name__}")
    return one_web_line(data, text, label)


def load_general(source: BranchedLine | BranchedLineSpec | Line | LineSpec | str | Path
                 | dict[str, Any]) -> tuple[BranchedLine, bool]:
    """Any line as the general loop runs it, and whether it was translated: a branched line
    (``[[webs]]``) as it is (False), a single-path line as its line of one web
    (``load_one_web``, True). Raises as ``load_line`` and ``load_one_web`` do."""
    if isinstance(source, str | Path):  # (read once: a problem keeps the file's line number)
        data, text, label = read_any(source)
        return general_from_file(data, text, label), not is_branched(data)
    line = load_line(source)
    if line.branched:
        return line, line.single_path is not None
    return load_one_web(line), True
