"""Benchmark of the main job's wall time (issue 12): how long a user waits for the CLI.

Run:  python benchmarks/bench_startup.py      (options: --repeat N)

Measured in the same run, each as the median of ``--repeat`` fresh processes, and printed as
a ratio to the plain peer ``python -c "import numpy"`` (the machine is shared and noisy: the
ratio means more than the seconds):

* ``webline --version``: the CLI's start-up (goal: at most 3x ``import numpy``);
* ``webline run hswl --scenario speed-change``: the main job with a warm numba cache (one
  unmeasured run first compiles and caches the loop), writing results, figures, summary and
  report to a temporary folder (goal: at most 1.5 s wall on the project's 2-core machine).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

WEBLINE = [sys.executable, "-c", "from webline.cli import main; main()"]


def wall(command: list[str], repeat: int) -> float:
    """Median wall time [s] of ``repeat`` runs of ``command`` (each must succeed)."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        run = [*WEBLINE, "run", "hswl", "--scenario", "speed-change", "--quiet",
               "--out", str(Path(folder) / "run")]
        wall(run, 1)  # compiles and caches the loop for this line's structure
        numpy = wall([sys.executable, "-c", "import numpy"], args.repeat)
        version = wall([*WEBLINE, "--version"], args.repeat)
        main_job = wall(run, max(3, args.repeat // 2))
    print(f"python -c 'import numpy'                   {numpy:7.3f} s   1.00x")
    print(f"webline --version                          {version:7.3f} s   {version / numpy:5.2f}x"
          f"   goal <= 3x: {'met' if version <= 3 * numpy else 'NOT met'}")
    print(f"webline run hswl --scenario speed-change   {main_job:7.3f} s   "
          f"{main_job / numpy:5.2f}x   goal <= 1.5 s: {'met' if main_job <= 1.5 else 'NOT met'}")


if __name__ == "__main__":
    main()
