"""Reading, checking and writing line files. Every problem becomes one ``LineFileError``."""

from __future__ import annotations

import difflib
import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

import tomli_w
from pydantic import BaseModel, ValidationError

from webline.errors import LineFileError, Problem
from webline.spec.check import check_spec
from webline.spec.locate import key_lines, locate
from webline.spec.quantities import WEB_WIDTH
from webline.spec.schema import LineSpec
from webline.spec.source import (  # noqa: F401  (re-exported: callers import them from here)
    BUILTIN_PACKAGE,
    MAX_FILE_BYTES,
    builtin_lines,
    file_is_branched,
    general_loop,
    is_branched,
    parse_toml,
    read_any,
    read_text,
)
from webline.units import clip, short, to_si

if TYPE_CHECKING:  # imported where a branched line is read: a single-path run never pays it
    from webline.spec.branched.schema import BranchedLineSpec

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
    for n, part in enumerate(loc):
        if isinstance(part, int):
            out += f"[{part}]"
            node = node[part] if isinstance(node, list) and 0 <= part < len(node) else None
        elif (isinstance(node, dict) and part == node.get("type") and n + 1 < len(loc)
              and loc[n + 1] in node):  # a tag named as a key of its table ("dancer")
            continue
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
        return f"unknown type {short(error['input'].get('type'))}; expected one of " + \
            str(error["ctx"]["expected_tags"])
    if error["type"] == "union_tag_not_found":
        return "a 'type' key is required here"
    return message


_SUFFIX = re.compile(r"^\[\[(.*?)\]\] ")  # a range validator's key suffix, see quantities.Strict
#: every key the schema knows, for "did you mean" on an unknown key
_ALL_KEYS: set[str] = set()


def _known_keys() -> set[str]:
    if not _ALL_KEYS:
        from webline.spec import schema

        for value in vars(schema).values():
            if isinstance(value, type) and issubclass(value, BaseModel):
                _ALL_KEYS.update(value.model_fields)
    return _ALL_KEYS


def _problems(exc: ValidationError, data: Any) -> list[Problem]:
    """Every error pydantic found, each at its key path; an unknown key that resembles a
    missing key of the same table is reported once, with a suggestion."""
    found: list[Problem] = []
    unknown: list[tuple[str, str, str]] = []  # (table path, key, full path)
    missing: dict[str, set[str]] = {}  # table path -> missing keys
    for error in exc.errors():
        key = _format_loc(tuple(error["loc"]), data)
        problem = _problem(error)
        suffix = _SUFFIX.match(problem)
        if suffix:
            key, problem = key + suffix.group(1), problem[suffix.end():]
        if error["type"] == "union_tag_invalid":
            key += ".type"  # the value the user wrote wrong is the 'type' key itself
        table, _, last = key.rpartition(".")
        if error["type"] == "extra_forbidden":
            unknown.append((table, last, key))
        elif error["type"] == "missing":
            missing.setdefault(table, set()).add(last)
        found.append(Problem(key, problem))
    replaced: set[str] = set()
    for table, name, key in unknown:
        close = difflib.get_close_matches(name, sorted(missing.get(table, ())), n=1, cutoff=0.6)
        if close:
            replaced.add(f"{table}.{close[0]}" if table else close[0])
        close = close or difflib.get_close_matches(name, sorted(_known_keys() - {name}), n=1,
                                                   cutoff=0.8)
        if close:
            found = [Problem(p.key, f"unknown key; did you mean {close[0]!r}?")
                     if p.key == key and p.problem == "unknown key" else p for p in found]
    out: list[Problem] = []
    for item in found:  # drop the 'missing' a suggestion explains, and duplicates
        if (item.problem == "required key is missing" and item.key in replaced) or item in out:
            continue
        out.append(item)
    return out


def _web_width(data: dict[str, Any]) -> float | None:
    """The web's width [m] as the file gives it, or None where it is missing or wrong (the
    schema reports that at web.width)."""
    web = data.get("web")
    try:
        width = to_si(web.get("width") if isinstance(web, dict) else None, "length")
    except ValueError:
        return None
    return width if 0.0 < width < math.inf else None


