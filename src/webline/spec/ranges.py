"""Physical ranges of every quantity of a line file, in one table keyed by field.

A value outside its **hard** range is no web line at all (a 1 m thick web, a 1 nm span, a
1 GHz sample rate): the schema rejects it naming key, value and range. A value outside its
**usual** range exists but is rare enough to be a typo (a 10 m idle roller radius): ``webline
validate`` and ``webline run`` print it as a warning and ``Line.warnings`` keeps it.

Keys are ``section.field``; ``SECTIONS`` names the sections each schema model answers to
(``UnwindSpec``: "unwind", "roll", "roller"), the first match wins. A
profile's values (ramp ``initial``, steps ``value``, ...) take the range of the key that holds
the profile (``line.speed``, ``span.tension``). ``docs/line-file.md`` shows the table
rendered by ``markdown()``; a test keeps the two equal. The table itself is in
``webline.spec.range_table``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from functools import cache

from pydantic import BaseModel

from webline.errors import ArgumentError
from webline.spec.range_table import PROFILE_VALUE_FIELDS, RANGES, SECTIONS, Range, fmt
from webline.units import short, to_si

__all__ = ["PROFILE_VALUE_FIELDS", "RANGES", "SECTIONS", "Range", "argument", "fmt",
           "markdown", "numbers_of", "range_for", "sections", "walk", "warnings",
           "whole_argument"]


def sections(model: type[BaseModel]) -> tuple[str, ...]:
    """The sections of ``RANGES`` a schema model's fields look up (a generic profile model
    ``Ramp[...]`` goes by ``Ramp``)."""
    origin = model.__pydantic_generic_metadata__.get("origin") or model
    return SECTIONS.get(origin.__name__, ())


@cache
def range_for(model: type[BaseModel], field: str) -> Range | None:
    """The range of ``field`` of a schema ``model``, or None where it has none."""
    for section in sections(model):
        found = RANGES.get(f"{section}.{field}")
        if found is not None:
            return found
    return None


def numbers_of(value: object, at: str = "") -> Iterator[tuple[str, float]]:
    """(key suffix, number) of every number in a field's value: itself, a list's items, a
    profile's values (``.initial``, ``.steps[2].value``, ``.value[0]``; its times have their
    own ranges)."""
    if isinstance(value, bool) or value is None:
        return
    if isinstance(value, int | float):
        try:
            yield at, float(value)
        except OverflowError:  # an int beyond float range is beyond every range
            yield at, math.inf if value > 0 else -math.inf
    elif isinstance(value, list | tuple):
        for i, item in enumerate(value):
            yield from numbers_of(item, f"{at}[{i}]")
    elif isinstance(value, BaseModel) and hasattr(value, "type"):
        for name in ("initial", "final", "value"):
            if name in type(value).model_fields:
                yield from numbers_of(getattr(value, name), f"{at}.{name}")
        for i, step in enumerate(getattr(value, "steps", ())):
            yield from numbers_of(step.value, f"{at}.steps[{i}].value")


def walk(model: BaseModel, key: str = "") -> Iterator[tuple[str, Range, float]]:
    """(key path, range, value [SI]) of every ranged number in a validated spec."""
    for name in type(model).model_fields:
        value = getattr(model, name)
        here = f"{key}.{name}" if key else name
        found = range_for(type(model), name)
        if found is not None:
            for suffix, number in numbers_of(value):
                yield here + suffix, found, number
        children = value.items() if isinstance(value, dict) else (
            enumerate(value) if isinstance(value, list) else [(None, value)])
        for index, child in children:
            if isinstance(child, BaseModel):
                sub = here if index is None else (
                    f"{here}[{index}]" if isinstance(index, int) else f"{here}.{index}")
                yield from walk(child, sub)


def warnings(spec: BaseModel) -> list[str]:
    """'key: problem' for every value outside its usual range."""
    out = []
    for key, found, value in walk(spec):
        problem = found.usual_problem(value)
        if problem:
            out.append(f"{key}: {problem}")
    return out


def markdown() -> str:
    """The table of ranges as docs/line-file.md shows it."""
    rows = ["| key | unit | hard range (error outside) | usual range (warning outside) | why |",
            "|---|---|---|---|---|"]
    for key, found in RANGES.items():
        rows.append(f"| `{key}` | {found.unit or '-'} | {fmt(found.hard[0])} .. "
                    f"{fmt(found.hard[1])} | {fmt(found.usual[0])} .. {fmt(found.usual[1])} "
                    f"| {found.why} |")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":  # python -m webline.spec.ranges > table (paste into the docs)
    print(markdown(), end="")


def whole_argument(value: object, name: str, minimum: int,
                   expected: str = "expected a whole number", note: str = "") -> int:
    """A whole-number argument of a Python front-door function (``substeps``, ``seed``, ...)
    of at least ``minimum``; else ``ArgumentError``: "NAME: EXPECTED >= MINIMUM[NOTE], got
    VALUE". A bool is not a number here."""
    import numpy as np

    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise ArgumentError(f"{name}: {expected} >= {minimum}{note}, got {value!r}")
    return int(value)


def argument(value: object, kind: str, name: str, bound: str = ">0",
             within: str | None = None) -> float:
    """An argument of a Python front-door function (``simulate(line, "2 min")``) as an SI
    float of dimension ``kind``: a number [SI], a string with units or a pint Quantity.
    ``bound`` is ">0" or ">=0"; ``within`` names an entry of ``webline.spec.ranges.RANGES``
    whose hard range the value must respect. Raises ``ArgumentError`` naming the argument."""
    try:
        number = to_si(value, kind)
    except ValueError as exc:
        raise ArgumentError(f"{name}: {exc}") from None
    if not (number > 0 if bound == ">0" else number >= 0):
        raise ArgumentError(f"{name}: must be {bound[:-1]} {bound[-1]}, got {short(value)}")
    problem = RANGES[within].hard_problem(number) if within else None
    if problem:
        raise ArgumentError(f"{name}: {problem}")
    return number


def reference_argument(name: str, value: object) -> float:
    """A reference set by hand (``Session.set_reference``) as SI: ``"speed"`` [m/s] in the
    range of the line file's ``speed`` key, a zone's ``"<span>.tension"`` [N] in that of
    ``spans[].tension``, with the same messages; numbers [SI] or strings with units."""
    if name == "speed":
        return argument(value, "speed", f"set_reference: {name}", ">=0", "line.speed")
    return argument(value, "force", f"set_reference: {name}", ">0", "span.tension")


def session_identity(spec_json: str, *settings: object) -> str:
    """A short digest of a line's resolved spec (``spec_json``) and a session's plan
    ``settings`` (sample period, sub-steps, user drives): what a snapshot is checked
    against before it is restored."""
    import hashlib

    text = spec_json + "|" + "|".join(repr(s) for s in settings)
    return hashlib.sha256(text.encode()).hexdigest()[:16]
