"""``webline.benchmark``: every contender on every case of the standard set, scored by the
metrics of ``scores`` and ranked by one stated rule (``records.RANK_RULE``)."""

from __future__ import annotations

import time as clock
from collections.abc import Callable

from webline.line import Line, load_line
from webline.sim.simulate import simulate
from webline.sim.sweeps.distributions import draw
from webline.studies.benchmark.contenders import (
    BUILTIN,
    Contender,
    NotApplicable,
    user_contenders,
)
from webline.studies.benchmark.records import CaseRun
from webline.studies.benchmark.result import BenchmarkResult
from webline.studies.benchmark.scores import robustness_scores, run_scores
from webline.studies.benchmark.standard_set import BENCHMARK_VERSION, Case, cases, set_hash
from webline.version import __version__


def benchmark(controllers: object = None, *, quick: bool = False, builtin: bool = True,
              progress: Callable[[int, int, str], None] | None = None) -> BenchmarkResult:
    """Run the standard set (``standard_set.CASES``, version ``BENCHMARK_VERSION``; with
    ``quick`` its subset for tests) for the built-in families (unless ``builtin`` is False)
    and ``controllers``: one user controller (an object, a class or factory called with no
    arguments for each run, or ``"file.py:Name"`` / ``"module:Name"``), a list of them or a
    dict name -> one of them. Every contender runs each case with the same line, duration,
    sample rate, noise and limits. ``progress(done, total, label)`` is called after each run.
    Returns a ``BenchmarkResult`` (``.table``, ``.ranking``, ``.to_markdown()``);
    ``ArgumentError`` for a controller that cannot be had."""
    chosen = cases(quick)
    contenders = [*(BUILTIN if builtin else ()), *user_contenders(controllers)]
    if not contenders:
        from webline.errors import ArgumentError

        raise ArgumentError("benchmark: no contenders (no controllers and builtin=False)")
    total, done = len(chosen) * len(contenders), 0
    runs: list[CaseRun] = []
    start = clock.perf_counter()
    for case in chosen:
        lines = case_lines(case)
        for contender in contenders:
            runs.append(run_case(case, lines, contender))
            done += 1
            if progress is not None:
                progress(done, total, f"{case.name}: {contender.name}")
    return BenchmarkResult(BENCHMARK_VERSION, set_hash(chosen), __version__, quick, chosen,
                           tuple(c.name for c in contenders), tuple(runs),
                           clock.perf_counter() - start)


def case_lines(case: Case) -> list[Line]:
    """The line(s) of ``case``: the built-in line under its scenario with its values set;
    a Monte Carlo case's ``samples`` lines, drawn once so every contender meets the same."""
    line = load_line(case.line)
    if case.scenario is not None:
        line = line.with_scenario(case.scenario)
    if case.set:
        line = line.replace(dict(case.set))
    if not case.monte_carlo:
        return [line]
    samples = draw(case.uncertain, case.samples, case.seed)  # SI, as Line.replace reads it
    return [line.replace({path: float(values[k]) for path, values in samples.items()})
            for k in range(case.samples)]


def run_case(case: Case, lines: list[Line], contender: Contender) -> CaseRun:
    """``contender`` on ``case`` (its ``lines``): scored, failed or n/a."""
    start = clock.perf_counter()
    outcomes: list[tuple[str, str, dict[str, float] | None]] = []
    for line in lines:
        try:
            outcomes.append(_one_run(case, line, contender))
        except NotApplicable as exc:
            return CaseRun(case.name, contender.name, "n/a", str(exc), {},
                           clock.perf_counter() - start)
    seconds = clock.perf_counter() - start
    if not case.monte_carlo:
        status, note, scores = outcomes[0]
        return CaseRun(case.name, contender.name, status, note, scores or {}, seconds)
    failed = [note for status, note, _ in outcomes if status == "failed"]
    others = [status for status, _, _ in outcomes if status not in ("ok", "failed")]
    worst = ("failed" if len(failed) == len(outcomes) else others[0] if others else "ok")
    note = (f"{len(failed)} of {len(outcomes)} samples failed; the first: {failed[0]}"
            if failed else next((n for s, n, _ in outcomes if n), ""))
    scores = {} if worst == "failed" else robustness_scores([s for *_, s in outcomes])
    return CaseRun(case.name, contender.name, worst, note, scores, seconds)


def _one_run(case: Case, line: Line,
             contender: Contender) -> tuple[str, str, dict[str, float] | None]:
    """(status, verdict line, scores or None) of one run."""
    try:
        run_line, controller = contender.setup(line)
        result = simulate(run_line, case.duration, raise_on_failure=False,
                          controller=controller)
    except NotApplicable:
        raise
    except Exception as exc:  # the user's constructor or reset(), or what a run raises:
        # that contender fails this case; the benchmark goes on
        return "failed", f"{type(exc).__name__}: {' '.join(str(exc).split())}", None
    if result.status == "interrupted":  # Ctrl-C stops the benchmark, not only this run
        raise KeyboardInterrupt
    if result.failure is not None:
        return "failed", result.message, None
    return result.status, result.message, run_scores(result, case.onset)