def spec_from_dict(data: Any, file: str = "<dict>") -> LineSpec:
    """Validate a plain dict (as read from TOML) into a checked ``LineSpec``.

    Raises ``LineFileError`` listing every problem the schema finds (or the first one of the
    checks across keys, which need a valid schema)."""
    if not isinstance(data, dict):
        raise LineFileError(file, "(top level)", "a line file must be a table of keys")
    if "webs" in data:
        raise LineFileError(file, "webs", "a branched line ([[webs]]): load it with "
                            "webline.load_line (docs/branching.md)")
    try:  # forces per width (pli, N/m) need the web's width: read it first
        spec = LineSpec.model_validate(data, context={WEB_WIDTH: _web_width(data)})
    except ValidationError as exc:
        raise LineFileError.of(file, _problems(exc, data)) from None
    except (TypeError, ValueError, ArithmeticError, RecursionError) as exc:  # defensive
        raise LineFileError(file, "(top level)", clip(str(exc), 200)) from None
    check_spec(spec, file)
    return spec


def branched_from_dict(data: Any, file: str = "<dict>") -> BranchedLineSpec:
    """Validate a plain dict into a checked ``BranchedLineSpec`` (``LineFileError`` else)."""
    from webline.spec.branched.check import check_branched
    from webline.spec.branched.schema import BranchedLineSpec

    if not isinstance(data, dict):
        raise LineFileError(file, "(top level)", "a line file must be a table of keys")
    if "spans" in data:
        raise LineFileError(file, "spans", "a branched line gives its spans in each of its "
                            "[[webs]], not at the top level")
    for key in not_yet_branched(data):
        raise LineFileError(file, key, "not yet supported on a branched line (speed, set, break, "
                            "splice, roll_change and disturbances scenarios)")
    try:
        spec = BranchedLineSpec.model_validate(data, context={WEB_WIDTH: _web_width(data)})
    except ValidationError as exc:
        raise LineFileError.of(file, _problems(exc, data)) from None
    except (TypeError, ValueError, ArithmeticError, RecursionError) as exc:  # defensive
        raise LineFileError(file, "(top level)", clip(str(exc), 200)) from None
    check_branched(spec, file)
    return spec


#: keys of a single-path line file that a branched line does not take yet (stage 1)
_NOT_YET_TOP: tuple[str, ...] = ()
_NOT_YET_SCENARIO: tuple[str, ...] = ()


def not_yet_branched(data: dict[str, Any]) -> list[str]:
    """Keys of ``data`` (a branched line file) that stage 1 does not support, as key paths."""
    keys = [key for key in _NOT_YET_TOP if key in data]
    scenarios = data.get("scenarios")
    for name, scenario in (scenarios.items() if isinstance(scenarios, dict) else ()):
        if isinstance(scenario, dict):
            keys += [f"scenarios.{name}.{key}" for key in _NOT_YET_SCENARIO if key in scenario]
    return keys


def parse_branched(data: dict[str, Any], text: str, label: str) -> BranchedLineSpec:
    """The checked branched spec of a line file's ``data``; problems carry their TOML line."""
    try:
        return branched_from_dict(data, label)
    except LineFileError as exc:
        lines = key_lines(text)
        raise LineFileError.of(label, [
            Problem(p.key, p.problem, p.line or locate(lines, p.key)) for p in exc.problems
        ]) from None


def parse_text(text: str, label: str) -> LineSpec:
    """The checked spec of a line file's ``text``; problems carry their TOML line."""
    return parse_text_data(parse_toml(text, label), text, label)


def parse_text_data(data: dict[str, Any], text: str, label: str) -> LineSpec:
    """The checked spec of a line file's ``data`` read from ``text``; problems carry their
    TOML line."""
    try:
        return spec_from_dict(data, label)
    except LineFileError as exc:
        lines = key_lines(text)
        raise LineFileError.of(label, [
            Problem(p.key, p.problem, p.line or locate(lines, p.key)) for p in exc.problems
        ]) from None


def read_spec(source: str | Path) -> tuple[LineSpec, str]:
    """Read a line from a file path or a built-in name; return the spec and its file label."""
    text, label = read_text(source)
    return parse_text(text, label), label


def dump_spec(spec: LineSpec | BranchedLineSpec) -> str:
    """TOML text of ``spec`` with every quantity in SI; loading it gives the same line."""
    data = spec.model_dump(mode="python", exclude_none=True)
    return tomli_w.dumps(data)
