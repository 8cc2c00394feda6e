"""Taper designed for a good roll (docs/wound-roll.md, "Taper for a good roll").

The rewind's taper (``physics.taper``: linear or hyperbolic) sets the wound-on stress of each
layer, ``σ_w(D) = T_set f(D) / (w h)`` (plus a lay-on nip's share). More taper lowers the
interlayer pressure and the core pressure and lifts the hoop stress of the inner layers (less
load from above); less taper keeps more tension, which the web and process want (flat web,
no air entrained, tight outer layers). So for each form the design is the least taper whose
roll meets every limit of the rewind's ``roll_stress`` table, found by bisection on the
steady roll; the form kept is the one winding the most tension (the largest mean wound-on
stress). ``webline taper`` then runs the line with it and computes the roll from the run.

A branched line's roll is one of its rewinds' (a shaft's lanes one each, ``roller/web``): its
web's (lane's, laminate's) width, thickness and modulus, its zone's set tension for that web.
The taper is the rewind's: on a shaft of several lanes it winds all of them, so the design
is the least taper under which EVERY lane's roll meets the limits. Feasibility grows with
the taper (more taper: less pressure, less hoop compression), so that is the largest of the
lanes' own least tapers: the lane needing the most binds, the others keep a margin.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.web_graph import BranchedLine, Roll
from webline.physics.roll_stress import RollStress, core_modulus, roll_stress
from webline.physics.taper import HYPERBOLIC, LINEAR, taper_factor
from webline.physics.wound_on import wound_on_stress
from webline.spec.roll_stress import RollStressSpec
from webline.spec.schema import RewindSpec

#: the taper of each form is searched in [0, MAX_TAPER] (a factor of 0.1 at the end: little
#: tension is left to wind with)
MAX_TAPER = 0.9
#: bisection stops when the bracket is narrower than this taper [-]
TAPER_TOLERANCE = 1e-3
#: the design solves rolls of at most this many layers (layers lumped: first-order in the
#: layer thickness, test_layer_count_convergence); the chosen taper is verified in full
DESIGN_LAYERS = 2000
FORMS = {"linear": LINEAR, "hyperbolic": HYPERBOLIC}


@dataclass(frozen=True)
class Limits:
    """What a roll must meet [Pa]: hoop above ``min_hoop``, pressure at most ``max_pressure``,
    core pressure at most ``core_rating`` (None: no limit)."""

    min_hoop: float
    max_pressure: float | None
    core_rating: float | None

    def violations(self, roll: RollStress) -> list[str]:
        """What ``roll`` breaks, one phrase each ([] when it meets every limit)."""
        out = []
        if roll.hoop.min() < self.min_hoop:
            out.append(f"hoop {roll.hoop.min() / 1e6:.3g} MPa < {self.min_hoop / 1e6:.3g} MPa")
        if self.max_pressure is not None and roll.pressure.max() > self.max_pressure:
            out.append(
                f"pressure {roll.pressure.max() / 1e6:.3g} MPa > {self.max_pressure / 1e6:.3g} MPa"
            )
        if self.core_rating is not None and roll.core_pressure > self.core_rating:
            out.append(
                f"core {roll.core_pressure / 1e6:.3g} MPa > {self.core_rating / 1e6:.3g} MPa"
            )
        return out

    def margins(self, roll: RollStress) -> dict[str, float]:
        """Each stated limit's headroom in ``roll`` [Pa] (negative: broken): ``hoop`` the
        least hoop stress above ``min_hoop``, ``pressure`` and ``core`` below their limits."""
        out = {"hoop": float(roll.hoop.min()) - self.min_hoop}
        if self.max_pressure is not None:
            out["pressure"] = self.max_pressure - float(roll.pressure.max())
        if self.core_rating is not None:
            out["core"] = self.core_rating - float(roll.core_pressure)
        return out


@dataclass(frozen=True)
class RollDesign:
    """The steady roll model of a rewind: set tension ``tension`` [N], web ``width``,
    ``thickness`` [m] and in-plane modulus ``modulus`` [Pa], roll from ``core_radius`` to
    ``outer_radius`` [m], its ``spec`` (the ``roll_stress`` table); ``rewind`` the roller
    whose taper it designs, ``roll_name`` the roll (the rewind's name, on a branched line
    ``roller/web``: ``RunResult.wound_rolls``'s key)."""

    tension: float
    width: float
    thickness: float
    modulus: float
    core_radius: float
    outer_radius: float
    spec: RollStressSpec
    rewind: str = ""
    roll_name: str = ""

    @property
    def limits(self) -> Limits:
        s = self.spec
        return Limits(s.min_hoop, s.max_pressure, s.core_rating)

    def roll(self, form: str, taper: float, max_layers: int | None = None) -> RollStress:
        """The roll wound at ``tension`` times the ``form`` taper of ``taper`` [-] (layers
        lumped to at most ``max_layers``)."""
        n = max(1, round((self.outer_radius - self.core_radius) / self.thickness))
        lump = 1 if max_layers is None else max(1, math.ceil(n / max_layers))
        h = self.thickness * lump
        r = self.core_radius + h * np.arange(max(1, n // lump))
        d_c, d_max = 2.0 * self.core_radius, 2.0 * self.outer_radius
        f = np.array([taper_factor(FORMS[form], taper, d_c, d_max, 2.0 * x) for x in r])
        s = self.spec
        nip = s.nip_load / self.width if s.nip_load is not None else 0.0
        stress = wound_on_stress(self.tension * f, self.width, self.thickness, nip, s.nip_friction)
        if isinstance(s.core, str):
            core = math.inf
        else:
            core = core_modulus(
                s.core.modulus, s.core.poisson, s.core.inner_radius, self.core_radius
            )
        k1, k2 = (
            (float(s.k1 or 0.0), float(s.k2 or 0.0))
            if s.model == "pfeiffer"
            else (float(s.radial_modulus or 0.0), 0.0)
        )
        return roll_stress(
            stress,
            self.core_radius,
            h,
            tangential_modulus=s.tangential_modulus or self.modulus,
            k1=k1,
            k2=k2,
            poisson=s.poisson,
            core_stiffness=core,
        )


@dataclass(frozen=True)
class LaneMargin:
    """One roll (a lane) of a taper designed for a shaft: ``alone`` the least taper it would
    need by itself (None: none up to ``MAX_TAPER``), ``margins`` each limit's headroom [Pa]
    in its roll at the shaft's taper (``Limits.margins``; empty when there is none)."""

    roll_name: str
    alone: float | None
    margins: dict[str, float]

    @property
    def tightest(self) -> tuple[str, float]:
        """The limit with the least headroom and that headroom [Pa]."""
        return min(self.margins.items(), key=lambda kv: kv[1])


@dataclass(frozen=True)
class TaperChoice:
    """One form's least taper meeting the limits of every roll it winds (``taper`` None: none
    up to ``MAX_TAPER`` does), the violations of the taper just below it (what a smaller
    taper breaks; ``roller/web: `` before each where it winds several rolls), the mean
    wound-on stress [Pa] of the chosen rolls, the binding roll's stresses (``roll``, its name
    ``binding``: the lane needing the most taper) and each roll's ``LaneMargin``."""

    form: str
    taper: float | None
    below: list[str]
    mean_stress: float
    roll: RollStress | None
    binding: str = ""
    lanes: tuple[LaneMargin, ...] = field(default=())


@dataclass(frozen=True)
class _Site:
    """What the design needs of a roll: its rewind, name, web width, thickness [m], in-plane
    modulus [Pa] and zone's set tension profile."""

    rewind: RewindSpec
    name: str
    width: float
    thickness: float
    modulus: float
    profile: object


def _chain_sites(line: Line, roll: str | None) -> list[_Site]:
    rewind = line.rewind
    if roll is not None and roll != rewind.name:
        raise ArgumentError(f"--roll {roll!r}: {line.name} winds one roll, on {rewind.name!r}")
    web = line.spec.web
    zone = line.zones[line.zone_of_span(line.n_spans - 1)]
    return [_Site(rewind, rewind.name, web.width, web.thickness,
                  line.ea / (web.width * web.thickness), line.spec.spans[zone.loadcell].tension)]


def _branched_sites(line: BranchedLine, roll: str | None) -> list[_Site]:
    """The rolls one taper winds: ``roll`` (``roller/web``); every roll on rewind ``roll``
    (a shaft's lanes); None: every roll on the line's only rewind with a ``roll_stress``
    table (else its only rewind)."""
    rollers, webs = line.spec.rollers, line.spec.webs
    wound = [r for r in line.rolls if isinstance(rollers[r.node], RewindSpec)]
    names = [f"{rollers[r.node].name}/{webs[r.web].name}" for r in wound]
    rewinds = list(dict.fromkeys(n.split("/")[0] for n in names))
    if roll is None:
        tabled = [w for w in rewinds if getattr(rollers[line.node_index[w]], "roll_stress", None)]
        if len(tabled or rewinds) != 1:
            rolls = ", ".join(names) or "none"
            raise ArgumentError(
                f"{line.name} winds rolls on several rewinds ({rolls}): choose one with "
                "--roll REWIND (all its lanes) or --roll ROLLER/WEB")
        roll = (tabled or rewinds)[0]
    picked = [k for k, n in enumerate(names) if roll in (n, n.split("/")[0])]
    if not picked:
        raise ArgumentError(f"--roll {roll!r}: no rewound roll of {line.name} by that name "
                            f"(its rolls: {', '.join(names) or 'none'})")
    return [_branched_site(line, wound[k], names[k]) for k in picked]


def _branched_site(line: BranchedLine, r: Roll, name: str) -> _Site:
    """What the design needs of rewound roll ``r`` (a ``line.rolls`` entry) named ``name``."""
    rollers, webs = line.spec.rollers, line.spec.webs
    node, web = r.node, r.web
    rewind = rollers[node]
    assert isinstance(rewind, RewindSpec)
    zone = line.zones.get(node)
    cells = [s for s in (zone.loadcells if zone else ()) if line.spans[s].web == web]
    if not cells:
        raise ArgumentError(f"--roll {name}: {rewind.name} holds no tension loop on "
                            f"{webs[web].name} (a differential shaft sets its lanes' "
                            "tension by slip torque): no taper to design")
    m = line.materials[web]
    return _Site(rewind, name, m.width, m.thickness, m.ea / (m.width * m.thickness),
                 line.span_tension_spec(cells[0]))


def design_rolls(line: Line | BranchedLine, diameter: float | None = None,
                 roll: str | None = None) -> list[RollDesign]:
    """The steady roll model of each roll the chosen rewind's taper winds (its
    ``roll_stress`` table; ``diameter`` [m] of the finished roll overrides the table's and
    the taper's): a single-path line's one roll; on a branched line ``roll`` (``roller/web``:
    one lane), a rewind's name (all the lanes on it) or None (all the lanes of the only
    rewind with a ``roll_stress`` table)."""
    sites = (_branched_sites(line, roll) if isinstance(line, BranchedLine)
             else _chain_sites(line, roll))
    rewind = sites[0].rewind
    spec = rewind.roll_stress
    if spec is None:
        raise ArgumentError(
            f"{line.name}: rollers.{rewind.name}.roll_stress: the rewind "
            "needs a roll_stress table (docs/line-file.md#roll-stress) to "
            "design a taper"
        )
    d = diameter or spec.diameter or (rewind.taper.max_diameter if rewind.taper else None)
    if d is None:
        raise ArgumentError(
            f"{line.name}: rollers.{rewind.name}.roll_stress.diameter: give "
            "the finished roll's diameter"
        )
    if d <= 2.0 * rewind.core_radius:
        raise ArgumentError(
            f"{line.name}: the finished roll ({d:g} m) must be larger than "
            f"the core ({2.0 * rewind.core_radius:g} m)"
        )
    from webline.profiles import breakpoints

    return [RollDesign(float(breakpoints(site.profile)[1][-1]), site.width, site.thickness,
                       site.modulus, rewind.core_radius, 0.5 * d, spec, rewind.name, site.name)
            for site in sites]


def design_roll(line: Line | BranchedLine, diameter: float | None = None,
                roll: str | None = None) -> RollDesign:
    """The steady roll model of the one roll ``design_rolls`` selects (an error where the
    selection is a shaft of several lanes: use ``design_rolls``)."""
    designs = design_rolls(line, diameter, roll)
    if len(designs) != 1:
        lanes = ", ".join(d.roll_name for d in designs)
        raise ArgumentError(f"--roll {roll!r}: the shaft winds {len(designs)} lanes ({lanes}): "
                            "choose one with --roll ROLLER/WEB")
    return designs[0]


def _least_alone(design: RollDesign, form: str) -> float | None:
    """The least taper of ``form`` whose roll meets the limits (bisection on lumped layers,
    then verified on every layer and raised until it holds there); None: none does."""
    limits = design.limits

    def ok(taper: float, full: bool = False) -> bool:
        roll = design.roll(form, taper, None if full else DESIGN_LAYERS)
        return not limits.violations(roll)

    if not ok(MAX_TAPER):
        return None
    lo, hi = 0.0, MAX_TAPER
    if ok(0.0):
        hi = 0.0
    while hi - lo > TAPER_TOLERANCE:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    taper = math.ceil(hi / TAPER_TOLERANCE) * TAPER_TOLERANCE  # a round value on the safe side
    while not ok(taper, full=True) and taper < MAX_TAPER:
        taper = min(MAX_TAPER, taper + TAPER_TOLERANCE)
    return taper


def least_taper(design: RollDesign | Sequence[RollDesign], form: str) -> TaperChoice:
    """The least taper of ``form`` under which the roll (or every roll of a shaft's lanes,
    ``design`` a sequence) meets its limits: the largest of the rolls' own least tapers,
    verified on every layer of every roll and raised until all hold."""
    designs = [design] if isinstance(design, RollDesign) else list(design)
    several = len(designs) > 1

    def broken(taper: float) -> list[str]:
        return [(f"{d.roll_name}: " if several else "") + v for d in designs
                for v in d.limits.violations(d.roll(form, taper))]

    alone = [_least_alone(d, form) for d in designs]
    if any(a is None for a in alone):
        lanes = tuple(LaneMargin(d.roll_name, a, {}) for d, a in zip(designs, alone, strict=True))
        return TaperChoice(form, None, broken(MAX_TAPER), math.nan, None, lanes=lanes)
    need = [float(a) for a in alone if a is not None]
    taper = max(need)
    while broken(taper) and taper < MAX_TAPER:  # feasibility should rise with the taper
        taper = min(MAX_TAPER, taper + TAPER_TOLERANCE)
    if broken(taper):  # it did not: no taper holds every lane at once
        lanes = tuple(LaneMargin(d.roll_name, a, {}) for d, a in zip(designs, need, strict=True))
        return TaperChoice(form, None, broken(taper), math.nan, None, lanes=lanes)
    rolls = [d.roll(form, taper) for d in designs]
    k = int(np.argmax(need))
    lanes = tuple(LaneMargin(d.roll_name, a, d.limits.margins(r))
                  for d, a, r in zip(designs, need, rolls, strict=True))
    below = [] if taper <= 0.0 else broken(max(0.0, taper - 2 * TAPER_TOLERANCE))
    mean = float(np.mean([r.wound_on.mean() for r in rolls]))
    return TaperChoice(form, taper, below, mean, rolls[k], designs[k].roll_name, lanes)


def design_taper(
    line: Line | BranchedLine,
    forms: tuple[str, ...] = ("linear", "hyperbolic"),
    diameter: float | None = None,
    roll: str | None = None,
) -> list[TaperChoice]:
    """Each form's least taper meeting the limits of every roll it winds (``design_rolls``'s:
    on a shaft, all its lanes unless ``roll`` names one), the best (most mean wound-on
    stress) first; forms without a feasible taper last."""
    for form in forms:
        if form not in FORMS:
            raise ArgumentError(f"--form {form!r}: expected one of {', '.join(FORMS)}")
    designs = design_rolls(line, diameter, roll)
    choices = [least_taper(designs, form) for form in forms]
    return sorted(choices, key=lambda c: (c.taper is None, -np.nan_to_num(c.mean_stress)))


def with_taper(
    line: Line | BranchedLine,
    choice: TaperChoice,
    diameter: float | None = None,
    roll: str | None = None,
) -> Line | BranchedLine:
    """``line`` with the rewind of ``design_rolls``'s rolls wound at ``choice``'s taper (its
    ``diameter`` the finished roll's, as the design used)."""
    if choice.taper is None:
        raise ArgumentError(f"no {choice.form} taper up to {MAX_TAPER} meets the roll limits")
    design = design_rolls(line, diameter, roll)[0]
    name = design.rewind
    taper: dict[str, object] = {"type": choice.form, "taper": round(choice.taper, 6)}
    if choice.form == "linear":
        taper["max_diameter"] = 2.0 * design.outer_radius
    return line.replace(
        {
            f"rollers.{name}.taper": taper,
            f"rollers.{name}.roll_stress.diameter": 2.0 * design.outer_radius,
        }
    )
