"""The first run from empty caches (issue 37): what a new user waits for before anything is
compiled, in CPU time (less sensitive to a shared machine's load than wall time).

    python benchmarks/bench_first_run.py [--src DIR ...]

With a fresh numba cache (``NUMBA_CACHE_DIR``) and a fresh unit cache (``XDG_CACHE_HOME``,
where webline keeps pint's parsed definitions), each in a new temporary folder, it runs

1. ``webline run hswl`` (the built-in single-path line; goal: at most 12 CPU-seconds), then
2. ``webline run laminator`` (the built-in branched line; goal: at most 8 CPU-seconds more),

and prints for each its CPU time (user + system of the command and every process it waited
for) and wall time, the load average beside them, and then what the numba cache holds: the
compiled functions and every function compiled for more than one signature (a duplicate
specialisation costs its compile time again). ``--src`` runs the same for each source tree
given (``PYTHONPATH``), one after another in this run, to compare two versions on the same
machine at the same load (e.g. ``--src /tmp/main/src --src src``).
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

WEBLINE = [sys.executable, "-c", "from webline.cli import main; main()"]
#: the runs timed, in order, with their CPU goals [s] (the second: more than the first)
RUNS = (("hswl", 12.0), ("laminator", 8.0))
#: a compiled function's cache file: ``module.function-line.pyXY.N.nbc`` (N: its signature)
OVERLOAD = re.compile(r"^(?P<function>.+-\d+)\.py\d+\.(?P<n>\d+)\.nbc$")


def load() -> str:
    """The load average (1/5/15 min)."""
    return "/".join(f"{x:.2f}" for x in os.getloadavg())


def timed(command: list[str], env: dict[str, str]) -> tuple[float, float]:
    """(CPU [s], wall [s]) of ``command`` run to success: user + system time of it and of
    every process it waited for."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - started
    if done.returncode not in (0, 1):  # 1: the line's own verdict (failed), still a run
        raise SystemExit(f"{' '.join(command[3:])} exited {done.returncode}:\n{done.stderr}")
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime, wall


def overloads(cache: Path) -> dict[str, int]:
    """Signatures compiled per function in the numba cache folder ``cache``."""
    counts: collections.Counter[str] = collections.Counter()
    for path in cache.rglob("*.nbc"):
        match = OVERLOAD.match(path.name)
        if match:
            counts[match["function"]] += 1
    return dict(counts)


def first_runs(src: str | None) -> None:
    """Time ``RUNS`` from empty caches with ``src`` on PYTHONPATH (None: as this process)."""
    with tempfile.TemporaryDirectory(prefix="webline-first-run-") as folder:
        root = Path(folder)
        env = {**os.environ, "NUMBA_CACHE_DIR": str(root / "numba"),
               "XDG_CACHE_HOME": str(root / "cache")}
        env.pop("PYTHONDONTWRITEBYTECODE", None)  # a user's Python writes its .pyc files
        if src is not None:
            env["PYTHONPATH"] = str(Path(src).resolve())
        print(f"sources: {src or 'as installed / PYTHONPATH'}")
        total = 0.0
        for line, goal in RUNS:
            print(f"  load average {load()}", flush=True)
            cpu, wall = timed([*WEBLINE, "run", line, "-q", "--out", str(root / line)], env)
            total += cpu
            print(f"  first webline run {line:10s} {cpu:6.1f} s CPU  {wall:6.1f} s wall   "
                  f"goal <= {goal:.0f} s CPU: {'met' if cpu <= goal else 'NOT met'}")
        counts = overloads(root / "numba")
        again = {f: n for f, n in counts.items() if n > 1}
        print(f"  together {total:.1f} s CPU; the numba cache holds {sum(counts.values())} "
              f"compiled signatures of {len(counts)} functions, load average {load()}")
        for function, n in sorted(again.items(), key=lambda item: -item[1]):
            print(f"    compiled {n}x: {function}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--src", action="append", default=None,
                        help="a source tree to put on PYTHONPATH (repeat to compare)")
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} cores, load average {load()} (1/5/15 min)")
    for src in args.src or [None]:
        first_runs(src)


if __name__ == "__main__":
    main()
