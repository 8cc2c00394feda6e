"""What the twin reads of a line, whatever its topology: the element names its signals are
measured on, the references a log may replace (the master's speed, each loadcell's set point,
each roll's starting radius) with the ``Line.replace`` path of each, and the RK4 sub-steps its
runs take.

A single-path line and a branched one (``[[webs]]``, docs/branching.md) number their spans,
zones and rolls differently; this module is the one place of the twin that reads either, so
replay, fit and the measurement loader ask a ``Layout`` and never which kind of line they have.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

#: the dimension of a signal kind where a line's runs record it on another than
#: ``signals.COMPARED`` says: a branched run records a radius per roll (a shaft's lanes one
#: each, named ``roller/web``), a single-path run per node
BRANCHED_DIMS = {"radius": "roll"}
#: signal kinds a branched run does not record (its loop records no trim)
BRANCHED_MISSING = ("trim",)


@dataclass(frozen=True)
class SetPoint:
    """A loadcell span's tension set point: the ``span`` name, the line file's ``value``
    (a number [N] or a profile), its ``path`` for ``Line.replace`` and whether its drive
    applies a taper (the logged reference then includes it)."""

    span: str
    value: object
    path: str
    tapered: bool


@dataclass(frozen=True)
class RollStart:
    """A roll whose starting radius a log may give: the ``signal`` that measures it
    (``radius[rewind]``), the line file's ``radius`` [m] and its ``path`` ("" where the
    line file has no value of that roll alone: a lane on a shaft of several)."""

    signal: str
    radius: float
    path: str


@dataclass(frozen=True)
class Layout:
    """A line as the twin sees it: ``elements`` (dimension -> names in the order its runs
    record them: span, node, drive, dancer, roll), ``dims`` (signal kind -> dimension, where
    it differs from ``signals.COMPARED``), ``missing`` (kinds its runs do not record), the
    ``master`` roller's name, its ``set_points`` and its ``rolls``."""

    elements: Mapping[str, tuple[str, ...]]
    dims: Mapping[str, str]
    missing: tuple[str, ...]
    master: str
    set_points: tuple[SetPoint, ...]
    rolls: tuple[RollStart, ...]


def layout(line: Any) -> Layout:
    """The ``Layout`` of a loaded line (``webline.load_line``'s), single-path or branched."""
    return _branched(line) if line.branched else _single_path(line)


def default_substeps(line: Any) -> int:
    """RK4 sub-steps per controller period a run of ``line`` takes by default (from its
    fastest mode), as ``webline.simulate`` chooses them."""
    if line.branched:
        from webline.sim.branches.run import plan_and_step

        return plan_and_step(line, None, None)[2]
    from webline.sim.core.plan import compile_plan
    from webline.sim.simulate import choose_substeps

    return choose_substeps(compile_plan(line))


def _names(line: Any) -> dict[str, tuple[str, ...]]:
    """Node, drive and dancer names: the same reading for either kind of line."""
    from webline.spec.schema import DancerSpec

    rollers = line.spec.rollers
    return {"node": tuple(r.name for r in rollers),
            "drive": tuple(rollers[i].name for i in line.drives),
            "dancer": tuple(r.name for r in rollers if isinstance(r, DancerSpec))}


def _tapered(line: Any, node: int) -> bool:
    return getattr(line.spec.rollers[node], "taper", None) is not None


def _single_path(line: Any) -> Layout:
    spans = tuple(line.span_name(k) for k in range(line.n_spans))
    names = _names(line)
    ends = (0, line.n_nodes - 1)
    set_points = tuple(
        SetPoint(spans[z.loadcell], line.spec.spans[z.loadcell].tension,
                 f"spans.{spans[z.loadcell]}.tension", _tapered(line, z.controller))
        for z in line.zones)
    rolls = tuple(RollStart(f"radius[{names['node'][i]}]", float(line.spec.rollers[i].radius),
                            f"rollers.{names['node'][i]}.radius") for i in ends)
    return Layout({"span": spans, **names, "roll": tuple(names["node"][i] for i in ends)},
                  {}, (), names["node"][line.master], set_points, rolls)


def _branched(line: Any) -> Layout:
    spans = tuple(s.name for s in line.spans)
    names = _names(line)
    webs = line.spec.webs
    set_points = tuple(
        SetPoint(spans[s], line.span_tension_spec(s),
                 f"webs.{webs[line.spans[s].web].name}.spans.{spans[s]}.tension",
                 _tapered(line, node))
        for node, zone in line.zones.items() for s in zone.loadcells)
    roll_names = tuple(f"{names['node'][r.node]}/{webs[r.web].name}" for r in line.rolls)
    per_node = [r.node for r in line.rolls]
    # a roll's radius is its roller's in the line file, shared by a shaft's lanes: only a
    # roller that holds one roll takes a logged one
    rolls = tuple(RollStart(f"radius[{name}]", float(r.radius),
                            f"rollers.{names['node'][r.node]}.radius"
                            if per_node.count(r.node) == 1 else "")
                  for name, r in zip(roll_names, line.rolls, strict=True))
    return Layout({"span": spans, **names, "roll": roll_names}, BRANCHED_DIMS,
                  BRANCHED_MISSING, names["node"][line.master], set_points, rolls)
