"""The cases of a batch, built with as little Python per case as their results allow.

A case is the base line with some values changed (``Line.replace`` paths). What each case
still needs in Python, and why:

- **its line**: the base line is validated once; a case re-validates only the elements its
  paths touch (``web``, ``control``, one roller, span or disturbance: the same pydantic
  validators and range table as a line file), then the checks across keys
  (``spec.check.check_spec``). A path it cannot place (a whole list, ``scenarios``, a
  top-level profile) takes ``Line.replace``; so does a value the element refuses, so that the
  error is ``Line.replace``'s (a ``LineFileError`` naming the path);
- **its plan**: patched from the base line's plan where only the drive table, the web's
  row and the operating point's equilibrium can differ (``sim.core.plan_patch``), else
  ``compile_plan``: the operating point, the controller designs and the tables that depend
  on them;
- **its initial state**, at that operating point;
- **its linear models** at t = 0, open and closed loop: the verdict's stability check needs
  the closed loop (built on the open one) anyway, and the RK4 step is chosen from both.

The eigenvalues of all the cases' models are computed in one batched LAPACK call per block
(``numpy.linalg.eigvals`` on a stack), not once per case, and the sub-steps of each case
follow from them (``batch_rates``).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal, TypeVar, get_args

import numpy as np
from pydantic import BaseModel, TypeAdapter, ValidationError

from webline.errors import ArgumentError, LineFileError
from webline.line import Line
from webline.sim.core import kernel
from webline.sim.core.plan import Plan, equilibrium_plan_state
from webline.sim.core.plan_patch import CasePlans
from webline.sim.linear import budget
from webline.sim.linear.fastest import DENSE_STATES
from webline.sim.linear.linearize import fastest_mode, plan_linear_model
from webline.sim.linear.steps import record_every
from webline.sim.simulate import choose_substeps
from webline.spec.check import check_spec
from webline.spec.paths import set_parts, split_path
from webline.spec.ranges import range_for
from webline.spec.schema import LineSpec

if TYPE_CHECKING:  # annotations only: a single-path study never loads the branched line
    from webline.model.web_graph import BranchedLine

#: top-level tables a case may change one key of in place (everything else: Line.replace)
_TABLES = ("web", "control")
_LISTS = ("rollers", "spans", "disturbances")


class _Unplaced(Exception):
    """A change the in-place route does not handle; ``Line.replace`` takes it."""


@functools.cache
def _adapter(top: str) -> TypeAdapter[Any]:
    """Validator of one element of the top-level list ``top``, or of the table ``top``."""
    annotation: Any = LineSpec.model_fields[top].annotation
    return TypeAdapter(get_args(annotation)[0] if top in _LISTS else annotation)


def _element(items: Sequence[Any], part: str | int) -> int:
    """Index of a list element chosen by index or by name (as ``spec.paths`` does)."""
    if isinstance(part, int) or part.lstrip("-").isdigit():
        index = int(part)
        if not -len(items) <= index < len(items):
            raise _Unplaced
        return index % len(items)
    for i, item in enumerate(items):
        if getattr(item, "name", None) == part:
            return i
    raise _Unplaced


#: a path with more values than this is checked at its extremes only (ranges are intervals)
CHECK_ALL_BELOW = 64
AnyLine = TypeVar("AnyLine", Line, "BranchedLine")


def probe_values(base: AnyLine, cases: Sequence[Mapping[str, object]],
                 what: Mapping[str, str],
                 derive: Callable[[AnyLine, Mapping[str, object]], AnyLine]) -> list[AnyLine]:
    """Refuse a study before any case runs when a path's values leave what the line accepts
    (ranges, cross-key checks): every value of a path with few of them, else its smallest and
    largest. Raises ``ArgumentError`` naming the path, what produced the values
    (``what[path]``: "the values", "the samples of normal(...)") and the line's message; a
    value that only fails in combination still fails when its case is built. ``derive``
    makes ``base`` with one change (``derive_line`` or the branched one). Returns the lines
    checked (the probes of the work estimate)."""
    probes: list[AnyLine] = []
    for path, source in what.items():
        values = [case[path] for case in cases if path in case]
        if len(values) > CHECK_ALL_BELOW and all(isinstance(v, float | int) for v in values):
            values = [min(values), max(values)]  # type: ignore[type-var]
        for value in values[:CHECK_ALL_BELOW]:
            try:
                probes.append(derive(base, {path: value}))
            except LineFileError as exc:
                raise ArgumentError(f"{path}: {source} include {value!r}, which the line "
                                    f"refuses ({exc}); no case was run") from None
    return probes


def derive_line(base: Line, changes: Mapping[str, object]) -> Line:
    """``base.replace(changes)``, re-validating only the elements the changes touch (module
    docstring); the spec is equal to ``Line.replace``'s. Raises ``LineFileError`` naming the
    path for a bad value."""
    if not changes:
        return base
    spec = base.spec
    try:
        touched: dict[tuple[str, int], dict[str, Any]] = {}
        for path, value in changes.items():
            parts = split_path(path)
            top = parts[0]
            if top in _TABLES and len(parts) >= 2:
                where = (str(top), -1)
                rest = parts[1:]
                if where not in touched:
                    touched[where] = getattr(spec, top).model_dump(exclude_none=True)
            elif top in _LISTS and len(parts) >= 3:
                items = getattr(spec, str(top))
                where = (str(top), _element(items, parts[1]))
                rest = parts[2:]
                if where not in touched:
                    touched[where] = items[where[1]].model_dump(exclude_none=True)
            else:
                raise _Unplaced
            set_parts(touched[where], rest, value)
        updates: dict[str, Any] = {}
        for (top, index), data in touched.items():
            element = _adapter(top).validate_python(data)
            if index < 0:
                updates[top] = element
            else:
                items = list(updates.get(top, getattr(spec, top)))
                items[index] = element
                updates[top] = items
    except (_Unplaced, LineFileError, ValueError, ValidationError):
        return base.replace(dict(changes))  # its own message for whatever is wrong
    new = spec.model_copy(update=updates)
    check_spec(new, base.source)
    return Line(new, base.source)


def case_value(line: Line | BranchedLine, path: str) -> object:
    """The value at ``path`` in ``line``'s validated spec [SI for quantities]."""
    node: Any = line.spec
    for part in split_path(path):
        node = _child(node, part)
    return node


