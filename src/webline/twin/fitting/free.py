"""The free parameters of a fit: ``{"rollers.unwind.inertia": "0.5 .. 5 kg*m**2"}`` read into
paths with SI bounds, the line's value as the start, and wildcards expanded
(``rollers.*.friction``: one parameter per roller that has a friction). A sensor's
calibration is a path like any other (``sensors.NAME.gain``, ``spec.sensors``) once the line
file declares the sensor."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from webline.errors import ArgumentError, LineFileError
from webline.line import Line
from webline.spec.paths import split_path

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine


@dataclass(frozen=True)
class FreeParameter:
    """A fitted value: line path, SI bounds ``low`` < ``high``, SI unit, the line's value."""

    path: str
    low: float
    high: float
    unit: str
    start: float

    def scaled(self, value: float) -> float:
        """``value`` [SI] as a share of the bounds (0 at ``low``, 1 at ``high``)."""
        return (value - self.low) / (self.high - self.low)

    def unscaled(self, x: float) -> float:
        """The SI value at share ``x`` of the bounds."""
        return self.low + x * (self.high - self.low)


def expand(data: dict[str, Any], path: str) -> list[str]:
    """``path`` with each ``*`` replaced by every list element's name (or dict key) under
    which the rest of the path exists in ``data`` (a dumped spec); ``[path]`` if it has none."""
    parts = [str(p) for p in split_path(path)]
    found: list[str] = []

    def walk(node: Any, depth: int, done: list[str]) -> None:
        if depth == len(parts):
            found.append(".".join(done))
            return
        part = parts[depth]
        if part != "*":
            if isinstance(node, dict) and part in node:
                walk(node[part], depth + 1, [*done, part])
            elif isinstance(node, list):
                for item in node:
                    if isinstance(item, dict) and item.get("name") == part:
                        walk(item, depth + 1, [*done, part])
            return
        items = (node.items() if isinstance(node, dict) else
                 ((i.get("name"), i) for i in node if isinstance(i, dict))
                 if isinstance(node, list) else ())
        for key, child in items:
            if key is not None:
                walk(child, depth + 1, [*done, str(key)])

    if "*" not in parts:
        return [path]
    walk(data, 0, [])
    return found


def lookup(data: dict[str, Any], path: str) -> Any:
    """The value at ``path`` (no wildcard) of a dumped spec, or None."""
    node: Any = data
    for part in split_path(path):
        if isinstance(node, list):
            if isinstance(part, int):
                node = node[part] if -len(node) <= part < len(node) else None
            else:
                node = next((i for i in node if isinstance(i, dict) and i.get("name") == part),
                            None)
        elif isinstance(node, dict):
            node = node.get(str(part))
        else:
            return None
        if node is None:
            return None
    return node


def _bounds(text: object, path: str) -> tuple[str, str]:
    """The two bound strings of ``"LOW .. HIGH UNIT"`` (the unit written once applies to
    both) or of a (low, high) pair."""
    from webline.units import quantity_parts

    if isinstance(text, tuple | list) and len(text) == 2:
        return str(text[0]), str(text[1])
    if not isinstance(text, str) or ".." not in text:
        raise ArgumentError(f"free {path}: expected 'LOW .. HIGH UNIT' (e.g. '0.5 .. 5 "
                            f"kg*m**2'), got {text!r}")
    low, _, high = (s.strip() for s in text.partition(".."))
    try:
        _, low_unit = quantity_parts(low)
        _, high_unit = quantity_parts(high)
    except ValueError as exc:
        raise ArgumentError(f"free {path}: {exc}") from None
    if not low_unit and high_unit:
        low = f"{low} {high_unit}"
    return low, high


def _si(line: Line | BranchedLine, path: str, value: str) -> float:
    """``value`` set at ``path`` of ``line`` and read back in SI (the line file's own check
    of the unit's kind and range)."""
    try:
        changed = line.replace({path: value})
    except LineFileError as exc:
        raise ArgumentError(f"free {path} = {value}: {exc.problem}") from None
    number = lookup(changed.spec.model_dump(exclude_none=True), path)
    if not isinstance(number, int | float):
        raise ArgumentError(f"free {path}: not a single number in the line file")
    return float(number)


def si_unit_of(text: str) -> str:
    """The SI unit (``webline.units.SI_UNITS``) of a quantity string's unit, "" if none."""
    from webline.units import SI_UNITS, quantity_parts, unit_reading

    _, unit = quantity_parts(text)
    if not unit:
        return ""
    _, dims, _ = unit_reading(unit, text)
    for si in SI_UNITS.values():
        if si and unit_reading(si, si)[1] == dims:
            return si
    return ""


def parse_free(line: Line | BranchedLine, free: Mapping[str, object]) -> list[FreeParameter]:
    """The free parameters of ``free`` (path -> "LOW .. HIGH UNIT"), wildcards expanded, in
    order. Raises ``ArgumentError`` naming the path for an unknown path, bounds that are not
    LOW < HIGH, or values the line refuses."""
    data = line.spec.model_dump(exclude_none=True)
    out: list[FreeParameter] = []
    for pattern, text in free.items():
        paths = expand(data, pattern)
        if not paths:
            raise ArgumentError(f"free {pattern}: matches no value of line {line.name!r}")
        for path in paths:
            start = lookup(data, path)
            if start is None and path.startswith("sensors."):
                raise ArgumentError(f"free {path}: line {line.name!r} declares no such sensor; "
                                    "add it to the line file's [[sensors]] (ideal: gain 1, "
                                    "offset 0, scale 1; docs/line-file.md, sensors)")
            if not isinstance(start, int | float):
                raise ArgumentError(f"free {path}: no single number there in line "
                                    f"{line.name!r} (a path such as rollers.NAME.inertia)")
            low_text, high_text = _bounds(text, path)
            low, high = _si(line, path, low_text), _si(line, path, high_text)
            if not low < high:
                raise ArgumentError(f"free {path}: the bounds must be LOW < HIGH, got "
                                    f"{low:g} .. {high:g} (SI)")
            out.append(FreeParameter(path, low, high, si_unit_of(high_text), float(start)))
    if len({p.path for p in out}) < len(out):
        raise ArgumentError("free: a parameter is named twice (a wildcard and its element?)")
    return out
