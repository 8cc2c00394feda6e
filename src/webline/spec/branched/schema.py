"""The line-file schema of a branched line: several webs, each on its own path of rollers
(docs/line-file.md, webs; docs/branching.md).

A branched line has ``[[webs]]`` in place of the top-level ``[[spans]]``. ``[[rollers]]`` is
the flat list of every roller; each web names the rollers it runs over (``path``) and has
one span table per pair of consecutive rollers. A web is a raw web (``web`` material, or the
line's ``[web]``), a laminate (``layers``: the webs gripped together at the roller where they
all end) or a lane (``slit_from``: cut from the web that ends at the slitter roller).
"""

from __future__ import annotations

from typing import Any

from pydantic import ConfigDict, Field

from webline.spec.control_schema import ControllerSpec  # noqa: F401 - used by RollerSpec
from webline.spec.disturbances import DisturbanceSpec, Name
from webline.spec.quantities import Force, Length, SpeedProfile, Strict, Time, TimeNonNeg
from webline.spec.schema import ControlSpec, RollerSpec, SpanSpec, Text, WebSpec
from webline.spec.sensors import SensorSpec
from webline.spec.splice import SpliceEvent
from webline.spec.winder import BreakEvent, StateChecksSpec


class WebPathSpec(Strict):
    """One web of a branched line: its name, material and path.

    ``web``: its material (default: the line's ``[web]``); ``layers``: the webs laminated
    into this one (EA and thickness summed, width the narrowest layer's, density keeping the
    mass per length); ``slit_from``: the web this lane is cut from, ``width`` [m] its share
    of that web and ``thickness`` [m] its own thickness (default: the base web's). ``path``:
    roller names in web order; ``spans``: one span table per pair of consecutive rollers.
    """

    name: Name
    web: WebSpec | None = None
    layers: list[Name] | None = None
    slit_from: Name | None = None
    width: Length | None = None
    thickness: Length | None = None
    path: list[Name] = Field(min_length=2)
    spans: list[SpanSpec] = Field(min_length=1)


class RollChangeSpec(Strict):
    """A new roll takes over an unwind at ``time`` [s]: its outer ``radius`` [m] (a full roll)
    and its ``wound_in_tension`` [N] (default: the old roll's). The new roll is brought to
    the web's surface speed before it takes over, as a flying splice does."""

    roller: Name
    time: TimeNonNeg
    radius: Length
    wound_in_tension: Force | None = None


class BranchedScenarioSpec(Strict):
    """A named run of a branched line: speed reference, values changed by nested path
    (``set``: ``"webs.film.spans.film_zone.tension"``, ``"webs.lane_1.thickness"``) and an
    unwind's ``roll_change`` or ``splice`` (a ``flying_splice`` added to its disturbances);
    ``disturbances`` replace the line's; ``break``: a web break (the chain's keys,
    docs/branching.md "Web breaks"), added to the disturbances as a ``web_break``;
    ``unwind_radius`` / ``rewind_radius`` [m]: the starting radius of every unwind / every
    rewind (``spec.branched.values``), applied before ``set``; ``duration`` the default run
    length [s]."""

    description: Text = ""
    duration: Time
    set: dict[str, Any] = Field(default_factory=dict)
    speed: SpeedProfile | None = None
    roll_change: RollChangeSpec | None = None
    splice: SpliceEvent | None = None  # docs/winder.md, Flying splice (an unwind's)
    disturbances: list[DisturbanceSpec] | None = None
    # ``break`` in the file (a Python keyword); a dump writes break_, which reads back too
    break_: BreakEvent | None = Field(None, alias="break")
    unwind_radius: Length | None = None  # every unwind's (spec.branched.values)
    rewind_radius: Length | None = None  # every rewind's
    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)


class BranchedLineSpec(Strict):
    """A line whose webs form a tree: laminated at nips, slit into lanes, wound on shared
    shafts (docs/branching.md). ``web`` is the default material of the webs that give none."""

    name: Name
    description: Text = ""
    source: Text = ""
    web: WebSpec | None = None
    rollers: list[RollerSpec] = Field(min_length=2)
    webs: list[WebPathSpec] = Field(min_length=1)
    speed: SpeedProfile
    control: ControlSpec = ControlSpec()
    scenarios: dict[str, BranchedScenarioSpec] = Field(default_factory=dict)
    disturbances: list[DisturbanceSpec] = Field(default_factory=list)
    #: thresholds of the verdict's winder-state findings, per web and lane zone, roll and
    #: dancer (docs/branching.md, "Winder states in the verdict")
    checks: StateChecksSpec = StateChecksSpec()
    #: loadcells' and encoders' calibration and delays (docs/branching.md, "Sensors"), as on
    #: a single-path line; the delays are checked against the sample rate in the plan
    #: (``sim.branches.sensors``)
    sensors: list[SensorSpec] = Field(default_factory=list)
