"""Time of a five-parameter fit to two records of 60 s each with the global stage (issue 36:
goal <= 60 s wall on a quiet 2-core machine), with the number of simulations it used and
the machine's load.

    python benchmarks/fit_speed.py [--duration 60] [--seed 1] [--starts 8]
    python benchmarks/fit_speed.py --line converter     # issue 24's one-record figure

``hswl`` (default): the line with five parameters changed (``JOINT_TRUTH``: the process
roller's inertia, the master's friction, the rewind's torque lag, the web's EA and span 1's
length), two records made by ``webline experiment``'s plans on it (``accel-ramps`` and
``tension-step``, the first ``--duration`` s of each), logged at 1 kHz with sensor noise;
fitted jointly from the line file (``JOINT_FREE``). ``converter``: one record, the
converter's start-up (0 to 300 m/min from 1 s to 21 s, then steady) with ``TRUTH``, logged at
200 Hz with a 3.7 s clock offset (issue 24: goal <= 30 s). The compiled loop is loaded (and
a first simulation run) before the clock starts: the fit's own time is measured.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

TRUTH = {"rollers.infeed.inertia": 0.7, "rollers.chill.inertia": 2.4,
         "rollers.drum.friction": 0.09, "web.modulus": 3.3e9,
         "rollers.dancer.dancer.damping": 700.0}
FREE = {"rollers.infeed.inertia": "0.1 .. 2 kg*m**2", "rollers.chill.inertia": "0.5 .. 8 kg*m**2",
        "rollers.drum.friction": "0.005 .. 0.5 N*m*s", "web.modulus": "2 .. 6 GPa",
        "rollers.dancer.dancer.damping": "100 .. 3000 N*s/m"}
JOINT_TRUTH = {"rollers.process.inertia": 0.11, "rollers.master.friction": 1.0,
               "rollers.rewind.drive.torque_lag": 0.004, "web.ea": 7500.0,
               "spans.span1.length": 7.0}
JOINT_FREE = {"rollers.process.inertia": "0.01 .. 0.5 kg*m**2",
              "rollers.master.friction": "0.05 .. 3 N*m*s",
              "rollers.rewind.drive.torque_lag": "0.5 .. 20 ms", "web.ea": "4000 .. 20000 N",
              "spans.span1.length": "3 .. 15 m"}


def records(line: str, folder: Path, duration: float, seed: int) -> tuple[list[Path], dict]:
    """The records of ``line``'s benchmark and the truth they were made with."""
    from webline.line import load_line
    from webline.twin.traces.synthetic import synthetic_csv
    from webline.twin.tuning.experiment import plan_experiment

    if line == "converter":
        return [synthetic_csv(folder / "log.csv", "converter", changes=TRUTH,
                              duration=duration, scenario="startup", offset=3.7,
                              seed=seed)], TRUTH
    paths = []
    for k, name in enumerate(("accel-ramps", "tension-step")):
        plan = plan_experiment(load_line("hswl"), name)
        paths.append(synthetic_csv(folder / f"{name}.csv", plan.line, changes=JOINT_TRUTH,
                                   duration=min(duration, plan.duration), rate=1000.0,
                                   seed=seed + k))
    return paths, JOINT_TRUTH


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--line", choices=("hswl", "converter"), default="hswl")
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--starts", type=int, default=8, help="starts of the global stage")
    parser.add_argument("--workers", type=int, default=1,
                        help="threads for the Jacobian's cases (0: every core)")
    args = parser.parse_args()
    import webline
    from webline.twin.fitting.fit import fit

    with tempfile.TemporaryDirectory() as folder:
        paths, truth = records(args.line, Path(folder), args.duration, args.seed)
        webline.simulate(args.line, 0.1)  # load the compiled loop
        load = os.getloadavg()
        started, cpu = time.perf_counter(), time.process_time()
        if args.line == "converter":
            result = fit("converter", paths[0], FREE, scenario="startup",
                         workers=args.workers or None, starts=args.starts)
        else:
            result = fit("hswl", paths, JOINT_FREE, workers=args.workers or None,
                         starts=args.starts)
        seconds, cpu = time.perf_counter() - started, time.process_time() - cpu
    print(result)
    inside = sum(result.ci95[i, 0] <= truth[p.path] <= result.ci95[i, 1]
                 for i, p in enumerate(result.parameters))
    worst = max(abs(result.value[i] / truth[p.path] - 1) for i, p in enumerate(result.parameters))
    print(f"fit of {len(truth)} parameters to {len(paths)} record(s) of {args.duration:g} s "
          f"of {args.line} traces, {args.starts} starts: {seconds:.1f} s wall, {cpu:.1f} s of "
          f"CPU, {result.simulations} simulations ({seconds / result.simulations * 1e3:.0f} ms "
          f"each), {inside}/{len(truth)} true values inside their 95 % intervals, largest "
          f"error {100 * worst:.2g} %, verdict {result.verdict.status}, "
          f"{args.workers or os.cpu_count()} thread(s)")
    print(f"machine: {os.cpu_count()} cores, load average before the fit "
          f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")


if __name__ == "__main__":
    main()
