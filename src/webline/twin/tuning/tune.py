"""``webline.tune``: controller settings that minimise a tension-error objective over a set
of scenarios, subject to torque limits, stability margins and robustness.

The default objective (``OBJECTIVE``) is the sum, over the scenarios and every span with a
loadcell, of the RMS tension error divided by the span's set tension (at the initial
operating point), so a zone at 150 N and one at 200 N weigh by their relative error. Each
candidate runs every scenario through the batched kernel (``webline.sim.sweeps.sweep.run_cases``),
a whole population at once: scipy's ``differential_evolution`` (vectorised, on the
logarithms of the free values, the line's own settings in the first population) with a
bounded number of evaluations. A candidate that misses a constraint
(``tune_constraints``) is penalised above every feasible one. Among the feasible candidates,
best first, the first that passes the robustness Monte Carlo (``tune_robust``) is the result;
its gains are written explicitly (``tune_space.frozen_gains``). A branched line
(``[[webs]]``) is tuned the same way with its own pieces (``LineOps``: ``tune_branched``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from webline.errors import ArgumentError
from webline.line import Line, load_line
from webline.sim.core.plan import compile_plan
from webline.sim.sweeps.cases import derive_line
from webline.sim.sweeps.sweep import run_cases
from webline.twin.tuning.tune_constraints import (
    Constraint,
    Limits,
    run_constraints,
    stability_constraints,
)
from webline.twin.tuning.tune_robust import RobustCheck, default_uncertain, robustness
from webline.twin.tuning.tune_space import (
    FreeParameter,
    LineOps,
    default_free,
    frozen_gains,
)

OBJECTIVE = ("sum over scenarios and loadcell spans of RMS(tension - reference) / set "
             "tension [1]")
#: the default scenario set: the line's scenarios without a web break, at most this long [s]
SCENARIO_LIMIT = 60.0
#: added to the objective of a candidate that misses a constraint (above any feasible one)
PENALTY = 1000.0
#: feasible candidates tried for robustness, best first, before giving up
ROBUST_TRIES = 3

Objective = Callable[[Mapping[str, Any], Line], np.ndarray]


@dataclass(frozen=True)
class Evaluation:
    """One candidate: its free values [SI], objective [1], its terms {"scenario/span": RMS
    error / set tension}, and its constraints."""

    values: dict[str, float]
    objective: float
    terms: dict[str, float]
    constraints: tuple[Constraint, ...]

    @property
    def feasible(self) -> bool:
        return all(c.holds for c in self.constraints)

    @property
    def penalised(self) -> float:
        if self.feasible:
            return self.objective
        return PENALTY + self.objective + sum(c.violation for c in self.constraints)


@dataclass(frozen=True)
class TuneResult:
    """What ``tune`` found: the line before and the tuned line (gains explicit), the free
    parameters, both evaluations, the robustness check of the result, the gains before and
    after [SI], the evaluations used and the seconds it took."""

    line: Line
    tuned: Line
    free: tuple[FreeParameter, ...]
    scenarios: tuple[str, ...]
    limits: Limits
    before: Evaluation
    after: Evaluation
    robust: RobustCheck
    gains_before: dict[str, float]
    gains_after: dict[str, float]
    evaluations: int
    seconds: float
    objective_name: str = OBJECTIVE
    notes: tuple[str, ...] = field(default_factory=tuple)

    @property
    def holds(self) -> bool:
        """Every constraint of the tuned line holds, robustness included."""
        return self.after.feasible and self.robust.holds

    @property
    def improvement(self) -> float:
        """Relative drop of the objective [1] (0.25: a quarter lower)."""
        return 1.0 - self.after.objective / self.before.objective

    def summary(self) -> str:
        """One line: the objective before and after and whether the constraints hold."""
        word = "every constraint holds" if self.holds else "NOT every constraint holds"
        change = (f"{self.improvement:.1%} lower" if self.improvement >= 0
                  else f"{-self.improvement:.1%} higher")
        return (f"objective {self.before.objective:.4g} -> {self.after.objective:.4g} "
                f"({change}); {word} (robustness: {self.robust.passed} of {self.robust.n} "
                f"draws)")


#: what ``tune`` does with a single-path line
CHAIN = LineOps(load=load_line, default_free=default_free, derive=derive_line,
                frozen_gains=frozen_gains, run_cases=run_cases,
                set_tension=lambda line: compile_plan(line).op.tension,
                stability=stability_constraints,
                default_uncertain=default_uncertain)


def line_ops(line: Any) -> LineOps:
    """``CHAIN``, or for a branched line (``line.branched``) its ``tune_branched.BRANCHED``."""
    from webline.model.lines import load_line as load_any

    if load_any(line).branched:
        from webline.twin.tuning.tune_branched import BRANCHED

        return BRANCHED
    return CHAIN


def default_scenarios(line: Any) -> list[str]:
    """The line's scenarios without a web break that last at most ``SCENARIO_LIMIT``."""
    out = []
    for name, s in line.spec.scenarios.items():
        if getattr(s, "break_", None) is None and getattr(s, "duration", math.inf) <= (
                SCENARIO_LIMIT) and not _breaks(s):
            out.append(name)
    return out


