"""Per-tick cost of hswl's compiled loop: the chain against hswl as a one-web ``[[webs]]`` file
through the general (branched) loop (issue 33).

    python benchmarks/one_web_cost.py [--seconds 60] [--repeat 5]

Each loop runs ``--seconds`` of simulated time from its operating point (plant, sampled
controllers, records: what a run costs) after a warm-up that compiles it; the best of
``--repeat`` wall times, the loops alternated so that a busy spell hits all, divided by the
ticks. The general loop is timed at the sub-steps the one step rule gives it now (one, as the
chain) and at the two its eigen-solve's 500.000000002 1/s gave it before
(``sim.linear.steps``): the before/after of that rule in one run. The machine should be
quiet.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import webline
from webline.model.web_graph import load_branched
from webline.sim.branches.loop.kernel import new_records
from webline.sim.branches.run import plan_and_step, start_state
from webline.sim.core import kernel
from webline.sim.core.plan import compile_plan, equilibrium_plan_state
from webline.sim.simulate import choose_substeps

ONE_WEB = Path(__file__).parents[1] / "tests" / "data" / "hswl_one_web.toml"


def chain_tick(seconds: float) -> tuple[float, int]:
    """(wall time [s] of ``seconds`` of hswl through the chain's loop, sub-steps)."""
    plan = compile_plan(webline.load_line("hswl"))
    substeps = choose_substeps(plan)
    x0, istate0 = equilibrium_plan_state(plan)
    slip = kernel.initial_slip(plan, x0)
    n_ticks = round(seconds / plan.dt)
    kernel.run(plan, x0, istate0, slip, 0, 100, substeps, 1, True)  # compile
    started = time.perf_counter()
    kernel.run(plan, x0, istate0, slip, 0, n_ticks, substeps, 1, True)
    return (time.perf_counter() - started) / n_ticks, substeps


def general_tick(seconds: float, substeps: int | None) -> tuple[float, int]:
    """(wall time [s] per tick of hswl as one web through the general loop, sub-steps)."""
    plan, point, steps = plan_and_step(load_branched(ONE_WEB), None, substeps)
    n_ticks = round(seconds / plan.dt)

    def once(ticks: int) -> float:
        x, istate = start_state(plan, point)
        rec = new_records(ticks, 1, plan.n_x, plan.di.shape[0])
        started = time.perf_counter()
        plan.run(
            x,
            istate,
            plan.wound.copy(),
            np.zeros(len(plan.events)),
            rec,
            point.torque.copy(),
            0,
            ticks,
            steps,
            1,
            True,
        )
        return time.perf_counter() - started

    once(100)  # compile
    return once(n_ticks) / n_ticks, steps


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    best = {"chain": np.inf, "general": np.inf, "general (2 sub-steps, before)": np.inf}
    steps = {}
    for _ in range(args.repeat):
        for name, run in (
            ("chain", lambda: chain_tick(args.seconds)),
            ("general", lambda: general_tick(args.seconds, None)),
            ("general (2 sub-steps, before)", lambda: general_tick(args.seconds, 2)),
        ):
            cost, steps[name] = run()
            best[name] = min(best[name], cost)
    for name, cost in best.items():
        print(f"hswl {name:32s} {cost * 1e9:7.0f} ns per tick ({steps[name]} sub-steps)")
    print(
        f"general / chain: {best['general'] / best['chain']:.2f} "
        f"(before: {best['general (2 sub-steps, before)'] / best['chain']:.2f})"
    )


if __name__ == "__main__":
    main()
