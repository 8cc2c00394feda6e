"""Batched cases of a branched line: built in Python, run many at once in compiled code.

A block of cases is built as ``simulate_branches`` builds one run (plan, operating point,
RK4 sub-steps, start state: ``branches.run``); the cases of one structure (the integer tables
the branch loop freezes, and the float tables' shapes) run in one compiled call per range of
cases (``branches.loop.batch``), ranges on every core (``blocks.over_ranges``); each case's
records become its ``BranchResult`` as a run alone makes it, so a case of a study is its run
alone to round-off (``tests/integration/test_branch_batch.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from webline.errors import WeblineError
from webline.model.web_graph import BranchedLine
from webline.sim.branches.loop.batch import CASE_TABLES, batch_key, compiled_cases
from webline.sim.branches.loop.kernel import new_records
from webline.sim.branches.plan import BranchPlan, compile_branches
from webline.sim.branches.result import BranchResult
from webline.sim.branches.run import plan_and_step, run_failure, run_result, run_start
from webline.sim.linear.steps import record_every
from webline.sim.sweeps.batch import stack_cases
from webline.sim.sweeps.blocks import BLOCK, over_ranges

#: records a block of cases holds at most [bytes] (every case keeps its records until its
#: metrics and verdict are collected): a 10 s laminator case's are ~3 MB
BLOCK_RECORD_BYTES = 256 * 2**20


def block_size(base: BranchedLine, seconds: float) -> int:
    """Cases per block: as many as ``BLOCK_RECORD_BYTES`` of records allow (at most
    ``blocks.BLOCK``), sized from the base line's sample period and state."""
    plan = compile_branches(base)
    n_ticks = max(1, round(seconds / plan.dt))
    rows = n_ticks // record_every(n_ticks, plan.dt) + 2
    case_bytes = 8 * rows * (1 + plan.n_x + 2 * plan.di.shape[0])
    return max(1, min(BLOCK, BLOCK_RECORD_BYTES // case_bytes))


@dataclass
class BranchBuilt:
    """A block's cases as built: for the ``ok`` ones (indices into the block) their line,
    plan, sub-steps, ticks, record interval and start (``run_start``); the others' error."""

    ok: list[int] = field(default_factory=list)
    lines: list[BranchedLine] = field(default_factory=list)
    plans: list[BranchPlan] = field(default_factory=list)
    substeps: list[int] = field(default_factory=list)
    n_ticks: list[int] = field(default_factory=list)
    every: list[int] = field(default_factory=list)
    starts: list[tuple[np.ndarray, ...]] = field(default_factory=list)
    failed: dict[int, Exception] = field(default_factory=dict)


def build_branch_cases(base: BranchedLine, changes: Sequence[Mapping[str, object]],
                       seconds: float,
                       derive: Callable[[BranchedLine, Mapping[str, object]], BranchedLine],
                       ) -> BranchBuilt:
    """Build each case of ``changes`` (``derive(base, changes)`` gives its line) for a run of
    ``seconds`` [s]; a case whose line, operating point or sub-steps cannot be had is kept in
    ``failed`` with its error (the others go on)."""
    built = BranchBuilt()
    for j, change in enumerate(changes):
        try:
            line = derive(base, change)
            plan, point, substeps = plan_and_step(line, None, None)
            start = run_start(plan, point)
        except (WeblineError, ValueError, ArithmeticError) as exc:  # this case only
            built.failed[j] = exc
            continue
        n_ticks = max(1, round(seconds / plan.dt))
        built.ok.append(j)
        built.lines.append(line)
        built.plans.append(plan)
        built.substeps.append(substeps)
        built.n_ticks.append(n_ticks)
        built.every.append(record_every(n_ticks, plan.dt))
        built.starts.append(start)
    return built


@dataclass
class BranchBatch:
    """What a batch leaves per case (leading axis, in its cases' order): final state ``x``
    and controller memory ``istate``, the records ``rec`` (``n_rec`` rows stored), the
    status (``layout`` STATUS_*) and the time of a failure [s]."""

    x: np.ndarray
    istate: np.ndarray
    rec: np.ndarray
    n_rec: np.ndarray
    status: np.ndarray
    t_fail: np.ndarray


def run_branch_block(built: BranchBuilt, workers: int | None,
                     ) -> list[tuple[list[int], BranchBatch]]:
    """Run a built block's cases, those of one structure and table shapes in one batch each;
    the cases (indices into ``built.plans``) and output of each batch."""
    groups: dict[tuple[object, ...], list[int]] = {}
    for j, plan in enumerate(built.plans):
        shapes = tuple(getattr(plan, name).shape for name in CASE_TABLES
                       if name not in ("prof_t", "prof_v"))  # (padded: read through prof_off)
        groups.setdefault((batch_key(plan), shapes), []).append(j)
    return [(idx, _run_batch(built, idx, workers)) for idx in groups.values()]


def _run_batch(built: BranchBuilt, idx: list[int], workers: int | None) -> BranchBatch:
    plans = [built.plans[j] for j in idx]
    first = plans[0]
    n_c, n_x, n_d = len(idx), first.n_x, first.di.shape[0]
    x, istate, wound, done, cmd = (np.ascontiguousarray(np.stack(
        [built.starts[j][k] for j in idx])) for k in range(5))
    n_ticks = np.array([built.n_ticks[j] for j in idx], dtype=np.int64)
    every = np.array([built.every[j] for j in idx], dtype=np.int64)
    rows = max(new_records(int(n), int(e), n_x, n_d).shape
               for n, e in zip(n_ticks, every, strict=True))  # (the longest case's)
    rec = np.empty((n_c, *rows))
    tables = [stack_cases([getattr(p, name) for p in plans]) for name in CASE_TABLES]
    n_rec = np.zeros(n_c, dtype=np.int64)
    status = np.zeros(n_c, dtype=np.int64)
    t_fail = np.full(n_c, np.nan)
    args = (x, istate, wound, done, rec, cmd, n_ticks, np.array([p.dt for p in plans]),
            np.array([built.substeps[j] for j in idx], dtype=np.int64), every,
            np.array([p.speed_max for p in plans]), *tables)
    loop = compiled_cases(batch_key(first))

    def task(lo: int, hi: int) -> None:  # each thread its own scratch
        loop(lo, hi, *args, np.empty((5, n_x)), first.scratch(), np.empty_like(first.wound),
             n_rec, status, t_fail)

    over_ranges(n_c, workers, task)
    return BranchBatch(x, istate, rec, n_rec, status, t_fail)


def batch_results(built: BranchBuilt, outputs: list[tuple[list[int], BranchBatch]],
                  duration: float) -> dict[int, BranchResult]:
    """Each run case's ``BranchResult`` by its place in ``built``'s lists (``built.ok``
    gives its index in the block), as ``simulate_branches`` makes it from the same records."""
    results = {}
    for idx, out in outputs:
        for c, j in enumerate(idx):
            plan = built.plans[j]
            failure = run_failure(plan, out.x[c], int(out.status[c]), float(out.t_fail[c]))
            results[j] = run_result(plan, out.rec[c, :out.n_rec[c]].copy(), failure,
                                              out.istate[c], duration, built.substeps[j],
                                              built.every[j])
    return results