def _breaks(scenario: Any) -> bool:
    data = scenario.model_dump(exclude_none=True, by_alias=True)
    return "break" in data or any(d.get("type") == "break" for d in data.get("disturbances", []))


def tune(line: Any, scenarios: Sequence[str] | None = None, *,
         free: Sequence[FreeParameter] | None = None, objective: Objective | None = None,
         constraints: Limits | None = None, uncertain: Mapping[str, Any] | None = None,
         samples: int = 20, seed: int = 0, evaluations: int = 200, popsize: int = 2,
         workers: int | None = None,
         progress: Callable[[int, float], None] | None = None) -> TuneResult:
    """Tune ``line``'s controllers (module docstring): a single-path or branched line (its
    object, a file or a built-in name).

    ``scenarios``: names of the line's scenarios (default ``default_scenarios``); ``free``:
    the tuning variables (default ``tune_space.default_free``); ``objective``: a function of
    ({scenario: the ``run_cases`` Dataset of the candidates}, line) giving one number per
    candidate (default ``OBJECTIVE``); ``constraints``: the ``Limits``; ``uncertain``:
    {path: distribution} of the robustness Monte Carlo (default
    ``tune_robust.default_uncertain``) with ``samples`` draws; ``evaluations``: the most
    candidates simulated (each runs every scenario); ``popsize``: the population per free
    value; ``progress(evaluations, best objective)`` after each generation."""
    started = time.perf_counter()
    ops = line_ops(line)
    base = ops.load(line)
    names = list(default_scenarios(base) if scenarios is None else scenarios)
    for name in names:
        if name not in base.spec.scenarios:
            known = ", ".join(base.spec.scenarios) or "none"
            raise ArgumentError(f"scenario {name!r}: not in {base.name} (it has: {known})")
    if not names:
        raise ArgumentError(f"{base.name}: no scenario to tune on (give --scenario)")
    space = list(ops.default_free(base) if free is None else free)
    if not space:
        raise ArgumentError(f"{base.name}: nothing to tune (no cascaded-PI drive; give --free)")
    limits = constraints or Limits()
    dists = dict(ops.default_uncertain(base) if uncertain is None else uncertain)
    set_tension = ops.set_tension(base)
    history: list[Evaluation] = []

    def evaluate(xs: np.ndarray) -> np.ndarray:
        cases = [{p.path: float(math.exp(v)) for p, v in zip(space, x, strict=True)}
                 for x in xs]
        history.extend(_evaluate(ops, base, names, cases, objective, set_tension, limits,
                                 workers))
        if progress is not None:
            progress(len(history), min(e.penalised for e in history))
        return np.array([e.penalised for e in history[-len(cases):]])

    start = [math.log(_clip(_current(base, p), p)) for p in space]
    bounds = [(math.log(p.low), math.log(p.high)) for p in space]
    members = max(5, popsize * len(space))
    generations = max(0, evaluations // members - 1)
    evaluate(np.array([start]))  # the line as it is: the "before"
    if generations > 0:
        from scipy.optimize import differential_evolution

        differential_evolution(lambda x: evaluate(np.atleast_2d(x.T)), bounds, x0=start,
                               popsize=max(1, members // len(space)), maxiter=generations,
                               vectorized=True, updating="deferred", polish=False,
                               seed=seed, tol=0.0, init="latinhypercube")
    before = history[0]
    chosen, robust, notes = _robust_choice(ops, base, history, names, dists, limits, samples,
                                           seed, workers)
    tuned_values = chosen.values
    tuned_plain = ops.derive(base, tuned_values)
    gains_after = ops.frozen_gains(tuned_plain)
    tuned = ops.derive(tuned_plain, gains_after)
    return TuneResult(base, tuned, tuple(space), tuple(names), limits, before, chosen, robust,
                      ops.frozen_gains(base), gains_after, len(history),
                      time.perf_counter() - started, notes=tuple(notes))


def _current(line: Any, p: FreeParameter) -> float:
    from webline.sim.sweeps.cases import case_value

    value = case_value(line, p.path)
    return float(value) if isinstance(value, float | int) else math.sqrt(p.low * p.high)


def _clip(value: float, p: FreeParameter) -> float:
    return min(max(value, p.low), p.high)


def _evaluate(ops: LineOps, base: Any, names: Sequence[str], cases: list[dict[str, float]],
              score: Objective | None, set_tension: np.ndarray, limits: Limits,
              workers: int | None) -> list[Evaluation]:
    """Simulate ``cases`` in every scenario and check each one's constraints."""
    runs = {s: ops.run_cases(base, cases, scenario=s, workers=workers) for s in names}
    n = len(cases)
    terms: list[dict[str, float]] = [{} for _ in range(n)]
    checks: list[list[Constraint]] = [[] for _ in range(n)]
    for s, ds in runs.items():
        rms = np.asarray(ds.tension_rms_error.values)
        spans = list(ds.span.values)
        drives = [str(d) for d in ds.drive.values]
        for c in range(n):
            for k, span in enumerate(spans):
                if np.isfinite(rms[c, k]):
                    terms[c][f"{s}/{span}"] = float(rms[c, k] / set_tension[k])
            checks[c] += run_constraints(s, str(ds.status.values[c]),
                                         np.asarray(ds.torque_limit_time.values[c]), drives,
                                         float(ds.attrs["duration"]), limits)
    if score is None:  # OBJECTIVE
        totals = np.array([sum(t.values()) for t in terms])
    else:
        totals = np.asarray(score(runs, base), dtype=float)
    out = []
    for c, case in enumerate(cases):
        line = ops.derive(base, case)
        explicit = ops.derive(line, ops.frozen_gains(line))
        checks[c] += ops.stability(explicit, limits)
        value = float(totals[c]) if np.isfinite(totals[c]) else math.inf
        out.append(Evaluation(dict(case), value, terms[c], tuple(checks[c])))
    return out


def _robust_choice(ops: LineOps, base: Any, history: list[Evaluation], names: Sequence[str],
                   dists: Mapping[str, Any], limits: Limits, samples: int, seed: int,
                   workers: int | None) -> tuple[Evaluation, RobustCheck, list[str]]:
    """The best feasible candidate that passes the robustness Monte Carlo (at most
    ``ROBUST_TRIES`` tried); if none passes, the best feasible one (or the line as it was,
    if nothing is feasible) with its failed check, and notes saying so."""
    notes: list[str] = []
    feasible = sorted((e for e in history if e.feasible), key=lambda e: e.objective)
    unique: list[Evaluation] = []
    for e in feasible:
        if not any(e.values == u.values for u in unique):
            unique.append(e)
    if not unique:
        notes.append("no candidate met every margin and limit: the line is kept as it was")
        first = history[0]
        return first, _check(ops, base, first, names, dists, limits, samples, seed,
                             workers), notes
    failed: RobustCheck | None = None
    for e in unique[:ROBUST_TRIES]:
        check = _check(ops, base, e, names, dists, limits, samples, seed, workers)
        if check.holds:
            if failed is not None:
                notes.append("a better candidate failed the robustness Monte Carlo; the best "
                             "that passed it is the result")
            return e, check, notes
        failed = failed or check
    notes.append(f"none of the {min(len(unique), ROBUST_TRIES)} best feasible candidates "
                 "passed the robustness Monte Carlo: the best one is reported with its check")
    return unique[0], failed if failed is not None else RobustCheck(
        0, 0, limits.robust_share, {}), notes


def _check(ops: LineOps, base: Any, e: Evaluation, names: Sequence[str],
           dists: Mapping[str, Any], limits: Limits, samples: int, seed: int,
           workers: int | None) -> RobustCheck:
    plain = ops.derive(base, e.values)
    explicit = ops.derive(plain, ops.frozen_gains(plain))

    def stability(line: Any, values: dict[str, float]) -> list[Constraint]:
        return ops.stability(ops.derive(line, values), limits)  # as the nominal's

    return robustness(explicit, dists, names, limits=limits, n=samples, seed=seed,
                      stability=stability, workers=workers)
