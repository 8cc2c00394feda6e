"""A line file's source, read without the schema: its text, its TOML data and whether it is a
branched line. Nothing here imports pydantic or the schema, so that a command can learn what
kind of line it was given (``file_is_branched``) before it pays for them: ``webline run``
forks its report process first, then loads the line (issue 37)."""

from __future__ import annotations

import os
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from webline.errors import LineFileError
from webline.units import clip

BUILTIN_PACKAGE = "webline.data.lines"

#: Largest line file read [bytes]; the built-in lines are ~10 kB, 50 000 scenarios ~1.5 MB.
MAX_FILE_BYTES = 2_000_000


def builtin_lines() -> dict[str, str]:
    """Names of the built-in lines and the first line of each file's description."""
    lines = {}
    for entry in sorted(resources.files(BUILTIN_PACKAGE).iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            data = tomllib.loads(entry.read_text(encoding="utf-8"))
            lines[entry.name[:-5]] = str(data.get("description", "")).strip().split("\n")[0]
    return lines


def general_loop() -> bool:
    """Whether single-path lines load as lines of one web and run through the general loop:
    issue 33's migration switch (``WEBLINE_GENERAL_LOOP=1``; docs/architecture.md, "Chain
    lines on the general loop"), until it is the only way."""
    return os.environ.get("WEBLINE_GENERAL_LOOP", "") not in ("", "0")


def is_branched(data: Any) -> bool:
    """Whether a line file's data is a branched line (``[[webs]]``, docs/branching.md)."""
    return isinstance(data, dict) and "webs" in data


def file_is_branched(source: str | Path) -> bool:
    """Whether the line file at ``source`` (a path or a built-in line's name) is a branched
    line; False where it cannot be read (loading it then says why). Reads the file's keys
    only: a single-path line's run does not import the branched schema."""
    try:
        return is_branched(read_any(source)[0])
    except LineFileError:
        return False


def read_any(source: str | Path) -> tuple[dict[str, Any], str, str]:
    """(TOML data, text, file label) of a line file path or a built-in line's name."""
    text, label = read_text(source)
    return parse_toml(text, label), text, label


def read_text(source: str | Path) -> tuple[str, str]:
    """(text, file label) of a line file path or a built-in line's name."""
    path = Path(source)
    if path.suffix == ".toml" or path.exists():
        label = str(source)
        try:
            with path.open("rb") as handle:  # at most the limit, even from /dev/zero
                raw = handle.read(MAX_FILE_BYTES + 1)
        except FileNotFoundError:
            raise LineFileError(label, "(file)", "no such file") from None
        except OSError as exc:
            raise LineFileError(label, "(file)", f"cannot read: {exc.strerror or exc}") from None
        if len(raw) > MAX_FILE_BYTES:
            raise LineFileError(
                label, "(file)", f"larger than a line file may be ({MAX_FILE_BYTES} bytes)"
            )
        if b"\0" in raw:
            raise LineFileError(label, "(file)", "contains NUL bytes: not a text file")
        try:
            return raw.decode("utf-8-sig"), label  # a byte-order mark is fine
        except UnicodeDecodeError as exc:
            raise LineFileError(label, "(file)", f"not UTF-8 text (byte {exc.start})") from None
    name = str(source)
    if name not in builtin_lines():
        known = ", ".join(builtin_lines())
        raise LineFileError(
            clip(name, 100), "(name)", f"no such file or built-in line (built-in: {known})"
        )
    label = f"{name}.toml (built-in)"
    return resources.files(BUILTIN_PACKAGE).joinpath(f"{name}.toml").read_text("utf-8"), label


def parse_toml(text: str, label: str) -> dict[str, Any]:
    """The TOML data of a line file's ``text`` (``LineFileError`` naming ``label`` else)."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise LineFileError(label, "(syntax)", str(exc)) from None
    except RecursionError:
        raise LineFileError(label, "(syntax)", "arrays or tables nested too deeply") from None
    except ValueError as exc:  # e.g. an integer of more than 4300 digits
        raise LineFileError(label, "(syntax)", clip(str(exc), 200)) from None
