"""Winder settings that are valid but do not act as a user expects (docs/winder.md): a taper
that changes nothing, a dancer whose load sets a tension the zone's loadcell loop is asked to
set. ``Line.warnings`` lists them with the unusual values; ``webline validate`` prints them."""

from __future__ import annotations

from webline.spec.check import zones
from webline.spec.schema import DancerSpec, LineSpec


def winder_warnings(spec: LineSpec) -> list[str]:
    """'key: problem' for every winder setting that cannot act (module docstring)."""
    out = []
    last = len(spec.rollers) - 1
    rewind = spec.rollers[last]
    taper = getattr(rewind, "taper", None)
    if taper is not None:
        factors = taper.factor if taper.type == "table" else [1.0, 1.0 - taper.taper]
        if len(set(factors)) == 1:
            out.append(f"rollers[{last}].taper: every diameter gets the same factor: the "
                       "taper does nothing")
    for first, end in zones(spec):
        for i in range(first + 1, end):
            roller = spec.rollers[i]
            if not isinstance(roller, DancerSpec):
                continue
            c = roller.dancer
            if c.use != "none" or c.stiffness > 0.0:
                continue
            problem = (f"rollers[{i}].dancer.use: the dancer {roller.name!r} has no spring, so "
                       "its load sets the zone's tension (load / 2); the zone's loadcell loop "
                       "cannot change it and walks the carriage to an end stop where the two "
                       "disagree (use = \"position\" lets the drive hold the carriage)")
            if end == last and taper is not None:
                problem += "; the rewind's taper cannot act on this zone's tension"
            out.append(problem)
    return out
