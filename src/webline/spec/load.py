"""Reading, checking and writing line files. Every problem becomes one ``LineFileError``."""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

import tomli_w
from pydantic import ValidationError

from webline.errors import LineFileError
from webline.spec.check import check_spec
from webline.spec.schema import LineSpec

BUILTIN_PACKAGE = "webline.data.lines"


def builtin_lines() -> dict[str, str]:
    """Names of the built-in lines and the first line of each file's description."""
    lines = {}
    for entry in sorted(resources.files(BUILTIN_PACKAGE).iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            data = tomllib.loads(entry.read_text(encoding="utf-8"))
            lines[entry.name[:-5]] = str(data.get("description", "")).strip().split("\n")[0]
    return lines


def _format_loc(loc: tuple[int | str, ...]) -> str:
    """('spans', 2, 'length') -> 'spans[2].length' (dropping pydantic's union tags)."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif part in {"constant", "ramp", "steps", "table", "unwind", "rewind", "driven",
                      "idle", "wound_in_ripple", "eccentric_roller", "speed_ripple"} and out:
            continue  # discriminator tag, not a key the user wrote
        elif "[" in part or "function-" in part:
            continue
        else:
            out += f".{part}" if out else str(part)
    return out or "(top level)"


def _problem(error: Any) -> str:
    message = str(error["msg"])
    for prefix in ("Value error, ", "Assertion failed, "):
        message = message.removeprefix(prefix)
    if error["type"] == "extra_forbidden":
        return "unknown key"
    if error["type"] == "missing":
        return "required key is missing"
    if error["type"] == "union_tag_invalid":
        return f"unknown type {error['input'].get('type')!r}; expected one of " + \
            str(error["ctx"]["expected_tags"])
    if error["type"] == "union_tag_not_found":
        return "a 'type' key is required here"
    return message


def spec_from_dict(data: Any, file: str = "<dict>") -> LineSpec:
    """Validate a plain dict (as read from TOML) into a checked ``LineSpec``."""
    if not isinstance(data, dict):
        raise LineFileError(file, "(top level)", "a line file must be a table of keys")
    try:
        spec = LineSpec.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        raise LineFileError(file, _format_loc(tuple(first["loc"])), _problem(first)) from None
    except (TypeError, ValueError, ArithmeticError) as exc:  # defensive: a validator misfired
        raise LineFileError(file, "(top level)", str(exc)) from None
    check_spec(spec, file)
    return spec


def read_spec(source: str | Path) -> tuple[LineSpec, str]:
    """Read a line from a file path or a built-in name; return the spec and its file label."""
    path = Path(source)
    if path.suffix == ".toml" or path.exists():
        label = str(source)
        try:
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise LineFileError(label, "(file)", "no such file") from None
        except (OSError, UnicodeDecodeError) as exc:
            raise LineFileError(label, "(file)", f"cannot read: {exc}") from None
    else:
        name = str(source)
        if name not in builtin_lines():
            known = ", ".join(builtin_lines())
            raise LineFileError(name, "(name)",
                                f"no such file or built-in line (built-in: {known})")
        label = f"{name}.toml (built-in)"
        text = resources.files(BUILTIN_PACKAGE).joinpath(f"{name}.toml").read_text("utf-8")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise LineFileError(label, "(syntax)", str(exc)) from None
    return spec_from_dict(data, label), label


def dump_spec(spec: LineSpec) -> str:
    """TOML text of ``spec`` with every quantity in SI; loading it gives the same line."""
    data = spec.model_dump(mode="python", exclude_none=True)
    return tomli_w.dumps(data)
