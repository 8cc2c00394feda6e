"""Line-file keys of a flying splice (turret roll change) on the unwind or the rewind
(docs/winder.md, Flying splice): a new roll, brought to line speed by its own drive, takes
over the web from the old roll at a given time."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Annotated, Any, Literal

from pydantic import Field

from webline.spec.quantities import Length, Strict, si

#: the new roll's surface speed may differ from the web's by at most this fraction
MISMATCH_LIMIT = 0.5


class FlyingSplice(Strict):
    """A flying splice (docs/winder.md, S1-S3): at time ``at`` [s] the web passes from the
    roll ``roll`` (the unwind's or the rewind's name) to a new roll of diameter
    ``new_diameter`` [m] (a full roll on the unwind, a core on the rewind), which its drive
    has brought to the web's speed times (1 + ``speed_mismatch``). The new roll's drive
    takes over with its diameter preset to the new one and its speed integrator carrying
    the new roll's tension torque. ``slack`` [m] is unstrained web the splice puts into the
    span next to the roll (a paster's loop, a tape overlap; negative: web drawn taut). The
    old roll leaves the web and is stopped by its own drive (it no longer acts on the line)."""

    type: Literal["flying_splice"]
    roll: Annotated[str, Field(min_length=1, max_length=100)]
    at: Annotated[float, si("time", ">=0")]
    new_diameter: Length
    speed_mismatch: Annotated[float, Field(ge=-MISMATCH_LIMIT, le=MISMATCH_LIMIT)] = 0.0
    slack: Annotated[float, si("length")] = 0.0


class SpliceEvent(FlyingSplice):
    """A scenario's ``splice = { roll = "...", at = "20 s", new_diameter = "0.8 m" }``: a
    ``flying_splice`` disturbance added to the scenario's disturbances (``type`` may be left
    out)."""

    type: Literal["flying_splice"] = "flying_splice"


def check_splices(items: Sequence[Any], rollers: Sequence[Any], key: str,
                  fail: Callable[[str, str], Any], *, indexed: bool = True) -> None:
    """Fail on a splice of a roller that is not a roll, two splices of one roll at the same
    time, a new diameter at or below the roll's core, or a roll whose drive has a compliant
    transmission (its motor speed and twist would have to jump with the roll). Keys are
    ``key[j]`` (``key`` itself where not ``indexed``: a scenario's one ``splice``)."""
    ends = {rollers[0].name: rollers[0], rollers[-1].name: rollers[-1]}
    spliced: set[tuple[str, float]] = set()
    for j, item in enumerate(items):
        if not isinstance(item, FlyingSplice):
            continue
        here = f"{key}[{j}]" if indexed else key
        roll = ends.get(item.roll)
        if roll is None:
            fail(f"{here}.roll", f"must name the unwind or the rewind roll "
                 f"({' or '.join(repr(n) for n in ends)}), got {item.roll!r}")
            continue
        if (item.roll, item.at) in spliced:
            fail(f"{here}.at", f"{item.roll!r} is already spliced at {item.at:g} s")
        spliced.add((item.roll, item.at))
        if item.new_diameter <= 2.0 * roll.core_radius:
            fail(f"{here}.new_diameter", f"must exceed the core's diameter "
                 f"{2.0 * roll.core_radius:g} m, got {item.new_diameter:g} m")
        if getattr(roll.drive.transmission, "type", "direct") != "direct":
            fail(f"{here}.roll", f"{item.roll!r} has a {roll.drive.transmission.type} "
                 "transmission; a flying splice needs a direct drive on the roll")
