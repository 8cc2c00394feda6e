"""Map key paths (``rollers[2].drive.torque_limit``) to the TOML lines that set them.

tomllib keeps no positions, so this reads the text once, line by line, tracking ``[table]``
and ``[[array]]`` headers, ``key = value`` lines, the keys of inline tables on the same
line, and the inline tables of a multi-line array (``disturbances = [`` then one ``{...}`` a
line). It is a locator, not a parser: where it cannot tell, a path falls back to the line
of its longest known prefix, or to none.
"""

from __future__ import annotations

import re

_KEY = r'(?:[A-Za-z0-9_-]+|"[^"\n]*"|\'[^\'\n]*\')'
_DOTTED = rf"{_KEY}(?:\s*\.\s*{_KEY})*"
_HEADER = re.compile(rf"\s*(\[\[?)\s*({_DOTTED})\s*\]\]?\s*(?:#.*)?$")
_ASSIGN = re.compile(rf"\s*({_DOTTED})\s*=\s*(.*)$")
_INLINE_KEY = re.compile(rf"[{{,]\s*({_DOTTED})\s*=")
_OPEN_ARRAY = re.compile(rf"\s*{_DOTTED}\s*=\s*\[\s*(?:#.*)?$")


def _parts(dotted: str) -> list[str]:
    return [p.strip().strip("\"'") for p in re.findall(_KEY, dotted)]


def _join(path: str, part: str) -> str:
    return f"{path}.{part}" if path else part


def key_lines(text: str) -> dict[str, int]:
    """Key path -> 1-based line number for every table, array element and key of ``text``."""
    lines: dict[str, int] = {}
    arrays: dict[str, int] = {}  # array-of-tables path -> index of its last element
    table = ""
    open_array: str | None = None  # path of a multi-line array of inline tables
    element = -1
    in_string = False
    for number, raw in enumerate(text.splitlines(), start=1):
        if raw.count('"""') % 2 or raw.count("'''") % 2:
            in_string = not in_string
            if in_string:
                _record_assignment(raw, table, number, lines)
            continue
        if in_string:
            continue
        if open_array is not None:
            if raw.lstrip().startswith("{"):
                element += 1
                here = f"{open_array}[{element}]"
                lines.setdefault(here, number)
                for key in _INLINE_KEY.findall(raw):
                    lines.setdefault(_join(here, ".".join(_parts(key))), number)
            if raw.strip().startswith("]"):
                open_array = None
            continue
        header = _HEADER.match(raw)
        if header:
            parts, path = _parts(header.group(2)), ""
            for k, part in enumerate(parts):
                path = _join(path, part)
                if k == len(parts) - 1 and header.group(1) == "[[":  # a new array element
                    arrays[path] = arrays.get(path, -1) + 1
                if path in arrays:
                    path += f"[{arrays[path]}]"
            table = path
            lines.setdefault(table, number)
            continue
        assigned = _record_assignment(raw, table, number, lines)
        if assigned is not None and _OPEN_ARRAY.match(raw):
            open_array, element = assigned, -1
    return lines


def _record_assignment(raw: str, table: str, number: int, lines: dict[str, int]) -> str | None:
    match = _ASSIGN.match(raw)
    if not match:
        return None
    here = table
    for part in _parts(match.group(1)):
        here = _join(here, part)
    lines.setdefault(here, number)
    value = match.group(2)
    if value.lstrip().startswith("{"):
        for key in _INLINE_KEY.findall(value):
            lines.setdefault(_join(here, ".".join(_parts(key))), number)
    elif value.lstrip().startswith("["):  # an array of inline tables on one line
        for i, item in enumerate(re.findall(r"\{[^{}]*\}", value)):
            lines.setdefault(f"{here}[{i}]", number)
            for key in _INLINE_KEY.findall(item):
                lines.setdefault(_join(f"{here}[{i}]", ".".join(_parts(key))), number)
    return here


def locate(lines: dict[str, int], key: str) -> int | None:
    """The line of ``key`` or of its longest known prefix (None if no prefix is known)."""
    key = key.split("..")[0]
    while key:
        if key in lines:
            return lines[key]
        cut = max(key.rfind("."), key.rfind("["))
        key = key[:cut] if cut > 0 else ""
    return None
