"""Studies at scale (issue 14): the batched sweep against a ``simulate()`` loop, on one core and
on all cores, on a 2-process Dask ``LocalCluster``, and the peak memory of a large sweep.

    python benchmarks/bench_sweep.py [--quick] [--cases N] [--loop-cases N]
                                     [--memory-cases N] [--no-dask]

Every case is a 10 s run of the built-in ``hswl`` line (1 kHz control) with its web modulus
drawn from ``uniform(1800 lbf, 2200 lbf)``. Printed, all measured in this run, beside the
machine's core count and load average (at the start and at the end):

(a) one core (the process pinned to one CPU): the per-case cost of
    ``simulate(line.replace(case), 10)`` in a loop (today's way) and of ``webline.monte_carlo``
    with ``workers=1``, as wall time and as CPU time of the thread, best of ``--repeat``
    interleaved rounds, and the kernel alone (the batch's own work per case beside it: goal
    < 20 %; and the same batch with every case's plan compiled in full, without the plan
    patches of ``sim.core.plan_patch``); their ratio (goal <= 0.5), its range round by
    round (the spread the machine's load makes), and where a batch case's time goes
    (plans in Python, compiled batch, verdicts and Dataset); the floor of the ratio (the
    compiled batch alone over a loop case) and the time per case the goal leaves for the
    plans; for scale, the same batch against a loop that also computes the metrics, and
    against the loop the issue called today's (reading the line file every case);
(b) all cores: the same batch with ``workers`` = the cores, best of ``--repeat`` runs, its
    speed-up over (a)'s batch (goal >= 1.7 on 2 cores) and the CPU it kept busy; beside it
    the machine's ceiling at that moment: the speed-up of the compiled batch alone (cases
    built beforehand, nothing shared), which a VM whose cores slow each other down keeps
    below 2;
(c) a 2-process, 1-thread-each ``LocalCluster``: its start-up and the workers' warm-up (import,
    loading the compiled loop) timed apart, then the same cases in the chunks a study on Dask
    takes (``chunks.task_chunk``: at least a second of kernel work each) through
    ``webline.sim.sweeps.chunks.run_chunked`` (chunk files written and merged), against the
    local batch on 2 threads without files (efficiency, goal >= 0.8) and with the same chunk
    files;
(d) the peak resident memory of a fresh process running ``--memory-cases`` cases (default
    10 000) without traces (``resource.getrusage``; goal < 1 GB), its wall time (goal <= 15 s
    on 2 cores) and that time over the kernel-only floor measured here (the compiled batch
    alone on every core, cases built beforehand, times the cases; goal <= 1.25).

On a machine shared with other work the numbers are noisy (CPU time less so than wall time):
compare them with the load average printed beside them.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from importlib import resources

DISTS = {"web.ea": "uniform(1800 lbf, 2200 lbf)"}
DURATION = 10.0


def memory_child(n: int) -> None:
    """Run ``n`` cases in this process; print its peak resident memory [MB] and wall time [s]."""
    import webline

    started = time.perf_counter()
    webline.monte_carlo("hswl", DISTS, n, seed=1, duration=DURATION)
    wall = time.perf_counter() - started
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux: kB
    print(f"{n} {peak:.0f} {wall:.2f}")


def _load() -> str:
    """The load average (1/5/15 min) and ``uptime``'s line, as every timing here is read."""
    line = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    return "/".join(f"{x:.2f}" for x in os.getloadavg()) + (f" (uptime: {line})" if line else "")


def _warm_worker() -> int:
    """Run on each Dask worker: import webline and load the compiled batch loop."""
    import webline

    webline.monte_carlo("hswl", DISTS, 2, seed=0, duration=0.1, workers=1)
    return os.getpid()


