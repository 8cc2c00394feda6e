"""The topology of a branched line (docs/branching.md): webs on paths of rollers, joined at
lamination nips, split at slitters, lanes wound on shared shafts; each drive's tension zone.

Pure Python over a checked ``BranchedLineSpec``: everything is numbered once here (nodes in
the file's roller order, spans web by web in path order, roll radii one per web that starts
at an unwind or ends at a rewind) and the simulation's plan reads these numbers.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any, ClassVar, Literal, NoReturn

from webline.errors import ArgumentError, LineFileError
from webline.spec.branched.check import kind_of
from webline.spec.branched.schema import BranchedLineSpec, RollChangeSpec, WebPathSpec
from webline.spec.branched.values import set_roll_radii, set_values
from webline.spec.branched.winder import check_roll_inertias, wound_web
from webline.spec.check import web_ea
from webline.spec.load import (
    branched_from_dict,
    general_loop,
    is_branched,
    parse_branched,
    read_any,
)
from webline.spec.schema import DrivenSpec, IdleSpec, LineSpec, RewindSpec, UnwindSpec

#: the notebook's view of a branched line, resolved by name when first displayed, as
#: ``webline.line.HTML_VIEW`` is (this layer imports nothing of the report)
HTML_VIEW = "webline.report.branch_report:branched_line_html"


@dataclass(frozen=True)
class Material:
    """A web's material as the simulation sees it: ``ea`` [N], ``thickness`` [m], ``width``
    [m], ``density`` [kg/m³]."""

    ea: float
    thickness: float
    width: float
    density: float


@dataclass(frozen=True)
class Span:
    """Span number ``index`` of web ``web`` (its ``k``-th), from node ``a`` to node ``b``."""

    index: int
    web: int
    k: int
    a: int
    b: int
    name: str
    length: float


@dataclass(frozen=True)
class Roll:
    """One wound radius: web ``web``'s roll on node ``node`` (``direction`` -1 unwinding,
    +1 winding), starting at ``radius`` [m]."""

    node: int
    web: int
    direction: float
    radius: float


@dataclass(frozen=True)
class Zone:
    """The tension zone of the drive on node ``node``: its ``spans`` and the ``loadcells``
    among them (several: their tensions' sum is controlled); ``sigma`` +1 where the drive
    pulls its zone (downstream of it), -1 where it feeds it (upstream)."""

    node: int
    spans: tuple[int, ...]
    loadcells: tuple[int, ...]
    sigma: float


@dataclass(frozen=True)
class BranchedLine:
    """A checked branched line and its topology. ``roll_change``: a scenario's roll change."""

    #: a line whose webs branch (``webline.line.Line.branched`` is False)
    branched: ClassVar[Literal[True]] = True

    spec: BranchedLineSpec
    source: str = "<spec>"
    roll_change: RollChangeSpec | None = None
    scenario: str | None = field(default=None)
    #: the single-path line this line of one web was read from (``spec.one_web``), or None
    single_path: LineSpec | None = field(default=None, compare=False)

    @property
    def name(self) -> str:
        return self.spec.name

    @cached_property
    def node_index(self) -> dict[str, int]:
        return {r.name: i for i, r in enumerate(self.spec.rollers)}

    @cached_property
    def web_index(self) -> dict[str, int]:
        return {w.name: k for k, w in enumerate(self.spec.webs)}

    @cached_property
    def exact(self) -> bool:
        """Whether the spans conserve web mass exactly (``web.transport``): one transport for
        the line, whose webs meet at nips and knives; the thesis's first-order form where
        any of its ``web`` tables asks for it (a dump writes every table's, the default
        "exact" included, so a line that asked for it keeps it)."""
        tables = [self.spec.web] + [w.web for w in self.spec.webs]
        return all(table.transport == "exact" for table in tables if table is not None)

    @cached_property
    def materials(self) -> tuple[Material, ...]:
        """The material of every web (module docstring of ``spec.branched.schema``)."""
        out: dict[str, Material] = {}

        def of(web: WebPathSpec) -> Material:
            if web.name in out:
                return out[web.name]
            kind = kind_of(web)
            if kind == "laminate":
                layers = [of(self.spec.webs[self.web_index[n]]) for n in web.layers or []]
                h = sum(m.thickness for m in layers)
                w = min(m.width for m in layers)
                mass = sum(m.density * m.thickness * m.width for m in layers)  # per length
                made = Material(sum(m.ea for m in layers), h, w, mass / (h * w))
            elif kind == "lane":
                assert web.slit_from is not None and web.width is not None
                base = of(self.spec.webs[self.web_index[web.slit_from]])
                h = web.thickness or base.thickness
                ea = base.ea * (web.width / base.width) * (h / base.thickness)
                made = Material(ea, h, web.width, base.density)
            else:
                spec = web.web or self.spec.web
                assert spec is not None
                made = Material(web_ea(spec), spec.thickness, spec.width, spec.density)
            out[web.name] = made
            return made

        return tuple(of(w) for w in self.spec.webs)

    @cached_property
    def spans(self) -> tuple[Span, ...]:
        out: list[Span] = []
        for w, web in enumerate(self.spec.webs):
            for k, s in enumerate(web.spans):
                a, b = self.node_index[web.path[k]], self.node_index[web.path[k + 1]]
                out.append(Span(len(out), w, k, a, b, s.name or f"{web.name}[{k}]", s.length))
        return tuple(out)

    def web_spans(self, w: int) -> list[int]:
        """Span numbers of web ``w`` in path order."""
        return [s.index for s in self.spans if s.web == w]

    @cached_property
    def rolls(self) -> tuple[Roll, ...]:
        out: list[Roll] = []
        for w, web in enumerate(self.spec.webs):
            first = self.spec.rollers[self.node_index[web.path[0]]]
            last = self.spec.rollers[self.node_index[web.path[-1]]]
            if isinstance(first, UnwindSpec):
                out.append(Roll(self.node_index[first.name], w, -1.0, first.radius))
            if isinstance(last, RewindSpec):
                out.append(Roll(self.node_index[last.name], w, 1.0, last.radius))
        return tuple(out)

    def wound_web(self, node: int) -> Any:
        """The web wound on roll ``node`` as its inertia totals see it (width [m] of its webs
        side by side, density [kg/m³] by width: ``spec.branched.winder.wound_web``)."""
        return wound_web([(self.materials[r.web].width, self.materials[r.web].density)
                          for r in self.rolls if r.node == node])

    def roll_of(self, node: int, web: int) -> int:
        """Index of web ``web``'s roll on ``node``, or -1 where ``node`` is no roll of it."""
        return next((j for j, r in enumerate(self.rolls) if r.node == node and r.web == web), -1)

    @property
    def master(self) -> int:
        return next(i for i, r in enumerate(self.spec.rollers)
                    if isinstance(r, DrivenSpec) and r.role == "master")

    @cached_property
    def drives(self) -> tuple[int, ...]:
        """Nodes with a drive, in roller order."""
        return tuple(i for i, r in enumerate(self.spec.rollers) if not isinstance(r, IdleSpec))

    @cached_property
    def junctions(self) -> frozenset[int]:
        """Nodes where a path ends and another starts (nips, slitters)."""
        starts = {self.node_index[w.path[0]] for w in self.spec.webs}
        ends = {self.node_index[w.path[-1]] for w in self.spec.webs}
        return frozenset(starts & ends)

    def span_tension_spec(self, s: int) -> Any:
        span = self.spans[s]
        return self.spec.webs[span.web].spans[span.k].tension

    @cached_property
    def zones(self) -> dict[int, Zone]:
        """Drive node -> its tension zone (``Zone``); the master has none. Raises
        ``LineFileError`` where a zone has no loadcell, two in series, or overlaps another."""
        out: dict[int, Zone] = {}
        owner: dict[int, int] = {}
        master = self.master
        for i in self.drives:
            if i == master:
                continue
            down = self._downstream_of(i, master)
            spans = self._walk(i, down)
            key = f"rollers[{i}]"
            cells = tuple(s for s in spans if self.span_tension_spec(s) is not None)
            if not cells:
                raise LineFileError(self.source, key, f"no loadcell span (a span with "
                                    f"'tension') in the zone of {self.spec.rollers[i].name!r}: "
                                    f"{', '.join(self.spans[s].name for s in spans)}")
            webs = [self.spans[s].web for s in cells]
            if len(set(webs)) < len(webs):
                raise LineFileError(self.source, key, "two loadcell spans in series in one "
                                    "zone: which one the drive controls is ambiguous")
            for s in spans:
                if s in owner:
                    raise LineFileError(self.source, key, f"its zone overlaps the zone of "
                                        f"{self.spec.rollers[owner[s]].name!r} at span "
                                        f"{self.spans[s].name!r}: ambiguous")
                owner[s] = i
            out[i] = Zone(i, tuple(spans), cells, 1.0 if not down else -1.0)
        for s in range(len(self.spans)):
            if self.span_tension_spec(s) is not None and s not in owner:
                span = self.spans[s]
                raise LineFileError(self.source, f"webs[{span.web}].spans[{span.k}].tension",
                                    "no drive's zone holds this span: nothing controls it")
        return out

    def _downstream_of(self, i: int, master: int) -> bool:
        """Whether node ``i``'s zone lies downstream of it (the master is downstream)."""
        roller = self.spec.rollers[i]
        if isinstance(roller, UnwindSpec | RewindSpec):
            return isinstance(roller, UnwindSpec)
        seen, todo = {i}, [i]
        while todo:
            n = todo.pop()
            for s in self.spans:
                if s.a == n and s.b not in seen:
                    seen.add(s.b)
                    todo.append(s.b)
        return master in seen

    def _walk(self, i: int, down: bool) -> list[int]:
        """Spans from node ``i`` towards the master up to the next driven node or junction."""
        out, todo = [], [i]
        while todo:
            n = todo.pop()
            for s in self.spans:
                if (s.a if down else s.b) != n:
                    continue
                out.append(s.index)
                m = s.b if down else s.a
                if isinstance(self.spec.rollers[m], IdleSpec) and m not in self.junctions:
                    todo.append(m)
        return sorted(out)

    def _repr_html_(self) -> str:
        """A notebook's view: the schematic (SVG) and the line's tables, drawn by
        ``HTML_VIEW``."""
        return str(_view(HTML_VIEW)(self))

    def with_scenario(self, name: str) -> BranchedLine:
        """This line with scenario ``name`` applied (speed, ``set``, roll change)."""
        if name not in self.spec.scenarios:
            known = ", ".join(self.spec.scenarios) or "none"
            raise ArgumentError(f"{self.source}: no scenario {name!r} (scenarios: {known})")
        scenario = self.spec.scenarios[name]
        data = self.spec.model_dump(exclude_none=True)
        dumped = scenario.model_dump(exclude_none=True)
        for key in ("speed", "disturbances"):  # a scenario's replace the line's
            if key in dumped:
                data[key] = dumped[key]
        if "break_" in dumped:  # docs/branching.md "Web breaks": a web_break disturbance
            data["disturbances"] = [*data.get("disturbances", []),
                                    {**dumped["break_"], "type": "web_break"}]
            data["scenarios"][name].pop("break_")  # (now the run's one web_break)
        if "splice" in dumped:  # a flying_splice disturbance (docs/winder.md, Flying splice)
            data["disturbances"] = [*data.get("disturbances", []), dumped["splice"]]
        set_roll_radii(data, dumped)  # every unwind's / rewind's (spec.branched.values)
        set_values(data, scenario.set, self.source)  # after them: it may pick one roll
        spec = branched_from_dict(data, self.source)
        return BranchedLine(spec, self.source, scenario.roll_change, name)

    def replace(self, changes: Mapping[str, object], /) -> BranchedLine:
        """A new, checked line with the values at ``changes``' paths changed, as a scenario's
        ``set`` writes them, units where the file takes them (``{"webs.film.web.ea": "50 kN",
        "webs.film.spans.film_zone.tension": "140 N", "rollers.nip.radius": 0.12}``; list
        elements by name or ``[i]``: ``webline.spec.paths``); its scenario and roll change
        kept. Raises ``LineFileError`` naming the path that does not exist (with the closest
        key) or the value's problem."""
        if not changes:
            return self
        data = self.spec.model_dump(exclude_none=True)
        set_values(data, changes, self.source)
        return _checked(BranchedLine(branched_from_dict(data, self.source), self.source,
                                     self.roll_change, self.scenario))


def load_branched(source: BranchedLine | BranchedLineSpec | str | Path | dict[str, Any]
                  ) -> BranchedLine:
    """A branched line from a line object, a spec, a dict, a TOML file or a built-in name: the
    loader behind ``webline.load_line`` (``model.lines``), for the modules that run only a
    branched line.

    Raises ``LineFileError`` naming the file, key and problem for malformed input (a line
    without ``[[webs]]`` included)."""
    if isinstance(source, BranchedLine):
        return source
    if isinstance(source, BranchedLineSpec):
        return _checked(BranchedLine(source))
    if isinstance(source, dict):
        return _checked(BranchedLine(branched_from_dict(source, "<dict>"), "<dict>"))
    data, text, label = read_any(source)
    if not is_branched(data) and not general_loop():
        raise LineFileError(label, "webs", "not a branched line (no [[webs]])")
    return general_from_file(data, text, label)


def general_from_file(data: dict[str, Any], text: str | None, label: str) -> BranchedLine:
    """Any line file's ``data`` (read from ``text``, None for a dict) as the general loop runs
    it: a file of ``[[webs]]`` as it is, a single-path file as its line of one web. The one
    place that tells the two by the file's format."""
    if is_branched(data):
        return (branched_from_file(data, text, label) if text is not None
                else _checked(BranchedLine(branched_from_dict(data, label), label)))
    return one_web_line(data, text, label)


def one_web_line(data: Mapping[str, Any], text: str | None, label: str) -> BranchedLine:
    """The single-path line file ``data`` (read from ``text``, None for a dict) as a checked
    line of one web (``spec.one_web``) labelled ``label``, which keeps its single-path spec.
    Raises ``LineFileError`` at the single-path file's keys."""
    from webline.spec.one_web import one_web_specs

    single_path, spec = one_web_specs(data, label, text)
    return _checked(BranchedLine(spec, label, single_path=single_path))


def branched_from_file(data: dict[str, Any], text: str, label: str) -> BranchedLine:
    """The checked branched line of a line file's ``data`` (read from ``text``; problems carry
    their TOML line), labelled ``label``."""
    return _checked(BranchedLine(parse_branched(data, text, label), label))


def _checked(line: BranchedLine) -> BranchedLine:
    _ = line.zones  # zones are checked when the line is loaded, not when it first runs

    def fail(key: str, problem: str) -> NoReturn:
        raise LineFileError(line.source, key, problem)

    check_roll_inertias(line.spec, {i: line.wound_web(i) for i in {r.node for r in line.rolls}},
                        fail)  # (totals need the webs' materials: J1)
    return line


def _view(hook: str) -> Any:
    """The function a display hook ``"module:function"`` names."""
    import importlib

    module, _, function = hook.partition(":")
    return getattr(importlib.import_module(module), function)
