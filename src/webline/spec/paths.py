"""Nested key paths into a line spec: ``"rollers.process.controller.tension_bandwidth"``.

A path is dot-separated keys; an element of a list (``rollers``, ``spans``, ``disturbances``)
is chosen by its ``name`` (``rollers.process``, ``spans.span2``) or by its index
(``rollers[2]``, ``spans.1``). Values are what a line file takes there: numbers (SI), strings
with units (``"9 kN"``), pint quantities, tables. ``Line.replace``, scenarios' ``set`` table and
the CLI's ``--set PATH=VALUE`` all use this one module.
"""

from __future__ import annotations

import difflib
import re
import tomllib
from collections.abc import Iterator, Mapping
from typing import Any

from webline.errors import LineFileError

_INDEX = re.compile(r"^(?P<key>[^\[\]]*)\[(?P<index>-?\d+)\]$")


def split_path(path: str) -> list[str | int]:
    """``"rollers[2].drive.ratio"`` -> ``["rollers", 2, "drive", "ratio"]`` (names stay str)."""
    parts: list[str | int] = []
    for piece in path.split("."):
        match = _INDEX.match(piece)
        if match:
            if match["key"]:
                parts.append(match["key"])
            parts.append(int(match["index"]))
        elif piece:
            parts.append(piece)
        else:
            raise ValueError("empty key (two dots in a row, or a leading or trailing dot)")
    if not parts:
        raise ValueError("empty path")
    return parts


def plain_value(value: object) -> object:
    """A value as a line file holds it: pint quantities become strings with units."""
    if hasattr(value, "magnitude") and hasattr(value, "units"):
        return f"{value.magnitude!r} {value.units}"
    if isinstance(value, Mapping):
        return {str(k): plain_value(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain_value(v) for v in value]
    return value


def set_path(data: dict[str, Any], path: str, value: object, file: str = "<python>") -> None:
    """Set ``path`` in the nested dict ``data`` (a dumped spec) to ``value``, in place.

    Raises ``LineFileError`` naming the path when a part of it does not exist (with the
    closest known key), so a typo never silently adds a key."""
    try:
        parts = split_path(path)
    except ValueError as exc:
        raise LineFileError(file, path, str(exc)) from None
    set_parts(data, parts, value, file)


def set_parts(data: dict[str, Any] | list[Any], parts: list[str | int], value: object,
              file: str = "<python>") -> None:
    """``set_path`` for a path already split into ``parts`` (``split_path``)."""
    node: Any = data
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = _render(parts[:depth + 1])
        if isinstance(node, list):
            index = _list_index(node, part, file, where)
            if last:
                node[index] = plain_value(value)
                return
            node = node[index]
        elif isinstance(node, dict):
            key = str(part)
            if last:
                node[key] = plain_value(value)  # a new key is checked by the strict schema
                return
            if key not in node:
                raise LineFileError(file, where, _unknown(key, list(node)))
            node = node[key]
        else:
            raise LineFileError(file, _render(parts[:depth]),
                                f"is a value, not a table: cannot set {_render(parts)!r} "
                                "inside it")


def parse_assignment(text: str) -> tuple[str, object]:
    """``"web.ea=9 kN"`` -> ``("web.ea", "9 kN")``; a TOML value (``2.5``, ``true``,
    ``{type = "ramp", ...}``, ``"quoted"``) is read as TOML, anything else as a string."""
    path, sep, raw = text.partition("=")
    path, raw = path.strip(), raw.strip()
    if not sep or not path:
        raise ValueError(f"expected PATH=VALUE, got {text!r}")
    return path, toml_value(raw)


#: Deepest nesting of arrays and inline tables a command-line value may have (a line file's
#: deepest is 3: a scenario's profile of points); tomllib recurses per level and would
#: overflow Python's stack near a few hundred.
MAX_NESTING = 32


def _depths(text: str) -> Iterator[tuple[int, str, int]]:
    """(index, character, depth of braces and brackets after it) of each character of
    ``text`` outside quotes."""
    depth, quote = 0, ""
    for i, char in enumerate(text):
        if quote:
            quote = "" if char == quote else quote
        elif char in "\"'":
            quote = char
        else:
            depth += (char in "{[") - (char in "}]")
            yield i, char, depth


def nesting(text: str) -> int:
    """How deep braces and brackets nest in ``text``, outside quotes."""
    return max([0, *(depth for _, _, depth in _depths(text))])


def toml_value(raw: str) -> object:
    """``raw`` read as a TOML value (``2.5``, ``true``, ``{type = "ramp", ...}``,
    ``"quoted"``), or as the string itself (``9 kN``). Raises ``ValueError`` for arrays or
    tables nested more than ``MAX_NESTING`` deep."""
    if nesting(raw) > MAX_NESTING:
        raise ValueError(f"{raw[:20]}...: arrays or tables nested more than {MAX_NESTING} "
                         "deep")
    try:
        return tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        return raw.strip()


def split_values(text: str) -> list[str]:
    """``text`` cut at the commas outside braces, brackets and quotes:
    ``'{type = "a", x = 1},{type = "b"}'`` is two values."""
    pieces, start = [], 0
    for i, char, depth in _depths(text):
        if char == "," and depth == 0:
            pieces.append(text[start:i])
            start = i + 1
    pieces.append(text[start:])
    return [piece.strip() for piece in pieces]


def _list_index(items: list[Any], part: str | int, file: str, where: str) -> int:
    if isinstance(part, int) or part.lstrip("-").isdigit():
        index = int(part)
        if not -len(items) <= index < len(items):
            raise LineFileError(file, where, f"index out of range (there are {len(items)})")
        return index % len(items)
    names = [item.get("name") for item in items if isinstance(item, dict)]
    if part in names:
        return names.index(part)
    known = [n for n in names if n]
    raise LineFileError(file, where, _unknown(part, known, "name"))


def _unknown(key: str, known: list[str], what: str = "key") -> str:
    close = difflib.get_close_matches(key, known, n=1)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    listed = ", ".join(map(repr, known)) if len(known) <= 12 else f"{len(known)} entries"
    return f"no {what} {key!r} here{hint} (known: {listed or 'none'})"


def _render(parts: list[str | int]) -> str:
    out = ""
    for part in parts:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else part)
    return out
