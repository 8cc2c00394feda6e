"""Per-tick cost of hswl's compiled loop: the chain against hswl as a one-web ``[[webs]]`` file
through the general (branched) loop (issue 33).

    python benchmarks/one_web_cost.py [--seconds 60] [--repeat 5]

Each loop runs ``--seconds`` of simulated time from its operating point (plant, sampled
controllers, records: what a run costs) after a warm-up that compiles it; the best of
``--repeat`` CPU times of the running thread (``time.thread_time``: on a loaded box the
time spent waiting for a core is left out; wall time there varied 4x run to run), the loops
alternated so that a busy spell hits all, divided by the ticks. The laminator is timed
too, through the general loop: with ``--frozen`` each loop's cost now is set against the
frozen tree's, measured alternately in the same run, and the load (``uptime``) printed
with them. The general loop is timed at the sub-steps the one step rule gives it now (one,
as the chain) and at the two its eigen-solve's 500.000000002 1/s gave it before
(``sim.linear.steps``): the before/after of that rule in one run. The machine should be
quiet.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
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
#: the laminator of this tree: its per-tick cost is compared with the frozen tree's (--frozen)
LAMINATOR = Path(webline.__file__).parent / "data" / "lines" / "laminator.toml"


def chain_tick(seconds: float) -> tuple[float, int]:
    """(CPU time [s] per tick of ``seconds`` of hswl through the chain's loop, sub-steps)."""
    plan = compile_plan(webline.load_line("hswl"))
    substeps = choose_substeps(plan)
    x0, istate0 = equilibrium_plan_state(plan)
    slip = kernel.initial_slip(plan, x0)
    n_ticks = round(seconds / plan.dt)
    kernel.run(plan, x0, istate0, slip, 0, 100, substeps, 1, True)  # compile
    started = time.thread_time()
    kernel.run(plan, x0, istate0, slip, 0, n_ticks, substeps, 1, True)
    return (time.thread_time() - started) / n_ticks, substeps


def general_tick(seconds: float, substeps: int | None,
                 path: Path = ONE_WEB) -> tuple[float, int]:
    """(CPU time [s] per tick of the line file ``path`` (hswl as one web) through the general
    loop, sub-steps)."""
    plan, point, steps = plan_and_step(load_branched(path), None, substeps)
    n_ticks = round(seconds / plan.dt)

    def once(ticks: int) -> float:
        x, istate = start_state(plan, point)
        rec = new_records(ticks, 1, plan.n_x, plan.di.shape[0])
        started = time.thread_time()
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
        return time.thread_time() - started

    once(100)  # compile
    return once(n_ticks) / n_ticks, steps


def measure(seconds: float, repeat: int) -> dict[str, tuple[float, int]]:
    """Best per-tick CPU time [s] and sub-steps of each loop, alternated ``repeat`` times."""
    best: dict[str, tuple[float, int]] = {}
    for _ in range(repeat):
        for name, run in (
            ("chain", lambda: chain_tick(seconds)),
            ("general", lambda: general_tick(seconds, None)),
            ("general (2 sub-steps, before)", lambda: general_tick(seconds, 2)),
            ("laminator", lambda: general_tick(seconds, None, LAMINATOR)),
        ):
            cost, steps = run()
            if name not in best or cost < best[name][0]:
                best[name] = (cost, steps)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--frozen",
        help="a checkout of the commit before (its src/ is run in a subprocess, alternated "
        "with this tree's, so both are measured in one run on the same machine state)",
    )
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.json:
        print(json.dumps(measure(args.seconds, args.repeat)))
        return
    trees = {"now": Path(__file__).parents[1]}
    if args.frozen:
        trees["before"] = Path(args.frozen)
    best: dict[str, dict[str, tuple[float, int]]] = {tree: {} for tree in trees}
    for _ in range(args.repeat):
        for tree, root in trees.items():
            env = {**os.environ, "PYTHONPATH": str(root / "src")}
            out = subprocess.run(
                [
                    sys.executable,
                    __file__,
                    "--json",
                    "--repeat",
                    "1",
                    "--seconds",
                    str(args.seconds),
                ],
                env=env,
                capture_output=True,
                text=True,
                check=True,
            ).stdout
            for name, (cost, steps) in json.loads(out.splitlines()[-1]).items():
                if name not in best[tree] or cost < best[tree][name][0]:
                    best[tree][name] = (cost, steps)
    for tree, rows in best.items():
        for name, (cost, steps) in rows.items():
            line = name if name == "laminator" else f"hswl {name}"
            print(f"{tree:6s} {line:35s} {cost * 1e9:7.0f} ns per tick ({steps} sub-steps)")
        print(f"{tree:6s} general / chain: {rows['general'][0] / rows['chain'][0]:.2f}")
    if "before" in best:
        for name in ("chain", "general", "laminator"):
            now, before = best["now"][name][0], best["before"][name][0]
            print(f"{name} now / before: {now / before:.2f}")
        print(f"general now / chain before: "
              f"{best['now']['general'][0] / best['before']['chain'][0]:.2f}")
    print("uptime:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    main()
