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
web's (lane's, laminate's) width, thickness and modulus, its zone's set tension for that web;
the taper is the rewind's (on a shaft of several lanes: the shaft's, for all of them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.web_graph import BranchedLine
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
class TaperChoice:
    """One form's least taper meeting the limits (``taper`` None: none up to ``MAX_TAPER``
    does), the violations of the taper just below it (what a smaller taper breaks), and the
    mean wound-on stress [Pa] of the chosen roll."""

    form: str
    taper: float | None
    below: list[str]
    mean_stress: float
    roll: RollStress | None


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


def _chain_site(line: Line, roll: str | None) -> _Site:
    rewind = line.rewind
    if roll is not None and roll != rewind.name:
        raise ArgumentError(f"--roll {roll!r}: {line.name} winds one roll, on {rewind.name!r}")
    web = line.spec.web
    zone = line.zones[line.zone_of_span(line.n_spans - 1)]
    return _Site(rewind, rewind.name, web.width, web.thickness,
                 line.ea / (web.width * web.thickness), line.spec.spans[zone.loadcell].tension)


def _branched_site(line: BranchedLine, roll: str | None) -> _Site:
    """The rewound roll ``roll`` (``roller/web``, or a rewind's name where it winds one
    roll; None: the line's only rewound roll)."""
    rollers, webs = line.spec.rollers, line.spec.webs
    wound = [r for r in line.rolls if isinstance(rollers[r.node], RewindSpec)]
    names = [f"{rollers[r.node].name}/{webs[r.web].name}" for r in wound]
    picked = [k for k, n in enumerate(names) if roll in (None, n, n.split("/")[0])]
    if len(picked) != 1:
        rolls = ", ".join(names) or "none"
        if roll is None:
            raise ArgumentError(
                f"{line.name} winds several rolls ({rolls}): choose one with --roll ROLLER/WEB")
        if picked:  # a shaft of several lanes
            lanes = ", ".join(names[k] for k in picked)
            raise ArgumentError(f"--roll {roll!r}: the shaft winds {len(picked)} lanes "
                                f"({lanes}): choose one with --roll ROLLER/WEB")
        raise ArgumentError(f"--roll {roll!r}: no rewound roll of {line.name} by that name "
                            f"(its rolls: {rolls})")
    r, name = wound[picked[0]], names[picked[0]]
    rewind = rollers[r.node]
    assert isinstance(rewind, RewindSpec)
    zone = line.zones.get(r.node)
    cells = [s for s in (zone.loadcells if zone else ()) if line.spans[s].web == r.web]
    if not cells:
        raise ArgumentError(f"--roll {name}: {rewind.name} holds no tension loop on "
                            f"{webs[r.web].name} (a differential shaft sets its lanes' "
                            "tension by slip torque): no taper to design")
    m = line.materials[r.web]
    return _Site(rewind, name, m.width, m.thickness, m.ea / (m.width * m.thickness),
                 line.span_tension_spec(cells[0]))


def design_roll(line: Line | BranchedLine, diameter: float | None = None,
                roll: str | None = None) -> RollDesign:
    """The steady roll model of ``line``'s rewind (its ``roll_stress`` table; ``diameter``
    [m] of the finished roll overrides the table's and the taper's); on a branched line
    the roll ``roll`` (``roller/web``, or a rewind winding one roll; None: the only one)."""
    site = _branched_site(line, roll) if isinstance(line, BranchedLine) else _chain_site(
        line, roll)
    rewind = site.rewind
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

    _, values = breakpoints(site.profile)
    return RollDesign(
        float(values[-1]),
        site.width,
        site.thickness,
        site.modulus,
        rewind.core_radius,
        0.5 * d,
        spec,
        rewind.name,
        site.name,
    )


def least_taper(design: RollDesign, form: str) -> TaperChoice:
    """The least taper of ``form`` whose roll meets the limits (bisection on lumped layers,
    then verified on every layer and raised until it holds there)."""
    limits = design.limits

    def ok(taper: float, full: bool = False) -> bool:
        roll = design.roll(form, taper, None if full else DESIGN_LAYERS)
        return not limits.violations(roll)

    if not ok(MAX_TAPER):
        return TaperChoice(
            form, None, limits.violations(design.roll(form, MAX_TAPER)), math.nan, None
        )
    lo, hi = 0.0, MAX_TAPER
    if ok(0.0):
        hi = 0.0
    while hi - lo > TAPER_TOLERANCE:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    taper = math.ceil(hi / TAPER_TOLERANCE) * TAPER_TOLERANCE  # a round value on the safe side
    while not ok(taper, full=True) and taper < MAX_TAPER:
        taper = min(MAX_TAPER, taper + TAPER_TOLERANCE)
    roll = design.roll(form, taper)
    below = (
        []
        if taper <= 0.0
        else limits.violations(design.roll(form, max(0.0, taper - 2 * TAPER_TOLERANCE)))
    )
    return TaperChoice(form, taper, below, float(roll.wound_on.mean()), roll)


def design_taper(
    line: Line | BranchedLine,
    forms: tuple[str, ...] = ("linear", "hyperbolic"),
    diameter: float | None = None,
    roll: str | None = None,
) -> list[TaperChoice]:
    """Each form's least taper meeting the roll's limits (``design_roll``'s roll), the best
    (most mean wound-on stress) first; forms without a feasible taper last."""
    for form in forms:
        if form not in FORMS:
            raise ArgumentError(f"--form {form!r}: expected one of {', '.join(FORMS)}")
    design = design_roll(line, diameter, roll)
    choices = [least_taper(design, form) for form in forms]
    return sorted(choices, key=lambda c: (c.taper is None, -np.nan_to_num(c.mean_stress)))


def with_taper(
    line: Line | BranchedLine,
    choice: TaperChoice,
    diameter: float | None = None,
    roll: str | None = None,
) -> Line | BranchedLine:
    """``line`` with the rewind of ``design_roll``'s roll wound at ``choice``'s taper (its
    ``diameter`` the finished roll's, as the design used)."""
    if choice.taper is None:
        raise ArgumentError(f"no {choice.form} taper up to {MAX_TAPER} meets the roll limits")
    design = design_roll(line, diameter, roll)
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
