"""Sweeps and Monte Carlo on a branched line (docs/branching.md, "Sweeps and Monte Carlo").

A case is the branched line with some values changed at paths as a scenario's ``set`` writes
them (``webs.film.web.ea``, ``webs.film.spans.film_zone.length``, ``rollers.nip.inertia``):
the changes are applied to the line's values and the whole line is checked again
(``derive_branched``), then it runs in the branch kernel from its own operating point
(``simulate_branches``). Its metrics are the chain's (``sim.results.metrics.run_metrics``:
per span, so per lane, the tension error's RMS and peak, min and max tension, settling and
slack time; per drive, time at its torque limit), plus each loadcell's final error; its status
is its run's verdict, and ``web_status`` the verdict per web and lane (a failed run fails every
web). A case that cannot be built or run is one ``failed`` row with its reason; the others go
on. The cases run batched as the chain's (``branch_batch``: many cases of one structure in one
compiled call, on every core, block by block through ``blocks``), each equal to its run alone
(``simulate_branches``) to round-off; chunks, a store and Dask are the chain's
(``sim.sweeps.chunks``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from webline.errors import ArgumentError, LineFileError, WeblineError
from webline.limits import CASE_BYTES
from webline.model.web_graph import BranchedLine, load_branched
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.loop import layout as B
from webline.sim.branches.plan import compile_branches
from webline.sim.branches.result import BranchResult
from webline.sim.branches.run import fastest_rate
from webline.sim.linear import budget
from webline.sim.linear.steps import record_every, substeps_for
from webline.sim.results.metrics import METRICS, run_metrics
from webline.sim.sweeps.blocks import blocks_of, run_blocks
from webline.sim.sweeps.branch_batch import (
    BranchBatch,
    BranchBuilt,
    batch_results,
    block_size,
    build_branch_cases,
    run_branch_block,
)
from webline.sim.sweeps.cases import case_value, path_unit, probe_values
from webline.sim.sweeps.sweep_dataset import _coordinate
from webline.spec.ranges import argument
from webline.verdict import RANK

#: metrics a branched study keeps beside the chain's ``METRICS``: (dimension, SI unit, text)
FINAL_ERROR = {"tension_final_error": ("span", "N", "tension minus loadcell reference at the "
                                                   "end")}
def branch_base(line: Any, scenario: str | None) -> BranchedLine:
    """The branched line ``line`` (a ``BranchedLine``, a file or a built-in name) with
    ``scenario`` applied."""
    base = load_branched(line)
    return base if scenario is None else base.with_scenario(scenario)


def derive_branched(base: BranchedLine, changes: Mapping[str, object]) -> BranchedLine:
    """``base`` with each path of ``changes`` set to its value (as a scenario's ``set``),
    validated and its topology checked as a loaded line is. Raises ``LineFileError`` naming
    the path (a path that does not exist, with the closest key) or the value's problem."""
    return base.replace(changes)  # BranchedLine.replace: zones checked now, not in the run


def _seconds(base: BranchedLine, duration: float | str | None, scenario: str | None) -> float:
    if scenario is not None and duration is None:
        return base.spec.scenarios[scenario].duration
    return 10.0 if duration is None else argument(duration, "time", "duration",
                                                  within="scenario.duration")


def check_branch_study(line: Any, cases: Sequence[Mapping[str, object]],
                       what: Mapping[str, str], *, duration: float | str | None,
                       scenario: str | None, record: float | str | None,
                       limit: bool) -> budget.StudyWork:
    """Refuse a study before any case runs: a value the line refuses (``ArgumentError`` naming
    the path, what produced the values and the line's message), a recorded trace (not yet on a
    branched line), or work beyond ``budget.check_study``. The work of a case is its run's
    RK4 steps, ticks × sub-steps (the sub-steps from the plant's fastest mode at the probe's
    own operating point, as ``simulate_branches`` chooses them); the study's is its number of
    cases times the costliest probe (every value of a path with few, else its extremes)."""
    if record is not None:
        raise ArgumentError("record: span tension traces are not yet recorded in a study of a "
                            "branched line (its metrics per span are)")
    base = branch_base(line, scenario)
    seconds = _seconds(base, duration, scenario)
    probes = [base, *probe_values(base, cases, what, derive_branched)]
    worst = budget.Work(0, 0, 0, 0)
    for probe in probes:
        work = _case_work(probe, seconds)
        if work is not None and work.rk4_steps > worst.rk4_steps:
            worst = work
    n_paths = len(what)
    held = 3 * 8 * (len(base.spans) * (len(METRICS) + 1) + len(base.drives) * 2
                      + len(base.spec.rollers) + len(base.spec.webs))
    study = budget.StudyWork(len(cases), worst, CASE_BYTES + 200 * n_paths + held)
    budget.check_study(study, limit=limit)
    return study


def _case_work(line: BranchedLine, seconds: float) -> budget.Work | None:
    """A run's work, as ``simulate_branches`` would size it; None where its operating point
    cannot be found (that case fails when it runs, alone)."""
    try:
        plan = compile_branches(line)
        rate = fastest_rate(plan, operating_point(plan))
    except (WeblineError, ValueError, ArithmeticError):
        return None
    ticks = max(1, round(seconds / plan.dt))
    return budget.estimate(ticks, substeps_for(rate, plan.dt), record_every(ticks, plan.dt),
                           1 + plan.n_x + 2 * plan.di.shape[0])  # a record: t, x, commands, radii


def branch_line_scale(base: BranchedLine, path: str,
                      written: Sequence[tuple[object, float]]) -> float:
    """Factor from a written distribution's SI numbers (``written``: (text, SI number) pairs of
    ``distributions.values_written``) to what the line reads at ``path`` (2π for a frequency
    in Hz of an angular frequency, else 1)."""
    for text, number in written:
        try:
            read = case_value(derive_branched(base, {path: text}), path)
        except LineFileError:
            continue
        if isinstance(read, float | int) and number != 0:
            scale = float(read) / number
            return 1.0 if abs(scale - 1.0) < 1e-12 else scale
    return 1.0


def run_branch_cases(line: Any, cases: Sequence[Mapping[str, object]], *,
                     duration: float | str | None = None, scenario: str | None = None,
                     record: float | str | None = None, workers: int | None = None,
                     progress: Callable[[int, int], None] | None = None) -> Any:
    """Run ``line`` once per mapping of changes in ``cases`` for ``duration`` [s] (default:
    the scenario's, else 10 s); the Dataset over ``case`` (module docstring). The cases run
    batched, block by block (``branch_batch``, ``blocks.run_blocks``), on ``workers`` threads
    (default: every core); ``progress``, if given, is called with (cases done, cases) after
    each block."""
    del record  # refused by check_branch_study
    base = branch_base(line, scenario)
    seconds = _seconds(base, duration, scenario)
    paths = list(dict.fromkeys(p for c in cases for p in c))
    out = _Collector(base, len(cases), paths)

    def build(block: range) -> BranchBuilt:
        return build_branch_cases(base, [cases[c] for c in block], seconds, derive_branched)

    def run(built: BranchBuilt) -> list[tuple[list[int], BranchBatch]]:
        return run_branch_block(built, workers)

    def collect(block: range, built: BranchBuilt,
                outputs: list[tuple[list[int], BranchBatch]]) -> None:
        for j, exc in built.failed.items():
            out.fail(block[j], cases[block[j]], exc)
        for j, result in batch_results(built, outputs, seconds).items():
            out.add(block[built.ok[j]], built.lines[j], result)
        if progress is not None:
            progress(block.stop, len(cases))

    run_blocks(blocks_of(len(cases), block_size(base, seconds)), build, run, collect, workers)
    return out.dataset(seconds)


def case_metrics(result: BranchResult) -> dict[str, np.ndarray]:
    """The chain's metrics (``METRICS``) of a branched run, plus ``tension_final_error`` [N]
    per loadcell span (NaN elsewhere): tension minus reference at the last record."""
    plan, line = result.plan, result.plan.line
    ds = result.dataset
    t = result.time
    tension = ds["tension"].values
    reference = np.full(tension.shape, math.nan)
    for span, p in plan.cells[:, :2].astype(int):
        a, b = plan.prof_off[p], plan.prof_off[p + 1]
        reference[:, span] = np.interp(t, plan.prof_t[a:b], plan.prof_v[a:b])
    interval = result.settings.get("record_every", 1) * plan.dt  # each record stands for this
    totals: dict[tuple[str, str], float] = {}
    for k, span in enumerate(line.spans):
        totals[("slack", span.name)] = float(np.sum(tension[:, k] <= 0.0) * interval)
    limits = plan.df[:, B.D_LIMIT]
    drives = [str(d) for d in ds["drive"].values]
    for d, name in enumerate(drives):
        at = np.abs(ds["torque_cmd"].values[:, d]) >= limits[d]
        totals[("torque_limit", name)] = float(np.sum(at) * interval)
    names = {"span": [s.name for s in line.spans], "drive": drives,
             "node": [r.name for r in line.spec.rollers]}
    metrics = run_metrics(t, tension, reference, totals, names)
    metrics["tension_final_error"] = tension[-1] - reference[-1]
    return metrics


def web_status(result: BranchResult) -> list[str]:
    """The verdict status per web and lane: its own findings (slack, tension limit), those
    of the drives on its path (a torque limit: a lane's shaft counts for each of its lanes),
    and for every web a run that stopped. The case's ``status`` is the worst of them."""
    spec = result.plan.line.spec
    webs = [w.name for w in spec.webs]
    worst = {w: "ok" for w in webs}
    on_path = {r.name: [w.name for w in spec.webs if r.name in w.path] for r in spec.rollers}
    line_name = result.plan.line.name
    for finding in result.verdict.findings:
        hit = (webs if finding.where == line_name
               else on_path.get(finding.where, [finding.where]))
        for w in hit:
            if w in worst and RANK[finding.level] > RANK[worst[w]]:
                worst[w] = finding.level
    return [worst[w] for w in webs]


class _Collector:
    """Per-case metrics, statuses and parameter values of a branched study."""

    def __init__(self, base: BranchedLine, n_c: int, paths: list[str]) -> None:
        self.base, self.paths = base, paths
        sizes = {"span": len(base.spans), "drive": len(base.drives),
                 "node": len(base.spec.rollers)}
        self.dims = {name: dim for name, (dim, _, _) in {**METRICS, **FINAL_ERROR}.items()}
        self.data = {name: np.full((n_c, sizes[dim]), math.nan)
                     for name, dim in self.dims.items()}
        self.status = np.full(n_c, "failed", dtype=object)
        self.headline = np.full(n_c, "", dtype=object)
        self.webs = np.full((n_c, len(base.spec.webs)), "failed", dtype=object)
        self.t_fail = np.full(n_c, math.nan)
        self.substeps = np.zeros(n_c, dtype=np.int64)
        self.values: dict[str, list[object]] = {p: [math.nan] * n_c for p in paths}

    def add(self, c: int, line: BranchedLine, result: BranchResult) -> None:
        for name, values in case_metrics(result).items():
            self.data[name][c] = values
        verdict = result.verdict
        self.status[c], self.headline[c] = verdict.status, verdict.headline
        self.webs[c] = web_status(result)
        if result.failure is not None:
            self.t_fail[c] = float(result.time[-1]) if len(result.time) else 0.0
        self.substeps[c] = int(result.settings["substeps"])
        for path in self.paths:
            self.values[path][c] = case_value(line, path)

    def fail(self, c: int, changes: Mapping[str, object], exc: Exception) -> None:
        """Case ``c`` could not be built or run: one line saying why; NaN metrics."""
        self.headline[c] = f"failed: {str(exc).splitlines()[0] if str(exc) else type(exc)}"
        self.t_fail[c] = 0.0
        for path in self.paths:
            if path in changes:
                try:  # the value as the base line's field would read it
                    self.values[path][c] = case_value(derive_branched(self.base, {
                        path: changes[path]}), path)
                except (WeblineError, ValueError):
                    self.values[path][c] = changes[path]

    def dataset(self, duration: float) -> Any:
        import xarray as xr

        base = self.base
        variables = {name: xr.Variable(("case", dim), self.data[name],
                                       attrs={"units": unit, "long_name": text})
                     for name, (dim, unit, text) in {**METRICS, **FINAL_ERROR}.items()}
        variables["status"] = xr.Variable(("case",), self.status.astype(str),
                                          attrs={"long_name": "verdict status of the run"})
        variables["headline"] = xr.Variable(("case",), self.headline.astype(str), attrs={
            "long_name": "verdict of the run: its status and first findings, in words"})
        variables["web_status"] = xr.Variable(("case", "web"), self.webs.astype(str), attrs={
            "long_name": "verdict status per web and lane (a stopped run: every web)"})
        variables["failure_time"] = xr.Variable(("case",), self.t_fail, attrs={
            "units": "s", "long_name": "time the run stopped early (NaN: it ran to the end)"})
        variables["substeps"] = xr.Variable(("case",), self.substeps, attrs={
            "long_name": "RK4 sub-steps per controller period"})
        coords: dict[str, Any] = {
            "case": np.arange(len(self.status)),
            "span": [s.name for s in base.spans],
            "span_web": ("span", [base.spec.webs[s.web].name for s in base.spans]),
            "drive": [base.spec.rollers[i].name for i in base.drives],
            "node": [r.name for r in base.spec.rollers],
            "web": [w.name for w in base.spec.webs]}
        for path in self.paths:
            unit = path_unit(base, path)
            coords[path] = ("case", _coordinate(self.values[path]),
                            {"long_name": f"line parameter {path}"}
                            | ({} if unit is None else {"units": unit}))
        ds = xr.Dataset(variables, coords=coords)
        ds.attrs.update({"line": base.name, "duration": duration, "parameters": self.paths,
                         "branched": 1})
        return ds