def one_core(line: object, cases: int, loop_cases: int, repeat: int) -> dict[str, float]:
    """(a): per-case wall and CPU time [s] of the loop and the one-thread batch, best of
    ``repeat`` interleaved rounds, and the batch's split (wall, from the Dataset)."""
    import webline
    from webline.sim.sweeps.distributions import draw

    samples = draw(DISTS, loop_cases, seed=2)["web.ea"]
    best = {"loop_wall": float("inf"), "loop_cpu": float("inf"),
            "batch_wall": float("inf"), "batch_cpu": float("inf")}
    split: dict[str, float] = {}
    # for scale: a loop that also computes what the batch gives per case (metrics, verdict)
    cpu = time.thread_time()
    for value in samples:
        webline.simulate(line.replace({"web.ea": float(value)}),  # type: ignore[attr-defined]
                         DURATION).metric_arrays()
    split["metrics_loop_cpu"] = (time.thread_time() - cpu) / loop_cases
    # for scale: the loop the issue measured as today's, which read the line file every case
    path = str(resources.files("webline.data.lines").joinpath("hswl.toml"))
    cpu = time.thread_time()
    for value in samples:
        webline.simulate(webline.load_line(path).replace({"web.ea": float(value)}), DURATION)
    split["file_loop_cpu"] = (time.thread_time() - cpu) / loop_cases
    rounds = []
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.thread_time()
        for value in samples:
            webline.simulate(line.replace({"web.ea": float(value)}), DURATION)  # type: ignore[attr-defined]
        loop_wall = (time.perf_counter() - wall) / loop_cases
        best["loop_wall"] = min(best["loop_wall"], loop_wall)
        best["loop_cpu"] = min(best["loop_cpu"], (time.thread_time() - cpu) / loop_cases)
        wall, cpu = time.perf_counter(), time.thread_time()
        ds = webline.monte_carlo(line, DISTS, cases, seed=3, duration=DURATION, workers=1)
        batch_wall = (time.perf_counter() - wall) / cases
        rounds.append(batch_wall / loop_wall)
        best["batch_cpu"] = min(best["batch_cpu"], (time.thread_time() - cpu) / cases)
        if batch_wall < best["batch_wall"]:
            best["batch_wall"] = batch_wall
            split |= {k: ds.attrs[f"seconds_{k}"] / cases for k in ("build", "loop", "collect")}
    # for scale: the same batch with every case's plan compiled in full (no plan patches,
    # ``sim.core.plan_patch``), one round
    from webline.sim.core import plan_patch

    patch_kind = plan_patch.patch_kind
    plan_patch.patch_kind = lambda changes: None  # type: ignore[assignment]
    try:
        cpu = time.thread_time()
        webline.monte_carlo(line, DISTS, cases, seed=3, duration=DURATION, workers=1)
        split["full_plans_cpu"] = (time.thread_time() - cpu) / cases
    finally:
        plan_patch.patch_kind = patch_kind
    return {**best, **split, "round_min": min(rounds), "round_max": max(rounds)}


def kernel_floor(line: object, cases: int, workers: int, repeat: int) -> tuple[float, float]:
    """The kernel-only floor of a case: (wall [s] per case of ``batch.run_batch`` alone on
    ``workers`` threads, its CPU [s] per case), on ``cases`` cases built beforehand, best of
    ``repeat``: what a study would cost if building the cases and collecting their metrics
    were free."""
    import numpy as np

    from webline.sim.sweeps.batch import run_batch
    from webline.sim.sweeps.cases import build_cases
    from webline.sim.sweeps.distributions import draw

    samples = draw(DISTS, cases, seed=5)["web.ea"]
    built = build_cases(line, [{"web.ea": float(v)} for v in samples], DURATION)  # type: ignore[arg-type]
    wall, cpu = math.inf, math.inf
    for _ in range(repeat):
        states = [(x.copy(), i.copy(), s.copy()) for x, i, s in built.states]
        started, used = time.perf_counter(), time.process_time()
        run_batch(built.plans, states, np.array(built.n_ticks), np.array(built.substeps),
                  np.array(built.every), workers=workers)
        wall = min(wall, (time.perf_counter() - started) / cases)
        cpu = min(cpu, (time.process_time() - used) / cases)
    return wall, cpu


