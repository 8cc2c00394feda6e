"""A user controller compiled into the loop (docs/controllers.md, "Moving a controller into
the loop"): the law's contract, ``CompiledController`` and what every loop shares of them live
in ``sim.core.laws``; here the chain's run with every user controller a compiled law, the laws
inside the compiled loop's tick (``sim.core.law_kernel``). Mixed with Python controllers, the
law is called from Python. (A branched line's laws run inside its loop too:
``sim.branches.user.loop``.)
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence

import numpy as np

from webline.sim.core import law_kernel
from webline.sim.core.law_kernel import law_hook
from webline.sim.core.laws import (
    CHECKED_HINT,
    CompiledController,
    LawBuffer,
    compile_checked,
    compile_law,
)
from webline.sim.core.plan import Plan
from webline.sim.core.user_protocol import reset_all
from webline.sim.drives.user_loop import STATUS_USER_NONFINITE
from webline.sim.elements import layout as L
from webline.sim.user_control import Group, UserRun, context_for

__all__ = ["CHECKED_HINT", "CompiledController", "compile_checked", "compile_law",
           "run_compiled"]


def run_compiled(plan: Plan, groups: Sequence[Group], x0: np.ndarray, istate0: np.ndarray,
                 slip0: np.ndarray, n_ticks: int, substeps: int, every: int,
                 buffer: np.ndarray) -> UserRun:
    """``user_control.run_user`` where every controller is a ``CompiledController``: the
    laws run inside the compiled loop (``sim.core.law_kernel``), in chunks of about 0.1 s of
    wall time (Ctrl-C is seen between them). Each controller's ``params`` and ``state``
    become views of the run's buffer (``state``: its memory where the run ended)."""
    ended = reset_all(groups, lambda g: context_for(plan, g, istate0))
    if ended is not None:  # (a ``params(context)`` or ``state(context)`` of the user's)
        return UserRun(0, STATUS_USER_NONFINITE, 0.0, -1, x0.copy(), istate0.copy(),
                       ended[1], ended[0].name)
    laws = LawBuffer.of(groups)
    hook = law_hook(laws.users, laws.key)
    buf = np.zeros(laws.size)
    laws.attach(buf)  # the laws' arrays become views of the run's buffer
    x, istate, slipping = x0, istate0, slip0
    # chunks as the built-in run's (``simulate.FIRST_CHUNK``, then ~0.1 s of work each)
    status, t_fail, where, done, stored, chunk = L.STATUS_OK, math.nan, -1, 0, 0, 2000
    interrupted = False
    try:
        while done < n_ticks and status == L.STATUS_OK:
            count = min(chunk, n_ticks - done)
            last = done + count == n_ticks
            started = time.perf_counter()
            n_rec, status, t_fail, where, x, istate, slipping = law_kernel.run(
                plan, x, istate, slipping, done, count, substeps, every, last,
                buffer[stored:], hook, buf)
            stored += n_rec
            done += count
            elapsed = time.perf_counter() - started
            chunk = max(500, round(count * 0.1 / max(elapsed, 1e-6)))
    except KeyboardInterrupt:  # Ctrl-C between chunks: keep what was computed
        interrupted = True
    run = UserRun(stored, status, t_fail, where, x, istate, interrupted=interrupted)
    if status == STATUS_USER_NONFINITE:
        run.where = -1
        run.controller, run.error = laws.failure(
            buf, where, t_fail, plan.dt, lambda d: plan.line.node_name(plan.line.drives[d]))
    return run