def path_unit(line: Line | BranchedLine, path: str) -> str | None:
    """The SI unit of the quantity at ``path`` in ``line`` (``"rad/s"``, ``"N"``, ``"1"`` for
    a ratio, as CF conventions write it), from the range table of its field
    (``spec.ranges``); None where the field has none (a table, a name, a choice)."""
    parts = split_path(path)
    holder: Any = line.spec
    try:
        for part in parts[:-1]:
            holder = _child(holder, part)
    except (AttributeError, KeyError, IndexError, _Unplaced):
        return None
    found = range_for(type(holder), str(parts[-1])) if isinstance(holder, BaseModel) else None
    return None if found is None else (found.unit or "1")


def _child(node: Any, part: str | int) -> Any:
    if isinstance(node, list | tuple):
        return node[_element(node, part)]
    if isinstance(node, Mapping):
        return node[str(part)]
    return getattr(node, str(part))


def batch_rates(plans: Sequence[Plan]) -> list[float]:
    """Fastest mode [1/s] of each plan: the largest |λ| of its open- and closed-loop linear
    models at t = 0, what ``linearize.fastest_mode`` gives (exact eigenvalues, up to LAPACK's
    rounding, for models of up to ``fastest.DENSE_STATES`` states; larger ones take
    ``fastest_mode`` itself, a rigorous bound). The models stay cached on each plan for the
    stability check of its verdict; the eigenvalues come from one batched call per shape."""
    rates = [0.0] * len(plans)
    stacks: dict[tuple[int, int], list[int]] = {}
    for c, plan in enumerate(plans):
        a_open = plan_linear_model(plan, loop="open").a
        a_closed = plan_linear_model(plan, loop="closed").a
        if max(a_open.shape[0], a_closed.shape[0]) > DENSE_STATES:
            rates[c] = fastest_mode(plan)
        else:
            stacks.setdefault((a_open.shape[0], a_closed.shape[0]), []).append(c)
    loops: tuple[Literal["open", "closed"], ...] = ("open", "closed")
    for sizes, idx in stacks.items():
        for loop, n in zip(loops, sizes, strict=True):
            if n == 0:
                continue
            stack = np.stack([plan_linear_model(plans[c], loop=loop).a for c in idx])
            values = np.linalg.eigvals(stack)
            for j, c in enumerate(idx):
                rates[c] = max(rates[c], float(np.abs(values[j]).max()))
                if loop == "closed":  # what plan_eigenvalues would compute, for the verdict
                    eig = values[j].copy()
                    eig.setflags(write=False)
                    plans[c].memo.setdefault(("eigenvalues", "closed", 0.0), eig)
    return rates


@dataclass
class Built:
    """Plans, initial states and run settings of a block of cases, ready for ``run_batch``;
    ``seconds``: the wall time building them took [s]."""

    plans: list[Plan]
    states: list[tuple[np.ndarray, np.ndarray, np.ndarray]]
    n_ticks: list[int]
    substeps: list[int]
    every: list[int]
    seconds: float


def build_cases(base: Line, cases: Sequence[Mapping[str, object]], duration: float,
                case_plans: CasePlans | None = None) -> Built:
    """The ``Built`` block of ``cases`` (changes to ``base``) for runs of ``duration`` [s];
    ``case_plans``: the study's ``CasePlans`` of ``base`` (default: made here), which patches
    each case's plan from the base's where it can (``sim.core.plan_patch``)."""
    started = time.perf_counter()
    case_plans = CasePlans(base) if case_plans is None else case_plans
    plans = [case_plans.plan_of(derive_line(base, changes), changes) for changes in cases]
    rates = batch_rates(plans)
    built = Built(plans, [], [], [], [], 0.0)
    for plan, rate in zip(plans, rates, strict=True):
        x, istate = equilibrium_plan_state(plan)
        built.states.append((x, istate, kernel.initial_slip(plan, x)))
        ticks = max(1, round(duration / plan.dt))
        built.n_ticks.append(ticks)
        built.substeps.append(choose_substeps(plan, rate))
        built.every.append(record_every(ticks, plan.dt))  # as simulate's
        columns = kernel.record_width(plan.n_x, plan.drives.shape[0], plan.line.n_nodes)
        budget.check_work(plan.line, budget.estimate(ticks, built.substeps[-1], built.every[-1],
                                                     columns), plan.dt)  # as run refuses
    built.seconds = time.perf_counter() - started
    return built

