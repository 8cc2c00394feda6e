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


_UNION_TAGS = {"constant", "ramp", "steps", "table", "unwind", "rewind", "driven", "idle",
               "wound_in_ripple", "eccentric_roller", "speed_ripple"}


#: union tags a table may leave out (its ``type`` then defaults to the tag)
_DEFAULT_TAGS = {"cascaded_pi": "cascaded_pi"}


def _format_loc(loc: tuple[int | str, ...], data: Any = None) -> str:
    """('spans', 2, 'length') -> 'spans[2].length' (dropping pydantic's union tags).

    ``data`` is the input being validated, walked alongside ``loc``: a part that is a key
    the user wrote there (a scenario named 'ramp', say) is kept, and a part equal to the
    table's own ``type`` is the discriminator tag pydantic inserts, whatever the union.
    """
    out = ""
    node = data
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
            node = node[part] if isinstance(node, list) and 0 <= part < len(node) else None
        elif isinstance(node, dict) and part in node:
            out += f".{part}" if out else str(part)
            node = node[part]
        elif isinstance(node, dict) and part == node.get("type", _DEFAULT_TAGS.get(part)):
            continue  # discriminator tag of the table at this point (or its default type)
        elif (part in _UNION_TAGS and out) or "[" in part or "function-" in part:
            continue  # discriminator tag or validator name, not a key the user wrote
        else:
            out += f".{part}" if out else str(part)
            node = None
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
        key = _format_loc(tuple(first["loc"]), data)
        if first["type"] == "union_tag_invalid":
            key += ".type"  # the value the user wrote wrong is the 'type' key itself
        raise LineFileError(file, key, _problem(first)) from None
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
