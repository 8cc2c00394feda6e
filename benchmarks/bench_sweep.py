"""Studies at scale (issue 14): the batched kernel against a ``simulate()`` loop, one core and
all cores, where a case's time goes, and the peak memory of a large sweep without traces.

    python benchmarks/bench_sweep.py [--cases N] [--loop-cases N] [--memory-cases N]

Every case is a 10 s run of the built-in ``hswl`` line (1 kHz control) with its web modulus
drawn from ``uniform(1800 lbf, 2200 lbf)``. Printed, all measured in this run:

- the per-case wall time of ``simulate(line.replace(case), 10)`` in a loop (today's way);
- the per-case wall time of ``webline.monte_carlo`` on one thread, split into building the
  plans (Python: ``Line.replace``, operating point, designs, RK4 step choice), the compiled
  batch, and collecting (verdicts, Dataset), and its ratio to the loop (goal <= 0.5);
- the same on every core and its speed-up over one thread (goal >= 1.7 on 2 cores);
- the same cases on a 2-process Dask ``LocalCluster`` and its efficiency against the local
  batch on every core (goal >= 0.8; ``--no-dask`` skips it);
- the peak resident memory of a process running ``--memory-cases`` cases (default 10 000)
  without traces (``resource.getrusage``; goal < 1 GB).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import time

DISTS = {"web.ea": "uniform(1800 lbf, 2200 lbf)"}


def memory_child(n: int) -> None:
    """Run ``n`` cases in this process and print its peak resident memory [MB]."""
    import webline

    ds = webline.monte_carlo("hswl", DISTS, n, seed=1, duration=10.0)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux: kB
    print(f"{n} {peak:.0f} {ds.attrs['seconds_build']:.2f} {ds.attrs['seconds_loop']:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=200, help="cases of the batch timings")
    parser.add_argument("--loop-cases", type=int, default=50, help="cases of the loop timing")
    parser.add_argument("--memory-cases", type=int, default=10_000)
    parser.add_argument("--no-dask", action="store_true", help="skip the LocalCluster timing")
    parser.add_argument("--memory-child", type=int, default=0, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.memory_child:
        memory_child(args.memory_child)
        return

    import webline
    from webline.sim.distributions import draw

    line = webline.load_line("hswl")
    webline.monte_carlo(line, DISTS, 2, seed=0, duration=10.0, workers=1)  # compile, warm
    webline.simulate(line, 10.0)
    samples = draw(DISTS, args.loop_cases, seed=2)["web.ea"]
    started = time.perf_counter()
    for value in samples:
        webline.simulate(line.replace({"web.ea": float(value)}), 10.0)
    loop = (time.perf_counter() - started) / args.loop_cases
    print(f"simulate() loop            {loop * 1e3:8.2f} ms/case  ({args.loop_cases} cases)")

    cores = os.cpu_count() or 1
    per_case = {}
    for workers in (1, cores):
        started = time.perf_counter()
        ds = webline.monte_carlo(line, DISTS, args.cases, seed=3, duration=10.0,
                                 workers=workers)
        total = (time.perf_counter() - started) / args.cases
        per_case[workers] = total
        build, run, collect = (ds.attrs[f"seconds_{k}"] / args.cases * 1e3
                               for k in ("build", "loop", "collect"))
        print(f"batch, {workers} thread{'s' if workers > 1 else ' '}          "
              f"{total * 1e3:8.2f} ms/case  ({args.cases} cases: plans {build:.2f}, "
              f"compiled batch {run:.2f}, collect {collect:.2f} ms/case)")
        if workers == 1:
            print(f"  batch / loop on one core  {total / loop:6.2f}   (goal <= 0.5)")
            print(f"  compiled batch / loop     {run / 1e3 / loop:6.2f}   (the loop alone)")
            compiled_one = run
        else:
            print(f"  speed-up on {cores} cores      {per_case[1] / total:6.2f}   (goal >= 1.7)")
            print(f"  compiled batch speed-up   {compiled_one / run:6.2f}")
        if cores == 1:
            break

    if not args.no_dask:
        # same cases on a 2-process LocalCluster (chunks of CHUNK cases are tasks)
        started = time.perf_counter()
        webline.monte_carlo(line, DISTS, args.cases, seed=3, duration=10.0,
                            scheduler="local", workers=2)
        dask_case = (time.perf_counter() - started) / args.cases
        print(f"Dask LocalCluster, 2 proc.  {dask_case * 1e3:8.2f} ms/case  (cluster start "
              "included)")
        print(f"  efficiency vs local batch {per_case[cores] / dask_case:6.2f}   (goal >= 0.8)")

    child = subprocess.run([sys.executable, __file__, "--memory-child", str(args.memory_cases)],
                           capture_output=True, text=True, check=True)
    n, peak, build, run = child.stdout.split()
    print(f"peak memory, {n} cases, no traces: {float(peak):.0f} MB  (goal < 1000 MB; "
          f"plans {float(build):.1f} s, compiled batch {float(run):.1f} s)")


if __name__ == "__main__":
    main()
