"""Benchmark of the main job's wall time (issue 12): how long a user waits for the CLI.

Run:  python benchmarks/bench_startup.py      (options: --repeat N)

Measured in the same run, each as the median of ``--repeat`` fresh processes, and printed as
a ratio to the plain peer ``python -c "import numpy"`` (the machine is shared and noisy: the
ratio means more than the seconds):

* ``webline --version``: the CLI's start-up (goal: at most 3x ``import numpy``);
* ``webline run hswl --scenario speed-change``: the main job with a warm numba cache (one
  unmeasured run first compiles and caches the loop), writing results, figures, summary and
  report to a temporary folder (goal: at most 1.5 s wall on the project's 2-core machine),
  and its CPU time with the report's processes (issue 37's goal: at most 1.6 s);
  and, for comparison, the same command with its report written in the command's process, as
  before ``webline.report.early`` (the report's own process turned off).

Then, in one more fresh process, where the main job's work goes: the same steps the command
takes (``PHASES``), one after another in one process, each timed (imports counted where they
first happen). The command itself overlaps them: the report's process imports matplotlib
while the line is simulated, and draws the figures while the results file is written.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

WEBLINE = [sys.executable, "-c", "from webline.cli import main; main()"]
#: the same, with the report written in the command's own process
WEBLINE_ONE_PROCESS = [sys.executable, "-c", "import webline.report.early as early; "
                       "early.can_fork = lambda: False; from webline.cli import main; main()"]

#: the main job's steps as ``webline run`` takes them, timed in a fresh process
PHASES = """
import sys, time
from pathlib import Path
clock = [time.perf_counter()]
def lap(name):
    clock.append(time.perf_counter())
    print(f"  {name:48s} {clock[-1] - clock[-2]:6.3f} s")
import webline.cli
lap("import the CLI (typer, rich)")
from webline.cli_common import _load
line = _load("hswl", "speed-change")
lap("load the line (pydantic; pint if a unit is new)")
from webline.sim.simulate import simulate
lap("import the simulation (numba, scipy)")
result = simulate(line)
lap("simulate 20 s")
result.verdict
lap("verdict")
out = Path(sys.argv[1])
from webline.report.results_file import write_results
write_results(result, out)
lap("write results.nc (h5py)")
from webline.report.writer import analyse, write_report
lap("import the report (matplotlib)")
write_report(result, out, analysis=analyse(line))
lap("write figures, summary, report")
print(f"  {'all of the above, one after another':48s} {clock[-1] - clock[0]:6.3f} s")
"""


def user_env() -> dict[str, str]:
    """This process's environment as a user's Python runs: writing its .pyc files
    (``PYTHONDONTWRITEBYTECODE``, set in some sandboxes, compiles every module from source in
    every process: about 0.3 s of the main job's CPU)."""
    return {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def wall(command: list[str], repeat: int) -> float:
    """Median wall time [s] of ``repeat`` runs of ``command`` (each must succeed)."""
    return timed(command, repeat)[0]


def timed(command: list[str], repeat: int) -> tuple[float, float]:
    """Median wall time and median CPU time (user + system of the process and every process
    it waited for: the report's copies) [s] of ``repeat`` runs of ``command``."""
    times, cpus = [], []
    env = user_env()
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                       env=env)
        times.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return statistics.median(times), statistics.median(cpus)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        job = ["run", "hswl", "--scenario", "speed-change", "--quiet", "--out",
               str(Path(folder) / "run")]
        wall([*WEBLINE, *job], 1)  # compiles and caches the loop for this line's structure
        numpy, numpy_cpu = timed([sys.executable, "-c", "import numpy"], args.repeat)
        version = wall([*WEBLINE, "--version"], args.repeat)
        main_job, main_cpu = timed([*WEBLINE, *job], max(3, args.repeat // 2))
        one_process = wall([*WEBLINE_ONE_PROCESS, *job], max(3, args.repeat // 2))
        phases = subprocess.run([sys.executable, "-c", PHASES, folder], check=True,
                                env=user_env(),
                                capture_output=True, text=True).stdout
    print(f"python -c 'import numpy'                   {numpy:7.3f} s   1.00x")
    print(f"webline --version                          {version:7.3f} s   {version / numpy:5.2f}x"
          f"   goal <= 3x: {'met' if version <= 3 * numpy else 'NOT met'}")
    print(f"webline run hswl --scenario speed-change   {main_job:7.3f} s   "
          f"{main_job / numpy:5.2f}x   goal <= 1.5 s: {'met' if main_job <= 1.5 else 'NOT met'}")
    print(f"  its CPU time (the command and its report's processes) {main_cpu:6.3f} s   "
          f"goal <= 1.6 s: {'met' if main_cpu <= 1.6 else 'NOT met'}; "
          f"{main_cpu / numpy_cpu:.1f}x import numpy's {numpy_cpu:.3f} s "
          f"(tests/unit/test_startup.py allows 35x)")
    print(f"  the same, report drawn in the command's process {one_process:6.3f} s   "
          f"(the report's process saves {one_process - main_job:.2f} s)")
    print("the main job's steps, one after another in one fresh process (wall):")
    print(phases, end="")


if __name__ == "__main__":
    main()
