"""Chunks of a study run on Dask hold at least ``chunks.TASK_RK4_STEPS`` of kernel work each
(issue 37: 32-case chunks of 10 s HSWL ran at 0.31 of the local batch's speed), the last
at least half as large as the others; a resumed study keeps the chunk size it started with."""

from __future__ import annotations

import json
import math

import pytest

from webline.sim.sweeps import chunks
from webline.sim.sweeps.chunks import CHUNK, TASK_RK4_STEPS, stored_chunk, task_chunk


def test_ten_thousand_hswl_cases_of_ten_seconds_run_in_twenty_tasks_of_a_second() -> None:
    # a 10 s HSWL case: 10 000 ticks of one RK4 step (budget.estimate, 1 kHz control)
    chunk = task_chunk(10_000, 10_000)
    assert chunk == 500  # 1e8 steps / 5e6 per task = 20 tasks of 500 cases
    assert chunk * 10_000 >= TASK_RK4_STEPS


@pytest.mark.parametrize("n_cases", [1, 7, 300, 1024, 9_999, 10_000, 123_457])
@pytest.mark.parametrize("case_steps", [1, 50, 10_000, 19_531, 2_000_000])
def test_every_task_holds_a_task_of_work_and_the_chunks_are_equal(n_cases, case_steps) -> None:
    chunk = task_chunk(n_cases, case_steps)
    tasks = math.ceil(n_cases / chunk)
    if chunk == CHUNK:  # long cases: the default chunk already holds a task's work
        assert CHUNK * case_steps >= TASK_RK4_STEPS
        return
    if tasks == 1:  # the whole study is less than two tasks' work: one task
        assert n_cases * case_steps < 2 * TASK_RK4_STEPS
        return
    assert chunk * case_steps >= TASK_RK4_STEPS  # every chunk but the last, whole
    last = n_cases - (tasks - 1) * chunk
    assert last >= chunk / 2  # never a task nearly empty


def test_a_resumed_store_keeps_its_chunk_size(tmp_path) -> None:
    assert stored_chunk(tmp_path) is None  # no record: a new study
    (tmp_path / chunks.STUDY_FILE).write_text(json.dumps({"chunk": 32, "cases": []}))
    assert stored_chunk(tmp_path) == 32
    (tmp_path / chunks.STUDY_FILE).write_text("{not json")
    assert stored_chunk(tmp_path) is None  # unreadable: check_resume names the problem
