"""A branched study batched against its cases run one by one (issue 33 item 3).

    python benchmarks/bench_branch_sweep.py [--cases 16] [--seconds 10] [--workers 2]

For the laminator and the slitter, ``--cases`` Monte Carlo cases (the film's or the web's EA,
normal 5 %) of ``--seconds`` each are run two ways, after a warm-up that compiles both loops:

* one by one: each case built, run through ``simulate_branches`` and collected in turn (what
  ``run_branch_cases`` did before the batch);
* batched: ``run_branch_cases`` (``sim.sweeps.branch_batch``) on ``--workers`` threads.

Prints the wall times, their ratio, and the compiled loop's share: the loop of every case
alone (``BranchPlan.run``, summed) against the batch's compiled calls. The machine should be
quiet; the rest of a case (operating point, verdict) is Python and runs on one core either way.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from webline.model.web_graph import load_branched
from webline.sim.branches.loop.kernel import new_records
from webline.sim.branches.run import simulate_branches
from webline.sim.sweeps.branch_batch import build_branch_cases, run_branch_block
from webline.sim.sweeps.branch_study import _Collector, derive_branched, run_branch_cases

PATHS = {"laminator": ("webs.film.web.ea", 103.5e3), "slitter": ("web.ea", 281.25e3)}


def cases_of(name: str, n: int) -> list[dict[str, object]]:
    path, ea = PATHS[name]
    rng = np.random.default_rng(1)
    return [{path: f"{v:.6g} N"} for v in rng.normal(ea, 0.05 * ea, n)]


def one_by_one(name: str, cases: list[dict[str, object]], seconds: float) -> float:
    """Wall time [s] of the cases built, run and collected in turn (the former path)."""
    base = load_branched(name)
    out = _Collector(base, len(cases), list(cases[0]))
    started = time.perf_counter()
    for c, change in enumerate(cases):
        line = derive_branched(base, change)
        out.add(c, line, simulate_branches(line, seconds, raise_on_failure=False))
    out.dataset(seconds)
    return time.perf_counter() - started


def loops(name: str, cases: list[dict[str, object]], seconds: float,
          workers: int) -> tuple[float, float]:
    """(the compiled loops of the cases alone, summed; the batch's compiled calls) [s]."""
    built = build_branch_cases(load_branched(name), cases, seconds, derive_branched)
    alone = 0.0
    for plan, start, n, every, sub in zip(built.plans, built.starts, built.n_ticks,
                                          built.every, built.substeps, strict=True):
        x, istate, wound, done, cmd = (a.copy() for a in start)
        rec = new_records(n, every, plan.n_x, plan.di.shape[0])
        started = time.perf_counter()
        plan.run(x, istate, wound, done, rec, cmd, 0, n, sub, every, True)
        alone += time.perf_counter() - started
    started = time.perf_counter()
    run_branch_block(built, workers)
    return alone, time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=16)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    for name in PATHS:
        warm = cases_of(name, 2)
        one_by_one(name, warm, 0.1)
        run_branch_cases(name, warm, duration=0.1, workers=args.workers)
        cases = cases_of(name, args.cases)
        serial = one_by_one(name, cases, args.seconds)
        started = time.perf_counter()
        run_branch_cases(name, cases, duration=args.seconds, workers=args.workers)
        batched = time.perf_counter() - started
        alone, batch = loops(name, cases, args.seconds, args.workers)
        print(f"{name}: {args.cases} cases x {args.seconds:g} s: one by one {serial:.2f} s, "
              f"batched ({args.workers} workers) {batched:.2f} s, ratio "
              f"{serial / batched:.2f}; compiled loops alone {alone:.3f} s, in the batch "
              f"{batch:.3f} s, ratio {alone / batch:.2f}")


if __name__ == "__main__":
    main()
