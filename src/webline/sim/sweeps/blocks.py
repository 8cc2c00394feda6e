"""How a study's cases are cut into blocks and threads, for every kind of line.

A block of cases is built in Python (plans, operating points), run in compiled code that
releases the GIL, and collected in Python (metrics, verdicts). ``run_blocks`` overlaps the
three: while block b runs, this thread collects block b - 1 and builds block b + 1, so
memory stays bounded by a few blocks. Inside a run, ``over_ranges`` gives disjoint ranges of
cases to threads, so a batch uses every core.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

#: Cases built and run together, at most: their plans are built while the block before runs
#: in compiled code (which releases the GIL), and dropped after it, so memory stays bounded.
BLOCK = 256
#: The first block's size: nothing runs while it is built, so it is small; blocks then
#: double up to ``BLOCK``.
FIRST_BLOCK = 16


def blocks_of(n: int, largest: int | None = None) -> list[range]:
    """Consecutive ranges covering ``n`` cases: ``FIRST_BLOCK``, then doubling to ``largest``
    (default and at most ``BLOCK``)."""
    largest = BLOCK if largest is None else min(largest, BLOCK)
    out, lo, size = [], 0, min(FIRST_BLOCK, largest)
    while lo < n:
        out.append(range(lo, min(n, lo + size)))
        lo, size = lo + size, min(largest, 2 * size)
    return out


def run_blocks(blocks: list[range], build: Callable[[range], Any],
               run: Callable[[Any], Any], collect: Callable[[range, Any, Any], None],
               workers: int | None) -> None:
    """``collect(block, built, run(built))`` with ``built = build(block)`` for each block in
    order; with more than one worker a block runs on a thread while the next is built and
    the one before collected."""
    if workers == 1:  # one core: build, run and collect in turn
        for block in blocks:
            built = build(block)
            collect(block, built, run(built))
    elif blocks:
        with ThreadPoolExecutor(1) as runner:
            built = build(blocks[0])
            pending = (blocks[0], built, runner.submit(run, built))
            for block in blocks[1:]:
                built = build(block)
                done_block, done_built, future = pending
                outputs = future.result()
                pending = (block, built, runner.submit(run, built))
                collect(done_block, done_built, outputs)
            collect(pending[0], pending[1], pending[2].result())


def over_ranges(n_cases: int, workers: int | None, task: Callable[[int, int], None]) -> None:
    """``task(lo, hi)`` over disjoint ranges covering ``n_cases`` cases, on ``workers``
    threads (default: the cores); several ranges per thread, so a slow case does not leave
    the other threads idle."""
    workers = workers or os.cpu_count() or 1
    size = max(1, math.ceil(n_cases / (4 * workers)))
    bounds = [(lo, min(n_cases, lo + size)) for lo in range(0, n_cases, size)]
    if workers == 1:
        for lo, hi in bounds:
            task(lo, hi)
    else:
        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(lambda b: task(*b), bounds))