def compiled_scaling(line: object, cases: int, cores: int, repeat: int) -> float:
    """Speed-up [1] of ``batch.run_batch`` alone on ``cores`` threads over one thread, on
    ``cases`` cases built beforehand (no Python in the timed part), best of ``repeat``: what
    the cores give compiled code that shares nothing, the ceiling of (b)."""
    import numpy as np

    from webline.sim.sweeps.batch import run_batch
    from webline.sim.sweeps.cases import build_cases
    from webline.sim.sweeps.distributions import draw

    samples = draw(DISTS, cases, seed=4)["web.ea"]
    built = build_cases(line, [{"web.ea": float(v)} for v in samples], DURATION)  # type: ignore[arg-type]
    best = {1: math.inf, cores: math.inf}
    for _ in range(repeat):
        for workers in best:
            states = [(x.copy(), i.copy(), s.copy()) for x, i, s in built.states]
            started = time.perf_counter()
            run_batch(built.plans, states, np.array(built.n_ticks), np.array(built.substeps),
                      np.array(built.every), workers=workers)
            best[workers] = min(best[workers], time.perf_counter() - started)
    return best[1] / best[cores]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="fewer cases (128 batch, 30 loop, 1000 memory), one round")
    parser.add_argument("--cases", type=int, default=None, help="cases of the batch timings "
                        "(default 1024)")
    parser.add_argument("--loop-cases", type=int, default=None,
                        help="cases of the simulate() loop (default 100)")
    parser.add_argument("--memory-cases", type=int, default=None,
                        help="cases of the memory run (default 10 000)")
    parser.add_argument("--repeat", type=int, default=None,
                        help="rounds of (a) and runs of (b) (default 3)")
    parser.add_argument("--no-dask", action="store_true", help="skip the LocalCluster timing")
    parser.add_argument("--memory-child", type=int, default=0, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.memory_child:
        memory_child(args.memory_child)
        return
    quick = args.quick
    cases = args.cases or (128 if quick else 1024)
    loop_cases = args.loop_cases or (30 if quick else 100)
    memory_cases = args.memory_cases or (1000 if quick else 10_000)
    repeat = args.repeat or (1 if quick else 3)

    import webline

    cores = os.cpu_count() or 1
    affinity = sorted(os.sched_getaffinity(0))
    print(f"machine: {cores} cores ({len(affinity)} usable by this process), "
          f"load average {_load()} (1/5/15 min) at the start")
    line = webline.load_line("hswl")
    webline.monte_carlo(line, DISTS, 2, seed=0, duration=DURATION, workers=1)  # compile, warm
    webline.simulate(line, DURATION)

    # (a) one core
    os.sched_setaffinity(0, {affinity[0]})
    a = one_core(line, cases, loop_cases, repeat)
    os.sched_setaffinity(0, affinity)
    wall_ratio, cpu_ratio = a["batch_wall"] / a["loop_wall"], a["batch_cpu"] / a["loop_cpu"]
    print(f"(a) one core, {cases} batch cases, {loop_cases} loop cases, best of {repeat}:")
    print(f"    simulate() loop   {a['loop_wall'] * 1e3:7.2f} ms/case wall, "
          f"{a['loop_cpu'] * 1e3:7.2f} ms CPU")
    print(f"    batch, 1 thread   {a['batch_wall'] * 1e3:7.2f} ms/case wall, "
          f"{a['batch_cpu'] * 1e3:7.2f} ms CPU  (plans {a['build'] * 1e3:.2f}, compiled batch "
          f"{a['loop'] * 1e3:.2f}, verdicts and Dataset {a['collect'] * 1e3:.2f} ms/case)")
    met = "met" if max(wall_ratio, cpu_ratio) <= 0.5 else (
        "met in CPU time only" if cpu_ratio <= 0.5 else "not met")
    print(f"    batch / loop      {wall_ratio:7.2f} wall, {cpu_ratio:.2f} CPU   "
          f"(goal <= 0.5: {met}; wall, round by round: {a['round_min']:.2f} to "
          f"{a['round_max']:.2f})")
    floor = a["loop"] / a["loop_wall"]
    room = 0.5 * a["loop_wall"] - a["loop"] - a["collect"]
    print(f"    floor: the compiled batch alone (simulate's own RK4 steps, which the 1e-12 "
          f"equality requires) is {floor:.2f} of a loop case; the goal leaves "
          f"{room * 1e3:.2f} ms/case for the plans, which take {a['build'] * 1e3:.2f}")
    _, kernel_cpu = kernel_floor(line, cases, 1, repeat)
    overhead = a["batch_cpu"] / kernel_cpu - 1.0
    print(f"    kernel alone      {kernel_cpu * 1e3:7.2f} ms/case CPU (cases built beforehand); "
          f"the batch's own work per case {overhead * 100:.0f} % of it (goal < 20 %: "
          f"{'met' if overhead < 0.2 else 'not met'})")
    print(f"    (for scale: the batch with every plan compiled in full, no plan patches: "
          f"{a['full_plans_cpu'] * 1e3:.2f} ms CPU/case, one round; its own work "
          f"{(a['full_plans_cpu'] / kernel_cpu - 1.0) * 100:.0f} % of the kernel)")
    print(f"    (for scale: a loop that also computes the batch's metrics and verdict, "
          f"{a['metrics_loop_cpu'] * 1e3:.2f} ms CPU/case, one round: batch / that "
          f"{a['batch_cpu'] / a['metrics_loop_cpu']:.2f})")
    print(f"    (for scale: the loop the issue called today's, reading the line file every case, "
          f"{a['file_loop_cpu'] * 1e3:.2f} ms CPU/case, one round: batch / that "
          f"{a['batch_cpu'] / a['file_loop_cpu']:.2f})")

    # (b) all cores, best of ``repeat`` runs
    b_wall = math.inf
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        run = webline.monte_carlo(line, DISTS, cases, seed=3, duration=DURATION, workers=cores)
        if (time.perf_counter() - wall) / cases < b_wall:
            b_wall = (time.perf_counter() - wall) / cases
            busy = (time.process_time() - cpu) / cases / b_wall
            ds = run
    speedup = a["batch_wall"] / b_wall
    goal = ("met" if speedup >= 1.7 else "not met") if cores == 2 else "stated for 2 cores"
    print(f"(b) all {cores} cores, best of {repeat}: batch {b_wall * 1e3:.2f} ms/case wall, "
          f"{busy:.2f} cores busy on average (plans {ds.attrs['seconds_build'] / cases * 1e3:.2f},"
          f" compiled {ds.attrs['seconds_loop'] / cases * 1e3:.2f} ms/case, overlapping)")
    print(f"    speed-up over one core {speedup:.2f}   (goal >= 1.7 on 2 cores: {goal})")
    ceiling = compiled_scaling(line, min(cases, 256), cores, repeat)
    print(f"    (the machine's ceiling now: the compiled batch alone, on cases built beforehand, "
          f"runs {ceiling:.2f}x as fast on {cores} threads as on 1)")

    # (c) Dask LocalCluster
    if not args.no_dask:
        import logging

        from distributed import Client, LocalCluster

        logging.getLogger("distributed").setLevel(logging.ERROR)  # a nanny's closing chatter

        from webline.sim.sweeps.chunks import run_chunked
        from webline.sim.sweeps.distributions import draw
        from webline.sim.sweeps.sweep import run_cases

        samples = draw(DISTS, cases, seed=3)["web.ea"]
        case_list = [{"web.ea": float(v)} for v in samples]
        from webline.sim.sweeps.chunks import task_chunk
        from webline.sim.sweeps.study_work import case_work

        steps = case_work(line, DURATION).rk4_steps  # type: ignore[arg-type]
        chunk = task_chunk(cases, steps)  # what a study on Dask takes (>= 1 s of work each)
        started = time.perf_counter()
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
        start_up = time.perf_counter() - started
        started = time.perf_counter()
        client.run(_warm_worker)
        warm = time.perf_counter() - started
        try:
            started = time.perf_counter()
            run_cases(line, case_list, workers=2, duration=DURATION)
            local = (time.perf_counter() - started) / cases
            with tempfile.TemporaryDirectory() as local_store:
                started = time.perf_counter()
                run_chunked(run_cases, line, case_list, store=local_store, workers=2,
                            chunk=chunk, duration=DURATION)
                local_chunked = (time.perf_counter() - started) / cases
            with tempfile.TemporaryDirectory() as store:
                started = time.perf_counter()
                run_chunked(run_cases, line, case_list, store=store, scheduler=client,
                            chunk=chunk, duration=DURATION)
                dask = (time.perf_counter() - started) / cases
        finally:
            client.close()
            cluster.close()
        efficiency = local / dask
        print(f"(c) Dask LocalCluster, 2 processes x 1 thread: start-up {start_up:.2f} s, "
              f"workers' warm-up {warm:.2f} s (both left out below)")
        print(f"    {cases} cases in chunks of {chunk} ({chunk * steps:.3g} RK4 steps each; "
              f"files written and merged): "
              f"{dask * 1e3:.2f} ms/case; local batch on 2 threads {local * 1e3:.2f} ms/case "
              f"(with the same chunk files {local_chunked * 1e3:.2f})")
        print(f"    efficiency {efficiency:.2f}   (goal >= 0.8: "
              f"{'met' if efficiency >= 0.8 else 'not met'}); against the local chunked run "
              f"{local_chunked / dask:.2f}")

    # (d) memory of a large sweep, in a fresh process
    child = subprocess.run([sys.executable, __file__, "--memory-child", str(memory_cases)],
                           capture_output=True, text=True, check=True)
    n, peak, seconds = child.stdout.split()
    print(f"(d) {n} cases without traces, all cores: peak memory {float(peak):.0f} MB "
          f"(goal < 1000 MB: {'met' if float(peak) < 1000 else 'not met'}), "
          f"{float(seconds):.1f} s")
    floor = kernel_floor(line, min(int(n), 1024), cores, repeat)[0] * int(n)
    ratio = float(seconds) / floor
    print(f"    kernel-only floor (the compiled batch alone on {cores} threads, cases built "
          f"beforehand) {floor:.1f} s; the study / floor {ratio:.2f}   (goal <= 1.25: "
          f"{'met' if ratio <= 1.25 else 'not met'}; <= 15 s on 2 cores: "
          f"{'met' if float(seconds) <= 15 else 'not met'})")
    print(f"load average {_load()} at the end")


if __name__ == "__main__":
    main()
