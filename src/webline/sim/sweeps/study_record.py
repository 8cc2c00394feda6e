"""A study's record (``STORE/study.json``): what a study is, so that a resumed study is the
same study.

A study is its inputs: the resolved line (the line file's values with the scenario applied,
as validated: comments and layout are not the line), webline's version, the cases, the
chunk size and the settings (duration, scenario, record). The record keeps the line's values
and their SHA-256 (of the canonical JSON: keys sorted, SI numbers), so a resume of a line
edited since, a built-in line changed by an upgrade, or another webline is refused naming
what changed (``check_resume``) instead of mixing two lines or two programs in one study.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from webline.errors import ArgumentError
from webline.line import Line
from webline.version import __version__

if TYPE_CHECKING:  # annotations only: a single-path study never loads the branched line
    from webline.model.web_graph import BranchedLine

#: differences named in a refusal, at most
SHOWN = 3
#: longest value shown in a refusal [characters]
VALUE_CHARS = 40
#: what a refusal tells the user to do
WHAT_TO_DO = ("start it again (--restart, which removes its chunks) or write the new study "
              "into another folder")


def _plain(value: Any) -> Any:
    """``value`` as JSON gives it back (tuples as lists, numpy and other types as text)."""
    return json.loads(json.dumps(value, sort_keys=True, default=str))


def line_values(line: Line | BranchedLine) -> dict[str, Any]:
    """The resolved line's values as plain JSON data [SI]."""
    return _plain(line.spec.model_dump(mode="json", exclude_none=True))


def line_hash(values: Mapping[str, Any]) -> str:
    """SHA-256 (hex) of ``line_values``'s canonical JSON (keys sorted, no spaces)."""
    text = json.dumps(values, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def study_record(line: Line | BranchedLine, cases: Sequence[Mapping[str, object]], chunk: int,
                 options: Mapping[str, Any]) -> dict[str, Any]:
    """The record of a study of ``line`` (its scenario, if any, in ``options["scenario"]``,
    not yet applied) over ``cases`` in chunks of ``chunk`` with ``run_cases``'s ``options``."""
    scenario = options.get("scenario")
    resolved = line if scenario is None else line.with_scenario(str(scenario))
    values = line_values(resolved)
    return {"line": line.name, "line_source": line.source, "line_sha256": line_hash(values),
            "line_values": values, "webline_version": __version__,
            "cases": _plain([dict(c) for c in cases]), "chunk": chunk,
            "options": _plain(dict(options))}


def write_text(record: Mapping[str, Any]) -> str:
    """The record as the file holds it."""
    return json.dumps(record, sort_keys=True, indent=None)


def check_resume(path: Path, record: Mapping[str, Any], resume: bool) -> None:
    """Refuse (``ArgumentError``, exit 2) to go on with the study recorded at ``path`` unless
    ``resume`` and it is the study of ``record``: same webline, cases, settings and resolved
    line. The refusal names what changed: the version, the settings that differ, or the line
    file and its first differing keys."""
    store = path.parent
    if not resume:
        raise ArgumentError(f"{store}: holds a study already; resume it (--resume), {WHAT_TO_DO}")
    try:
        stored = json.loads(path.read_text("utf-8"))
        if not isinstance(stored, dict):
            raise ValueError("not a JSON object")
    except (OSError, ValueError) as exc:
        raise ArgumentError(f"{path}: unreadable study record ({exc}); {WHAT_TO_DO}") from None
    if "line_sha256" not in stored:
        raise ArgumentError(f"{store}: holds a study of an older webline, without a record of "
                            f"its line; it cannot be resumed: {WHAT_TO_DO}")
    if stored.get("webline_version") != record["webline_version"]:
        raise ArgumentError(
            f"{store}: holds a study of webline {stored.get('webline_version')}; this is webline "
            f"{record['webline_version']}, whose cases may differ: {WHAT_TO_DO}")
    if stored.get("cases") != record["cases"] or stored.get("chunk") != record["chunk"]:
        what = "other cases" if stored.get("cases") != record["cases"] else "another chunk size"
        raise ArgumentError(f"{store}: holds a different study ({what}); cannot resume it")
    changed = differences(stored.get("options", {}), record["options"])
    if changed:
        raise ArgumentError(f"{store}: holds a different study (other settings: "
                            f"{_listed(changed)}); cannot resume it")
    if stored["line_sha256"] != record["line_sha256"]:
        source = record["line_source"]
        was = stored.get("line_source")
        where = source if was == source else f"{source} (the study's was {was})"
        keys = differences(stored.get("line_values", {}), record["line_values"])
        raise ArgumentError(
            f"{store}: the line changed since the study began: {where} now hashes to "
            f"{record['line_sha256'][:12]}, the study's to {stored['line_sha256'][:12]} "
            f"({_listed(keys) if keys else 'values differ'}); resuming would mix two lines in "
            f"one study: {WHAT_TO_DO}")


def differences(old: Any, new: Any, prefix: str = "") -> list[tuple[str, Any, Any]]:
    """(path, old, new) of every value that differs between two JSON trees, in the order of
    ``new`` then ``old``'s own keys; list elements are named by their ``name`` key where they
    have one (as ``Line.replace`` paths are), else by index."""
    if isinstance(old, dict) and isinstance(new, dict):
        out: list[tuple[str, Any, Any]] = []
        for key in [*new, *(k for k in old if k not in new)]:
            out += differences(old.get(key), new.get(key), f"{prefix}{key}.")
        return out
    if isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        out = []
        for i, (a, b) in enumerate(zip(old, new, strict=True)):
            name = b.get("name") if isinstance(b, dict) else None
            out += differences(a, b, f"{prefix}{name if isinstance(name, str) else i}.")
        return out
    return [] if old == new else [(prefix.rstrip("."), old, new)]


def _listed(changed: list[tuple[str, Any, Any]]) -> str:
    def short(value: Any) -> str:
        text = "(none)" if value is None else json.dumps(value, ensure_ascii=False)
        return text if len(text) <= VALUE_CHARS else text[:VALUE_CHARS - 3] + "..."

    shown = [f"{path}: {short(a)} -> {short(b)}" for path, a, b in changed[:SHOWN]]
    more = len(changed) - len(shown)
    return "; ".join(shown) + (f"; and {more} more" if more else "")
