"""``webline.sweep`` and ``webline.monte_carlo``: many runs of one line, batched.

Each case is the line with some values replaced (``Line.replace`` paths); its plan, RK4
sub-steps and initial state are built once in Python, then all cases of one structure run
in the batched kernel (``webline.sim.sweeps.batch``) on every core. The result is an
``xarray.Dataset`` over ``case`` with the parameters as coordinates [SI] and the metrics of
``webline.sim.results.metrics`` per case, plus the verdict status of each case (``sweep_dataset``).
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.errors import ArgumentError, LineFileError
from webline.limits import check_case_count
from webline.line import Line, load_line
from webline.model.lines import load_line as load_any
from webline.sim.core.plan import compile_plan
from webline.sim.core.plan_patch import CasePlans
from webline.sim.linear.budget import StudyWork
from webline.sim.linear.steps import record_every
from webline.sim.sweeps.batch import BatchOutput, run_batch
from webline.sim.sweeps.blocks import blocks_of, run_blocks
from webline.sim.sweeps.cases import (
    Built,
    build_cases,
    case_value,
    derive_line,
    probe_values,
)
from webline.sim.sweeps.distributions import draw, values_written
from webline.sim.sweeps.study_grid import as_grid
from webline.sim.sweeps.study_work import check_study_work
from webline.sim.sweeps.sweep_dataset import Collector
from webline.spec.ranges import argument, whole_argument

if TYPE_CHECKING:  # a single-path study loads neither the branched line nor its kernel
    from webline.model.web_graph import BranchedLine


def run_cases(line: Line | str | Path, cases: Sequence[Mapping[str, object]], *,
              duration: float | str | None = None, scenario: str | None = None,
              record: float | str | None = None, workers: int | None = None,
              progress: Callable[[int, int], None] | None = None) -> Any:
    """Simulate ``line`` once per mapping of changes in ``cases`` for ``duration`` [s]
    (default: the scenario's, else 10 s); the Dataset of ``sweep``. ``record`` [s]: keep the
    span tensions at that interval (``tension`` over case, time, span). ``workers``: threads
    (default: every core). ``progress``, if given, is called with (cases done, cases) after
    each block of cases (``blocks_of``)."""
    check_workers(workers)
    base = load_line(line)
    if scenario is not None:
        base = base.with_scenario(scenario)
        if duration is None:
            duration = base.spec.scenarios[scenario].duration
    duration = 10.0 if duration is None else argument(duration, "time", "duration",
                                                      within="scenario.duration")
    record_s = None if record is None else argument(record, "time", "record", within=None)
    base_plan = compile_plan(base)
    trace_every = n_trace = 0
    if record_s is not None:
        # a multiple of the record interval, so every trace point is a record
        ticks = max(1, round(duration / base_plan.dt))
        step = record_every(ticks, base_plan.dt)
        trace_every = step * max(1, round(record_s / (base_plan.dt * step)))
        n_trace = ticks // trace_every + 1
    out = Collector(base_plan.line, len(cases), list(dict.fromkeys(p for c in cases for p in c)),
                     n_trace)
    seconds = {"build": 0.0, "loop": 0.0, "collect": 0.0}

    case_plans = CasePlans(base)  # the base plan, compiled once; the cases patch it

    def build(block: range) -> Built:
        built = build_cases(base, [cases[c] for c in block], duration, case_plans)
        seconds["build"] += built.seconds
        return built

    def run(built: Built) -> list[tuple[list[int], BatchOutput]]:
        started = time.perf_counter()
        outputs = _run_block(built, trace_every, n_trace, workers)
        seconds["loop"] += time.perf_counter() - started
        return outputs

    def collect(block: range, built: Built, outputs: list[tuple[list[int], BatchOutput]],
                ) -> None:
        started = time.perf_counter()
        for idx, result in outputs:
            out.add([block[j] for j in idx], [built.plans[j] for j in idx],
                    [built.substeps[j] for j in idx], result)
        seconds["collect"] += time.perf_counter() - started
        if progress is not None:
            progress(block.stop, len(cases))

    run_blocks(blocks_of(len(cases)), build, run, collect, workers)
    ds = out.dataset(duration, trace_every * base_plan.dt)
    # where the time went [s]; with more than one worker the three overlap
    ds.attrs.update({f"seconds_{k}": v for k, v in seconds.items()})
    return ds


def _run_block(built: Built, trace_every: int, n_trace: int, workers: int | None,
               ) -> list[tuple[list[int], BatchOutput]]:
    """Run a built block: cases of one structure and table shapes in one batch each; the
    cases (indices into the block) and output of each batch."""
    groups: dict[tuple[object, ...], list[int]] = {}
    for j, plan in enumerate(built.plans):
        key = (*(a.tobytes() for a in plan.structure()), plan.wound_ripple.shape,
               plan.speed_ripple.shape, plan.prof_off.shape)
        groups.setdefault(key, []).append(j)
    return [(idx, run_batch([built.plans[j] for j in idx], [built.states[j] for j in idx],
                            np.array([built.n_ticks[j] for j in idx]),
                            np.array([built.substeps[j] for j in idx]),
                            np.array([built.every[j] for j in idx]), trace_every, n_trace,
                            workers))
            for idx in groups.values()]


def sweep(line: Line | BranchedLine | str | Path, values: Mapping[str, Sequence[object]], *,
          duration: float | str | None = None, scenario: str | None = None,
          record: float | str | None = None, mode: str = "grid",
          workers: int | None = None, progress: Callable[[int, int], None] | None = None,
          scheduler: Any = None, store: str | Path | None = None,
          resume: bool = False, work_limit: bool = True) -> Any:
    """Simulate ``line`` over parameter values: ``{path: [v1, v2, ...]}`` (paths as in
    ``Line.replace``, values with units as a line file takes them). ``mode`` "grid" runs every
    combination (the last path varies fastest), "zip" the i-th value of every path together.
    Returns the Dataset of ``run_cases`` (a ``study_view.StudyDataset``: a short repr); its
    attribute ``mode`` and, for a grid, ``shape``. A grid has one dimension per path instead
    of ``case``, named by the path, its values as coordinate (``sim.sweeps.study_grid.as_grid``;
    ``as_cases`` flattens it back).
    The study's work is bounded before it runs (``sim.sweeps.study_work``; ``work_limit=False``
    lifts ``budget.MAX_STUDY_RK4_STEPS``). A branched line runs each case in the branch kernel
    (``sim.sweeps.branch_study``; docs/branching.md)."""
    paths = list(values)
    columns = [list(values[p]) for p in paths]
    for path, column in zip(paths, columns, strict=True):
        if not column:
            raise ArgumentError(f"{path}: no values to sweep")
    if mode == "grid":
        check_case_count(math.prod(len(c) for c in columns), "the grid")
        combos = list(itertools.product(*columns))
    elif mode == "zip":
        if len({len(c) for c in columns}) > 1:
            counts = ", ".join(f"{p}: {len(c)}" for p, c in zip(paths, columns, strict=True))
            raise ArgumentError(f"mode='zip' (--zip) needs as many values for every path, got "
                                f"{counts}")
        combos = list(zip(*columns, strict=True))
    else:
        raise ArgumentError(f"mode must be 'grid' or 'zip', got {mode!r}")
    cases = [dict(zip(paths, combo, strict=True)) for combo in combos]
    attrs: dict[str, Any] = {"mode": mode}
    if mode == "grid":
        attrs["shape"] = [len(c) for c in columns]
    what = {p: "the values" for p in paths}
    line = load_any(line)
    if line.branched:  # docs/branching.md: each case in the branch kernel
        from webline.sim.sweeps.branch_study import check_branch_study

        work = check_branch_study(line, cases, what, duration=duration, scenario=scenario,
                           record=record, limit=work_limit)
    else:
        base = _base(line, scenario)
        probes = probe_values(base, cases, what, derive_line)
        work = _check_work(base, probes, len(cases), len(paths), duration, scenario, record,
                           work_limit)
    ds = _study(line, cases, attrs, duration=duration, scenario=scenario, record=record,
                workers=workers, progress=progress, scheduler=scheduler, store=store,
                resume=resume, case_steps=work.case.rk4_steps)
    from webline.sim.sweeps.study_view import as_study  # xarray: loaded when a study returns

    return as_study(as_grid(ds, paths, attrs["shape"]) if mode == "grid" else ds)


def monte_carlo(line: Line | BranchedLine | str | Path, distributions: Mapping[str, Any], n: int, *,
                seed: int, duration: float | str | None = None, scenario: str | None = None,
                record: float | str | None = None, workers: int | None = None,
                progress: Callable[[int, int], None] | None = None, scheduler: Any = None,
                store: str | Path | None = None, resume: bool = False,
                work_limit: bool = True) -> Any:
    """``n`` runs of ``line`` with parameters drawn from ``distributions`` ({path: ``"normal(9
    kN, 5 %)"``, ``"uniform(0.1, 0.3)"``, ``"lognormal(9 kN, 5 %)"`` or a scipy.stats frozen
    distribution in SI}), all drawn up front from ``numpy.random.default_rng(seed)`` so the
    result does not depend on ``workers``. Returns the Dataset of ``run_cases``. ``n`` and the
    study's work are bounded before anything is drawn (``sim.linear.budget``; ``work_limit=False``
    lifts ``budget.MAX_STUDY_RK4_STEPS``)."""
    whole_argument(n, "n", 1, "a Monte Carlo study needs a whole number of samples")
    check_case_count(n, "n (--samples)")
    whole_argument(seed, "seed", 0)
    try:
        samples = draw(distributions, n, seed)
    except ValueError as exc:
        raise ArgumentError(str(exc)) from None
    line = load_any(line)
    branched = line.branched
    if line.branched:  # the branch kernel's modules (and scipy.optimize): a branched line only
        from webline.sim.sweeps.branch_study import (
            branch_base,
            branch_line_scale,
            check_branch_study,
        )

        bbase = branch_base(line, scenario)
    else:
        base = _base(line, scenario)
    for path, dist in distributions.items():
        if isinstance(dist, str):
            samples[path] = samples[path] * (
                branch_line_scale(bbase, path, values_written(dist)) if branched
                else _line_scale(base, path, dist))
    cases: list[dict[str, object]] = [{p: float(samples[p][c]) for p in samples}
                                      for c in range(n)]
    what = {p: f"the samples of {distributions[p]}" for p in distributions}
    if branched:
        work = check_branch_study(line, cases, what, duration=duration,
                                  scenario=scenario, record=record, limit=work_limit)
    else:
        probes = probe_values(base, cases, what, derive_line)
        work = _check_work(base, probes, n, len(distributions), duration, scenario, record,
                           work_limit)
    from webline.sim.sweeps.study_view import as_study

    return as_study(_study(line, cases, {"mode": "monte_carlo", "seed": seed},
                               duration=duration, scenario=scenario, record=record,
                               workers=workers, progress=progress, scheduler=scheduler,
                               store=store, resume=resume, case_steps=work.case.rk4_steps))


def _base(line: Line | str | Path, scenario: str | None) -> Line:
    base = load_line(line)
    return base if scenario is None else base.with_scenario(scenario)


def _line_scale(base: Line, path: str, dist: str) -> float:
    """Factor from a written distribution's SI numbers to what the line reads for the same
    text at ``path`` (``distributions.values_written``): 2π for a frequency in Hz of an
    angular frequency, the web's width for a force per width, else 1. Raises
    ``ArgumentError`` with the line's message when it refuses every value as written (a
    length for a force)."""
    refusal = ""
    for text, number in values_written(dist):
        try:
            read = case_value(derive_line(base, {path: text}), path)
        except LineFileError as exc:
            refusal = refusal or str(exc)
            continue
        if isinstance(read, float | int) and number != 0:
            scale = float(read) / number
            return 1.0 if abs(scale - 1.0) < 1e-12 else scale  # the same unit, rounded apart
    if refusal:
        raise ArgumentError(f"{path}: {dist}: the line refuses its values as written "
                            f"({refusal}); no case was run")
    return 1.0


#: a path with more distinct values than this is checked at its smallest and largest only


def _check_work(base: Line, probes: Sequence[Line], n_cases: int, n_paths: int,
                duration: float | str | None, scenario: str | None,
                record: float | str | None, limit: bool) -> StudyWork:
    """Refuse a study beyond a run's budget in any probed case, or beyond the study's
    (``sim.sweeps.study_work.check_study_work``), before any case runs; its estimate."""
    if scenario is not None and duration is None:
        duration = base.spec.scenarios[scenario].duration
    seconds = 10.0 if duration is None else argument(duration, "time", "duration",
                                                     within="scenario.duration")
    n_trace = 0
    if record is not None:
        interval = argument(record, "time", "record", within=None)
        n_trace = int(seconds / interval) + 1
    return check_study_work(base, probes, n_cases, seconds, n_paths=n_paths, n_trace=n_trace,
                            limit=limit)


def check_workers(workers: object) -> None:
    """Refuse a ``workers`` that is neither None (every core) nor a whole number >= 1."""
    if workers is not None:
        whole_argument(workers, "workers", 1, note=" (or None for every core)")


def _study(line: Line | BranchedLine | str | Path, cases: list[dict[str, object]],
           attrs: dict[str, Any], *,
           scheduler: Any, store: str | Path | None, resume: bool, workers: int | None,
           progress: Callable[[int, int], None] | None, case_steps: int,
           **options: Any) -> Any:
    """Run the cases here at once, or chunk by chunk into ``store`` and/or on Dask
    (``webline.sim.sweeps.chunks``; ``case_steps``, a case's estimated RK4 steps, sizes the
    chunks of a Dask study)."""
    check_workers(workers)
    run: Callable[..., Any] = run_cases
    if load_any(line).branched:
        from webline.sim.sweeps.branch_study import run_branch_cases

        run = run_branch_cases
    if scheduler is None and store is None:
        ds = run(line, cases, workers=workers, progress=progress, **options)
        ds.attrs.update(attrs)
        return ds
    from webline.sim.sweeps.chunks import run_chunked

    if store is None:
        import tempfile

        with tempfile.TemporaryDirectory(prefix="webline-study-") as folder:
            return run_chunked(run, line, cases, store=folder, scheduler=scheduler,
                               workers=workers, progress=progress, attrs=attrs,
                               case_steps=case_steps, **options)
    return run_chunked(run, line, cases, store=store, resume=resume, scheduler=scheduler,
                       workers=workers, progress=progress, attrs=attrs, case_steps=case_steps,
                       **options)
