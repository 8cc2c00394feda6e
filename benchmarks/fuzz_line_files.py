"""Fuzz the front door: N mutated line files through what ``webline validate`` does.

    python benchmarks/fuzz_line_files.py --n 10000 --seed 1

Each file (a built-in line damaged by one category of ``fuzz_mutations``) is loaded, every
scenario applied and the line's plan built, in a worker process with a per-case timeout.
Prints one row per category: tried | clean reject (a ``LineFileError``) | accepted |
crash (any other exception) | hang (past the timeout) | accepted-but-absurd (a loaded value
outside its hard range, or not finite). Exit status 1 if any crash, hang or absurd value.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import random
import sys
import tempfile
import time
import traceback
from collections import Counter
from multiprocessing.connection import Connection
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fuzz_mutations import CATEGORIES, check, mutate

ORDER = [*CATEGORIES, "file"]


class RandomChooser:
    """The ``Chooser`` of ``fuzz_mutations`` over ``random.Random``."""

    def __init__(self, seed: int) -> None:
        self.rng = random.Random(seed)

    def pick(self, options):  # type: ignore[no-untyped-def]
        return options[self.rng.randrange(len(options))]

    def integer(self, low: int, high: int) -> int:
        return self.rng.randint(low, high)


def worker(conn: Connection, folder: str) -> None:
    """Check the files sent on ``conn``; answer (outcome, detail) for each."""
    path = str(Path(folder) / "line.toml")
    sys.setrecursionlimit(1000)  # as a fresh interpreter has it
    while True:
        raw = conn.recv()
        if raw is None:
            return
        try:
            conn.send(check(raw, path))
        except BaseException as exc:
            conn.send(("crash", "".join(traceback.format_exception_only(exc)).strip()[:300]))


def start(folder: str) -> tuple[mp.Process, Connection]:
    here, there = mp.Pipe()
    process = mp.Process(target=worker, args=(there, folder), daemon=True)
    process.start()
    return process, here


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=10_000, help="files to try")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=float, default=30.0, help="per case [s]")
    args = parser.parse_args()
    counts: dict[str, Counter[str]] = {c: Counter() for c in ORDER}
    examples: list[str] = []
    started = time.perf_counter()
    slowest = 0.0
    with tempfile.TemporaryDirectory() as folder:
        process, conn = start(folder)
        for case in range(args.n):
            category = ORDER[case % len(ORDER)]
            raw = mutate(category, RandomChooser(args.seed * 1_000_003 + case))
            t0 = time.perf_counter()
            conn.send(raw)
            if conn.poll(args.timeout):
                outcome, detail = conn.recv()
            else:
                outcome, detail = "hang", f"over {args.timeout:g} s"
                process.kill()
                process, conn = start(folder)
            slowest = max(slowest, time.perf_counter() - t0)
            counts[category][outcome] += 1
            if outcome in ("crash", "hang", "absurd") and len(examples) < 20:
                examples.append(f"case {case} ({category}): {outcome}: {detail}")
        conn.send(None)
        process.join(5)
    header = ["category", "tried", "clean reject", "accepted", "crash", "hang",
              "accepted-but-absurd"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    total: Counter[str] = Counter()
    for category in ORDER:
        c = counts[category]
        total.update(c)
        print(f"| {category} | {sum(c.values())} | {c['clean']} | {c['accepted']} | "
              f"{c['crash']} | {c['hang']} | {c['absurd']} |")
    print(f"| all | {sum(total.values())} | {total['clean']} | {total['accepted']} | "
          f"{total['crash']} | {total['hang']} | {total['absurd']} |")
    print(f"\n{args.n} files, seed {args.seed}, in {time.perf_counter() - started:.0f} s; "
          f"slowest case {slowest:.2f} s (timeout {args.timeout:g} s)")
    for line in examples:
        print(line)
    return 1 if total["crash"] or total["hang"] or total["absurd"] else 0


if __name__ == "__main__":
    sys.exit(main())
