"""Benchmark of issue 2: webline's compiled simulation against plain scipy, 60 s of the HSWL.

Run:  python benchmarks/bench_hswl.py        (or: make bench)

Scenario: the built-in ``hswl`` line, line speed ramped 200 -> 1000 ft/min from t = 1 s over
5 s, a 1 lbf, 1 Hz wound-in tension ripple, 60 s simulated.

* webline: ``webline.simulate(line, 60.0)`` (1 kHz sampled cascaded PI, RK4 plant), timed as
  the whole public call and as the bare compiled kernel call ``webline.sim.core.kernel.run`` on the
  plan arrays (the same call ``simulate`` makes), each after a warm-up, median of ``--repeat``.
* plain: the same equations written out with numpy and continuous-time controllers,
  integrated by ``scipy.integrate.solve_ivp`` (LSODA, rtol 1e-6, default atol, solution on the
  same 1 ms grid via ``t_eval``), see ``plain_scipy.py``; after a 1 s warm-up, median of 3.
* start-up: a fresh ``python -c "import webline; webline.simulate('hswl', 0.1)"`` twice; the
  second one (numba cache warm) is the start-up cost of a new process.

Targets (issue 2): webline at least 20x faster than the plain version and under 20 ms per 60 s
simulation on one core. The process pins itself to one CPU (``--no-pin`` to leave it free).
"""

from __future__ import annotations

import argparse
import gc
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import plain_scipy

import webline
from webline.sim.core import kernel
from webline.sim.core.plan import compile_plan, equilibrium_plan_state
from webline.sim.linear.steps import record_every
from webline.sim.simulate import choose_substeps

DURATION = 60.0
TARGET_RATIO = 20.0
TARGET_MS = 20.0
STARTUP_SNIPPET = ("import time; t=time.time(); import webline; t1=time.time(); "
                   "webline.simulate('hswl', 0.1); t2=time.time(); "
                   "print(t2-t, t1-t, t2-t1)")


def timed(fn: Callable[[], object], repeat: int) -> tuple[float, list[float]]:
    """Median and all wall times [s] of ``repeat`` calls of ``fn``."""
    times = []
    for _ in range(repeat):
        gc.collect()
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), times


def pin_to_one_core() -> str:
    """Restrict this process (and its children) to one CPU; returns a description."""
    if not hasattr(os, "sched_setaffinity"):
        return "not pinned (no sched_setaffinity on this platform)"
    cpus = sorted(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {cpus[-1]})
    return f"pinned to CPU {cpus[-1]} of {len(cpus)} available"


