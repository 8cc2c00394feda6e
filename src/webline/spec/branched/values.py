"""Values of a branched line changed by path (``--set``, ``BranchedLine.replace``, sweeps) and
a scenario's starting roll radii (``unwind_radius``, ``rewind_radius``; docs/branching.md,
"Options and scenario keys").

A branched line may have several unwinds and rewinds (a laminator's two unwinds, a slitter's
shafts of lanes). A scenario's ``unwind_radius`` is the starting radius of EVERY unwind and
``rewind_radius`` of EVERY rewind (each lane on a shaft starts at its shaft's radius), as a
run that starts on fresh rolls all round; one roll alone is set by its path in the
scenario's ``set`` (``"rollers.unwind_foil.radius"``), which is applied after them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, NoReturn

from webline.spec.paths import set_path, split_path

Fail = Callable[[str, str], NoReturn]

#: a web's stiffness is given one way: setting one of these replaces the other
_STIFFNESS = {"modulus": "ea", "ea": "modulus"}

#: scenario key -> the roller ``type`` whose starting radius it gives
ROLL_KEYS = {"unwind_radius": "unwind", "rewind_radius": "rewind"}


def set_values(data: dict[str, Any], changes: Mapping[str, object], file: str) -> None:
    """Set each path of ``changes`` in ``data`` (a dumped branched spec), in place, as a
    scenario's ``set`` does; ``LineFileError`` naming a path that does not exist (with the
    closest key). Setting a web's ``modulus`` drops its ``ea`` and the reverse."""
    for path, value in changes.items():
        _one_stiffness(data, path)
        set_path(data, path, value, file)


def _one_stiffness(data: dict[str, Any], path: str) -> None:
    """Setting ``webs.W.web.modulus`` on a web that gives ``ea`` (or the reverse) replaces
    it: a web's stiffness is given one way (``ea`` would otherwise win, silently)."""
    try:
        parts = split_path(path)
    except ValueError:
        return  # set_path says what is wrong with it
    if len(parts) != 4 or parts[0] != "webs" or parts[2] != "web" or parts[3] not in _STIFFNESS:
        return
    for k, web in enumerate(data.get("webs", [])):
        if str(parts[1]) in (web.get("name"), str(k)) and isinstance(web.get("web"), dict):
            web["web"].pop(_STIFFNESS[str(parts[3])], None)


def set_roll_radii(data: dict[str, Any], scenario: Mapping[str, Any]) -> None:
    """Give every unwind of ``data`` (a dumped branched spec) the ``scenario``'s (dumped)
    ``unwind_radius`` [m] and every rewind its ``rewind_radius`` [m], where it gives them."""
    for key, kind in ROLL_KEYS.items():
        radius = scenario.get(key)
        if radius is None:
            continue
        for roller in data["rollers"]:
            if roller.get("type") == kind:
                roller["radius"] = radius


def check_roll_radii(spec: Any, fail: Fail) -> None:
    """Every roll's ``radius`` above its ``core_radius`` (as the chain's check), and each
    scenario's ``unwind_radius`` / ``rewind_radius`` (``spec``: a ``BranchedLineSpec``): the
    line has a roll of that kind, and the radius lies above the core of every one of them
    (a roll starts with web on it)."""
    for i, roller in enumerate(spec.rollers):
        if roller.type in ROLL_KEYS.values() and roller.core_radius >= roller.radius:
            fail(f"rollers[{i}].core_radius", f"must be below the roll radius "
                 f"{roller.radius:g} m, got {roller.core_radius:g} m")
    for name, scenario in spec.scenarios.items():
        for key, kind in ROLL_KEYS.items():
            radius = getattr(scenario, key)
            if radius is None:
                continue
            rolls = [r for r in spec.rollers if r.type == kind]
            if not rolls:
                fail(f"scenarios.{name}.{key}", f"this line has no {kind}")
            for roll in rolls:
                if radius <= roll.core_radius:
                    fail(f"scenarios.{name}.{key}", f"{radius:g} m must be above the core "
                         f"radius of every {kind}: {roll.name!r}'s is {roll.core_radius:g} m")


def radius_changes(spec: Any, unwind_radius: object = None, rewind_radius: object = None
                   ) -> dict[str, object]:
    """The paths and radii [m] (``rollers[i].radius``) that start every unwind of ``spec``
    (a ``BranchedLineSpec``) at ``unwind_radius`` and every rewind at ``rewind_radius``
    (numbers [m] or strings with units; None: the file's), as a scenario's keys of those
    names do. ``ArgumentError`` naming the argument for a radius not above a roll's core or
    a line with no roll of that kind."""
    from webline.errors import ArgumentError
    from webline.spec.ranges import argument

    changes: dict[str, object] = {}
    for (key, kind), given in zip(ROLL_KEYS.items(), (unwind_radius, rewind_radius),
                                  strict=True):
        if given is None:
            continue
        radius = argument(given, "length", key, ">0")
        rolls = [(i, r) for i, r in enumerate(spec.rollers) if r.type == kind]
        if not rolls:
            raise ArgumentError(f"{key}: this line has no {kind}")
        for i, roll in rolls:
            if radius <= roll.core_radius:
                raise ArgumentError(f"{key}: {radius:g} m must be above the core radius of "
                                    f"every {kind}: {roll.name!r}'s is {roll.core_radius:g} m")
            changes[f"rollers[{i}].radius"] = radius
    return changes
