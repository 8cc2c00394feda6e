"""The work of a study, estimated and bounded before any case runs (``webline.sim.linear.budget``).

Each case costs what its run would: ``ticks x sub-steps`` RK4 steps, its sub-steps set by its
own fastest mode. Building every case to learn its sub-steps would cost what the study is
meant to bound, so the cases probed by ``cases.probe_values`` (every value of a path with
few, else its smallest and largest, each applied alone to the base line) stand for them: each
is checked as a run is (``budget.check_work``: a case ``run`` would refuse is refused), and
the study is estimated as its number of cases times the costliest probe. A case that only
costs more in combination is still checked when it is built (``cases.build_cases``).
"""

from __future__ import annotations

from collections.abc import Sequence

from webline.limits import CASE_BYTES
from webline.line import Line
from webline.sim.core import kernel
from webline.sim.core.plan import compile_plan
from webline.sim.linear import budget
from webline.sim.linear.steps import record_every
from webline.sim.results.metrics import METRICS
from webline.sim.simulate import choose_substeps


def case_work(line: Line, duration: float) -> budget.Work:
    """The work of one case of ``line`` for ``duration`` [s], as ``simulate`` counts it, after
    checking it with ``budget.check_work`` (``LineFileError`` naming the key beyond it)."""
    plan = compile_plan(line)
    ticks = max(1, round(duration / plan.dt))
    every = record_every(ticks, plan.dt)
    columns = kernel.record_width(plan.n_x, plan.drives.shape[0], line.n_nodes)
    work = budget.estimate(ticks, choose_substeps(plan), every, columns)
    budget.check_work(line, work, plan.dt)
    return work


def case_bytes(line: Line, n_paths: int, n_trace: int) -> int:
    """Bytes [B] one case of a study of ``line`` holds: ``limits.CASE_BYTES``, a value per
    path, and its metrics and ``n_trace`` span tensions three times (the collector, the
    merged Dataset and its copy written to the results file)."""
    sizes = {"span": line.n_spans, "drive": len(line.drives), "node": line.n_nodes}
    values = sum(sizes[dim] for dim, _, _ in METRICS.values()) + n_trace * line.n_spans
    return CASE_BYTES + 200 * n_paths + 3 * 8 * values


def check_study_work(base: Line, probes: Sequence[Line], n_cases: int, duration: float, *,
                     n_paths: int, n_trace: int, limit: bool = True) -> budget.StudyWork:
    """Check a study of ``n_cases`` cases of ``duration`` [s] each, changes of ``base`` (its
    scenario applied) of which ``probes`` are the probed ones (module docstring), before it
    runs; returns its estimate. Raises ``LineFileError`` for a case beyond a run's budget and
    ``ArgumentError`` for a study beyond ``budget.check_study``'s."""
    worst = case_work(base, duration)
    for line in probes:
        work = case_work(line, duration)
        if work.rk4_steps > worst.rk4_steps:
            worst = work
    study = budget.StudyWork(n_cases, worst, case_bytes(base, n_paths, n_trace))
    budget.check_study(study, limit=limit)
    return study