def startup_seconds() -> tuple[float, float, float]:
    """(total, import, first simulate) [s] of a fresh process simulating 0.1 s of hswl."""
    out = subprocess.run([sys.executable, "-c", STARTUP_SNIPPET], check=True,
                         capture_output=True, text=True).stdout.split()
    total, imp, first = (float(s) for s in out[-3:])
    return total, imp, first


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7,
                        help="timed webline runs (median reported; default 7, at least 5)")
    parser.add_argument("--plain-repeat", type=int, default=3,
                        help="timed plain-scipy runs (median reported; default 3)")
    parser.add_argument("--no-pin", action="store_true", help="do not pin to one CPU")
    parser.add_argument("--no-startup", action="store_true",
                        help="skip the fresh-process start-up measurement")
    args = parser.parse_args(argv)
    repeat = max(5, args.repeat)

    pinned = "not pinned (--no-pin)" if args.no_pin else pin_to_one_core()
    print(f"webline {webline.__version__} benchmark: hswl, 200->1000 ft/min ramp + 1 Hz "
          f"wound-in ripple, {DURATION:g} s simulated")
    print(f"python {platform.python_version()}, numpy {np.__version__}, {os.cpu_count()} CPUs, "
          f"{pinned}")

    line = plain_scipy.benchmark_line()

    # --- webline: whole public call ----------------------------------------------------
    result = webline.simulate(line, DURATION)  # warm-up (compiles or loads the numba cache)
    t_public, all_public = timed(lambda: webline.simulate(line, DURATION), repeat)

    # --- webline: bare kernel call, exactly as simulate() makes it ---------------------
    plan = compile_plan(line)
    n_ticks = round(DURATION / plan.dt)
    substeps = choose_substeps(plan)
    every = record_every(n_ticks, plan.dt)
    x0, istate0 = equilibrium_plan_state(plan)

    def kernel_call() -> object:
        return kernel.run(plan, x0, istate0, kernel.initial_slip(plan, x0), 0, n_ticks, substeps,
                          every, True)

    kernel_call()
    t_kernel, all_kernel = timed(kernel_call, repeat)

    # --- plain scipy -------------------------------------------------------------------
    model = plain_scipy.build(line)
    plain_scipy.simulate(model, 1.0)  # warm-up
    solution = None

    def plain_call() -> None:
        nonlocal solution
        solution = plain_scipy.simulate(model, DURATION)

    t_plain, all_plain = timed(plain_call, args.plain_repeat)
    assert solution is not None

    # --- same physics? ------------------------------------------------------------------
    t_web = result.tension
    t_ref = plain_scipy.span_tensions(model, solution)
    if t_web.shape != t_ref.shape or not np.allclose(result.time, solution.t, atol=1e-9):
        raise RuntimeError("webline and plain results are not on the same time grid")
    rel = np.abs(t_web - t_ref) / np.abs(t_ref)
    swing = np.abs(t_ref - t_ref[0]) / np.abs(t_ref[0])

    # --- report -------------------------------------------------------------------------
    def ms(s: float) -> str:
        return f"{1e3 * s:9.2f} ms"

    print()
    print(f"RK4 sub-steps per 1 ms tick: {substeps}; records: {result.time.size}; "
          f"plain LSODA rhs evaluations: {solution.nfev}")
    print(f"webline.simulate (public call)  {ms(t_public)}  median of {repeat} "
          f"(min {ms(min(all_public)).strip()})")
    print(f"webline kernel.run (bare)       {ms(t_kernel)}  median of {repeat} "
          f"(min {ms(min(all_kernel)).strip()})")
    print(f"  public-call overhead           {ms(t_public - t_kernel)}  (plan, operating point, "
          f"fastest-mode linearisation, record copy, Result)")
    print(f"plain scipy LSODA               {ms(t_plain)}  median of {args.plain_repeat} "
          f"(min {ms(min(all_plain)).strip()})")
    print()
    ratio_public, ratio_kernel = t_plain / t_public, t_plain / t_kernel
    print(f"speed-up, public call: {ratio_public:6.1f}x   bare kernel: {ratio_kernel:6.1f}x")

    def verdict(ok: bool) -> str:
        return "MET" if ok else "NOT MET"

    print(f"target >= {TARGET_RATIO:g}x faster:  public call "
          f"{verdict(ratio_public >= TARGET_RATIO)}, bare kernel "
          f"{verdict(ratio_kernel >= TARGET_RATIO)}")
    print(f"target < {TARGET_MS:g} ms per {DURATION:g} s:  public call "
          f"{verdict(1e3 * t_public < TARGET_MS)}, bare kernel "
          f"{verdict(1e3 * t_kernel < TARGET_MS)}")
    print()
    worst = np.unravel_index(np.argmax(rel), rel.shape)
    print(f"span tensions, webline (1 kHz sampled PI) vs plain (continuous PI): max relative "
          f"difference {rel.max():.2e} (span {result.span_names[worst[1]]}, "
          f"t = {result.time[worst[0]]:.3f} s); the tensions themselves swing "
          f"{swing.max():.2e} from equilibrium")

    if not args.no_startup:
        print()
        first = startup_seconds()
        second = startup_seconds()
        print(f"fresh process, import webline + simulate('hswl', 0.1): first {first[0]:.3f} s, "
              f"second {second[0]:.3f} s (cache warm: import {second[1]:.3f} s + first "
              f"simulate incl. cache load {second[2]:.3f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
