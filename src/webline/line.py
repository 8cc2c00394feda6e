"""A web line: the validated spec plus its derived topology (zones, master, who controls what).

Nodes are the rollers in web order (0 = unwind roll, N = rewind roll); span k joins node k
to node k + 1. A *tension zone* is the run of spans between two consecutive driven nodes.
Each tension-controlled drive regulates the zone between itself and the next driven node
towards the master-speed roller, which is how the HSWL of thesis Fig. 4.2 is arranged.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import ClassVar, Literal

import numpy as np

from webline.spec.check import check_spec, web_ea, zones
from webline.spec.load import read_spec, spec_from_dict
from webline.spec.paths import set_path
from webline.spec.schema import (
    DrivenSpec,
    IdleSpec,
    LineSpec,
    RewindSpec,
    UnwindSpec,
)
from webline.spec.splice import FlyingSplice
from webline.spec.web_law import stretch_at
from webline.spec.web_law_checks import law_array
from webline.spec.winder import WebBreak

#: The notebook view of a line, "module:function" taking the ``Line`` and returning HTML: a
#: display hook named, not imported (the report sits layers above; resolved on first display,
#: as pandas names its plotting backend). Set it to another view to replace the report's.
HTML_VIEW = "webline.report.notebook:line_html"


@dataclass(frozen=True)
class Zone:
    """A tension zone: nodes ``first``..``last``, tension measured on span ``loadcell``,
    regulated by the drive on node ``controller``."""

    first: int
    last: int
    loadcell: int
    controller: int

    @property
    def spans(self) -> range:
        return range(self.first, self.last)


@dataclass(frozen=True)
class Line:
    """A single-path web line ready to simulate and analyse. Build it with
    ``webline.load_line``."""

    #: a line of one web on one path (``model.web_graph.BranchedLine.branched`` is True)
    branched: ClassVar[Literal[False]] = False

    spec: LineSpec
    source: str = "<python>"
    #: memo of derived objects (compiled plans), never part of equality
    memo: dict[object, object] = field(default_factory=dict, compare=False, repr=False)

    @property
    def name(self) -> str:
        return self.spec.name

    @property
    def ea(self) -> float:
        """Axial stiffness of the web E·A [N]."""
        return web_ea(self.spec.web)

    @cached_property
    def law(self) -> np.ndarray:
        """The web's stress-strain law in stretch s = EA·ε [N] (``physics.web_law``; a
        one-element array for the linear law), read-only."""
        law = law_array(self.spec.web, self.ea)
        law.setflags(write=False)
        return law

    @property
    def nonlinear(self) -> bool:
        """Whether the web's law is other than T = EA ε."""
        return self.law.size > 1

    @property
    def exact(self) -> bool:
        """Whether spans conserve web mass exactly (``web.transport``), else thesis 6.8."""
        return self.spec.web.transport == "exact"

    def stretch_of(self, tension: float) -> float:
        """Stretch EA·ε [N] at which the web carries ``tension`` [N] (itself, linear)."""
        return stretch_at(self.law, tension) if self.nonlinear else tension

    @property
    def n_nodes(self) -> int:
        return len(self.spec.rollers)

    @property
    def n_spans(self) -> int:
        return len(self.spec.spans)

    @cached_property
    def master(self) -> int:
        """Index of the master-speed roller."""
        return next(i for i, r in enumerate(self.spec.rollers)
                    if isinstance(r, DrivenSpec) and r.role == "master")

    @cached_property
    def drives(self) -> tuple[int, ...]:
        """Indices of the driven nodes (rolls and driven rollers), in web order."""
        return tuple(i for i, r in enumerate(self.spec.rollers) if not isinstance(r, IdleSpec))

    @cached_property
    def zones(self) -> tuple[Zone, ...]:
        out = []
        for first, last in zones(self.spec):
            loadcell = next(k for k in range(first, last) if self.spec.spans[k].tension is not None)
            controller = first if last <= self.master else last
            out.append(Zone(first, last, loadcell, controller))
        return tuple(out)

    @cached_property
    def warnings(self) -> tuple[str, ...]:
        """'key: problem' for every value of the line file outside its usual physical range
        (``webline.spec.ranges``): possible, but rare enough to be a slip of the unit; and
        every winder setting that cannot act (``webline.spec.winder_checks``); a web whose
        momentum flux ρA v² is a share of its tension (``spec.web_mass``)."""
        from webline.spec.ranges import warnings
        from webline.spec.web_mass import web_mass_warnings
        from webline.spec.winder_checks import winder_warnings

        return (tuple(warnings(self.spec)) + tuple(winder_warnings(self.spec))
                + tuple(web_mass_warnings(self.spec)))

    @cached_property
    def notes(self) -> tuple[str, ...]:
        """What webline derived from the file beyond its keys' plain reading (a roll's core
        inertia and wound density from its totals, ``spec.roll_inertia``), one line each."""
        from webline.spec.roll_inertia import derivation

        found = (derivation(r, self.spec.web) for r in (self.unwind, self.rewind))
        return tuple(note for note in found if note)

    def zone_of_span(self, span: int) -> int:
        return next(z for z, zone in enumerate(self.zones) if span in zone.spans)

    def controlled_zone(self, node: int) -> int | None:
        """The zone the drive on ``node`` regulates, or None for the master."""
        return next((z for z, zone in enumerate(self.zones) if zone.controller == node), None)

    def span_name(self, k: int) -> str:
        return self.spec.spans[k].name or f"span{k + 1}"

    def node_name(self, i: int) -> str:
        return self.spec.rollers[i].name

    @property
    def unwind(self) -> UnwindSpec:
        roll = self.spec.rollers[0]
        assert isinstance(roll, UnwindSpec)
        return roll

    @property
    def rewind(self) -> RewindSpec:
        roll = self.spec.rollers[-1]
        assert isinstance(roll, RewindSpec)
        return roll

    def with_scenario(self, name: str) -> Line:
        """The line as the named scenario runs it (speed, disturbances, roll radii replaced, a
        web break or a flying splice added)."""
        from webline.errors import LineFileError, Problem

        scenario = self.spec.scenarios.get(name)
        if scenario is None:
            known = ", ".join(self.spec.scenarios) or "none"
            raise LineFileError(self.source, f"scenarios.{name}",
                                f"no such scenario (this line has: {known})")
        # Every part of the scenario was validated with the file: swap them in without
        # re-validating the line (which made validating a file of N scenarios cost O(N²)),
        # keep only this scenario, and re-run the checks across keys.
        rollers = list(self.spec.rollers)
        for index, radius in ((0, scenario.unwind_radius), (-1, scenario.rewind_radius)):
            if radius is not None:
                rollers[index] = rollers[index].model_copy(update={"radius": radius})
        # the kept scenario names its own disturbances (the line's where it gave none), so that
        # the checks, and this scenario applied again, find its break and splice not yet in
        # them: without it, the line's list (its break and splice added) was the scenario's
        own = (scenario.disturbances if scenario.disturbances is not None
               else self.spec.disturbances)
        scenario = scenario.model_copy(update={"disturbances": list(own)})
        changes: dict[str, object] = {"rollers": rollers, "scenarios": {name: scenario}}
        if scenario.speed is not None:
            changes["speed"] = scenario.speed
        if scenario.disturbances is not None:
            changes["disturbances"] = scenario.disturbances
        if scenario.break_ is not None:  # docs/winder.md: a web_break disturbance
            before = (scenario.disturbances if scenario.disturbances is not None
                      else self.spec.disturbances)
            # as a plain web_break, the type a line file's disturbance has (its subclass
            # BreakEvent only lets a scenario leave ``type`` out)
            changes["disturbances"] = [*before, WebBreak(**scenario.break_.model_dump())]
        if scenario.splice is not None:  # docs/winder.md: a flying_splice disturbance
            listed = changes.get("disturbances", scenario.disturbances if
                                 scenario.disturbances is not None else self.spec.disturbances)
            changes["disturbances"] = [*listed,  # type: ignore[misc]
                                       FlyingSplice(**scenario.splice.model_dump())]
        spec = self.spec.model_copy(update=changes)
        label = f"{self.source} [scenario {name}]"
        if scenario.set:  # values set by path: validate the changed line as a whole
            data = spec.model_dump(exclude_none=True)
            try:
                for path, value in scenario.set.items():
                    set_path(data, path, value)
                return Line(spec_from_dict(data), self.source)
            except LineFileError as err:  # named where the user wrote it: the scenario's set
                raise LineFileError.of(self.source, [
                    Problem(f"scenarios.{name}.set: {p.key}", p.problem)
                    for p in err.problems]) from None
        check_spec(spec, label)
        return Line(spec, self.source)

    def __repr__(self) -> str:
        """A few lines: name, size, source and scenarios (the dataclass's own repr printed
        the whole spec, some 6 kB)."""
        scenarios = ", ".join(self.spec.scenarios) or "none"
        return (f"<webline Line {self.name!r}: {self.n_nodes} rollers, {self.n_spans} spans, "
                f"{len(self.drives)} drives, {len(self.zones)} tension zones>\n"
                f"  from {self.source}; scenarios: {scenarios}")

    def _repr_html_(self) -> str:
        """A notebook's view: the schematic (SVG) and key tables, drawn by ``HTML_VIEW``."""
        import importlib

        module, _, function = HTML_VIEW.partition(":")
        view = getattr(importlib.import_module(module), function)
        return str(view(self))

    def __reduce__(self) -> tuple[object, ...]:
        """Pickled as its plain data, validated again when unpickled (the spec's profile
        models are generic pydantic classes, which pickle cannot find by name): a line goes
        to another process (the report's, a Dask worker) whatever its profiles; its memo of
        plans stays behind."""
        return (_unpickle_line, (self.spec.model_dump(exclude_none=True), self.source))

    def replace(self, changes: Mapping[str, object] | None = None, /,
                **top_level: object) -> Line:
        """A new, validated line with some values changed.

        ``changes`` maps nested paths to values, with units where the line file takes them:
        ``line.replace({"rollers.process.controller.tension_bandwidth": "2 Hz",
        "web.ea": "9 kN", "spans.span2.length": 12})`` (list elements by name or ``[i]``,
        see ``webline.spec.paths``). Keyword arguments replace top-level keys
        (``line.replace(speed="800 ft/min")``). Raises ``LineFileError`` naming the path.
        """
        data = self.spec.model_dump(exclude_none=True)
        for path, value in {**(changes or {}), **top_level}.items():
            set_path(data, path, value, self.source)
        return Line(spec_from_dict(data, self.source), self.source)


def load_line(source: Line | str | Path | LineSpec | dict[str, object]) -> Line:
    """A single-path line from a TOML file, a built-in name (``"hswl"``), a dict or a
    ``LineSpec`` (the front door's ``webline.load_line``, ``model.lines``, loads any line).

    Raises ``LineFileError`` naming the file, key path and problem for any malformed input.
    """
    if isinstance(source, Line):
        return source
    if isinstance(source, LineSpec):
        return Line(source)
    if isinstance(source, dict):
        return Line(spec_from_dict(source, "<dict>"), "<dict>")
    if not isinstance(source, str | Path):
        from webline.errors import ArgumentError

        raise ArgumentError(f"line: expected a Line, a line file path, a built-in line's name, "
                            f"a dict or a LineSpec, got {type(source).__name__}")
    spec, label = read_spec(source)
    return Line(spec, label)


def is_roll(roller: object) -> bool:
    return isinstance(roller, UnwindSpec | RewindSpec)


def _unpickle_line(data: dict[str, object], source: str) -> Line:
    """The line pickled by ``Line.__reduce__``."""
    return Line(spec_from_dict(data, source), source)
