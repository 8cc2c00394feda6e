"""A user controller compiled into the loop (docs/controllers.md, "Moving a controller into
the loop").

The controller is a control law, a plain Python function (or a ``numba.njit`` one) that numba
compiles::

    def law(t, meas, refs, params, state, out) -> None

``t`` [s] is the tick's time; ``meas`` and ``refs`` are the measurements and references of
the Python protocol (``sim.user_control``), in its order and units (per drive: speed [m/s],
tension [N], radius [m], inertia [kg·m²]; speed reference [m/s], tension reference [N]);
``params`` the user's parameters (read them only); ``state`` the law's own memory
(integrators, filters), kept from tick to tick; ``out`` the torque command [N·m] per drive,
which the law writes. All are float64 arrays over the run's memory: the law should allocate
nothing and must keep no reference to them.

``CompiledController(law, params=..., state=...)`` is accepted wherever a Python controller
is (``simulate(line, controller=...)``, per drive or for the whole line, ``Session``). Where
every user controller of a run is compiled, the laws run inside the compiled loop's tick
(``sim.core.law_kernel``); mixed with Python controllers, the law is called from Python.
"""

from __future__ import annotations

import functools
import math
import re
import time
from collections.abc import Callable, Sequence
from typing import Any

import numba as nb
import numpy as np
from numba.core.dispatcher import Dispatcher

from webline.errors import ArgumentError, LawCompileError
from webline.sim.core import law_kernel
from webline.sim.core.law_kernel import buffer_layout, law_hook
from webline.sim.core.plan import Plan
from webline.sim.core.user_protocol import ENDINGS, reset_all
from webline.sim.drives.user_loop import N_MEASURED, N_REFERENCES, STATUS_USER_NONFINITE
from webline.sim.elements import layout as L
from webline.sim.user_control import (
    ControllerContext,
    Group,
    UserRun,
    context_for,
    controller_error,
)

#: what ``params`` and ``state`` may be: numbers, or a function of the run's context
Values = Sequence[float] | np.ndarray | Callable[[ControllerContext], Any]

_ARRAY = nb.float64[::1]
#: the law's signature: (t, meas, refs, params, state, out)
SIGNATURE = nb.void(nb.float64, _ARRAY, _ARRAY, _ARRAY, _ARRAY, _ARRAY)
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


class CompiledController:
    """A control law numba compiles into the loop (module docstring).

    ``law``: the function (plain or ``numba.njit``); ``params``: its parameters, numbers or
    ``params(context) -> numbers`` (``sim.user_control.ControllerContext``: the drives'
    gains, limits, operating point, sample period); ``state``: the size of its memory
    (zeros), its initial values, or ``state(context) -> values``; ``name``: what errors call
    it (default the function's name). ``params`` and ``state`` after ``reset`` are the arrays
    the law is given (``state`` holds the memory where the run ended).

    ``checked``: the law's checked mode, for finding a fault: every array index is checked
    (an out-of-bounds one raises ``IndexError`` and ends the run with ``ControllerError``
    naming it, where an unchecked law writes over memory, which can crash the process) and
    a non-finite ``state`` after a call ends it too; slower (documented in
    docs/controllers.md), so meant for debugging.
    """

    def __init__(self, law: Callable[..., None], *, params: Values = (),
                 state: int | Values = 0, name: str | None = None,
                 checked: bool = False) -> None:
        py_func = getattr(law, "py_func", law)
        if not callable(py_func):
            raise ArgumentError(f"CompiledController: law must be a function, "
                                f"not a {type(law).__name__}")
        self.law_source = law
        self.checked = bool(checked)
        self.name = name or getattr(py_func, "__qualname__", repr(py_func))
        self.params_given, self.state_given = params, state
        self.params = np.zeros(0)
        self.state = np.zeros(0)
        self.torques = np.zeros(0)
        self._law: Any = None

    def __getstate__(self) -> dict[str, Any]:
        """Copied or pickled without its compiled form (compiled again where used: numba's
        cache makes that quick)."""
        return {**self.__dict__, "_law": None}

    @property
    def kind(self) -> str:
        """What errors call this controller: ``compiled law <name>``."""
        return f"compiled law {self.name}"

    @property
    def law(self) -> Any:
        """The law as a numba dispatcher, compiled for ``SIGNATURE`` (``LawCompileError``,
        bad input, naming the function if numba cannot compile it)."""
        if self._law is None:
            self._law = (compile_checked(self.law_source, self.name) if self.checked
                         else compile_law(self.law_source, self.name))
        return self._law

    def reset(self, context: ControllerContext) -> None:
        """Compile the law and set its parameters and initial state for ``context``."""
        self.params = _floats(self.params_given, context, f"{self.name}: params")
        given = self.state_given
        if isinstance(given, bool):
            raise ArgumentError(f"{self.name}: state = {given}: expected a size or values")
        if isinstance(given, int | np.integer):
            if given < 0:
                raise ArgumentError(f"{self.name}: state = {given}: a size must be >= 0")
            self.state = np.zeros(int(given))
        else:
            self.state = _floats(given, context, f"{self.name}: state")
        self.torques = np.zeros(len(context.drives))
        self.law  # noqa: B018  (compile now: a failure names the law before the run)

    def __call__(self, t: float, measurements: np.ndarray,
                 references: np.ndarray) -> np.ndarray:
        """The Python protocol's call (a run that mixes it with Python controllers)."""
        self.law(t, measurements, references, self.params, self.state, self.torques)
        return self.torques


@functools.cache
def compile_law(law: Callable[..., None], name: str) -> Any:
    """``law`` compiled by numba for ``SIGNATURE``: a plain function with numba's disk cache
    where its source file allows it, a ``numba.njit`` dispatcher as its author set it up.
    Once per function in a process (the same dispatcher: ``law_kernel.law_hook`` reuses the
    hook it compiled for it)."""
    if not isinstance(law, Dispatcher):
        try:  # numba's disk cache fails on code without a stable module (a notebook's, a
            # file loaded by path): then compile without it
            dispatcher = nb.njit(cache=True, error_model="numpy")(law)
            dispatcher.compile(SIGNATURE)
            return dispatcher
        except Exception:  # any failure: compile again below, uncached
            law = nb.njit(error_model="numpy")(law)
    try:
        law.compile(SIGNATURE)
    except Exception as exc:  # numba's errors on the user's code: one line naming it
        raise LawCompileError(f"compiled law {name}: numba cannot compile {name}(t, meas, "
                              f"refs, params, state, out) with float64 arrays: "
                              f"{_first_line(exc)}") from None
    return law


@functools.cache
def compile_checked(law: Callable[..., None], name: str) -> Any:
    """``law``'s checked mode (``CompiledController``): compiled with bounds checks, wrapped
    in a law that raises where the state becomes non-finite; ``LawCompileError`` as
    ``compile_law``."""
    py_func = getattr(law, "py_func", law)
    inner = nb.njit(boundscheck=True, error_model="python")(py_func)

    def checked(t: float, meas: np.ndarray, refs: np.ndarray, params: np.ndarray,
                state: np.ndarray, out: np.ndarray) -> None:
        inner(t, meas, refs, params, state, out)
        for i in range(state.size):
            if not math.isfinite(state[i]):
                raise FloatingPointError("state became non-finite (checked mode)")

    try:
        return compile_law(nb.njit(boundscheck=True, error_model="python")(checked), name)
    except LawCompileError:
        raise
    except Exception as exc:  # numba's errors on the user's code
        raise LawCompileError(f"compiled law {name}: numba cannot compile it in checked "
                              f"mode: {_first_line(exc)}") from None


#: what the error of a compiled law that failed recommends
CHECKED_HINT = ("; to find it, run the law in checked mode (checked = true in the line "
                "file, CompiledController(..., checked=True): bounds and NaN checks, slower)")


def _first_line(exc: Exception) -> str:
    """The first informative line of a numba error (its colour codes removed)."""
    lines = [line.strip() for line in _ANSI.sub("", str(exc)).splitlines() if line.strip()]
    lines = [line for line in lines
             if not line.startswith(("During:", "File ", "^", "Failed in ", "<source"))]
    return f"{type(exc).__name__}: {lines[0] if lines else ''}"


def _floats(given: Values, context: ControllerContext, what: str) -> np.ndarray:
    """``given`` (numbers or a function of ``context``) as a fresh 1-d float64 array."""
    try:
        values = given(context) if callable(given) else given
        array = np.array(values, dtype=np.float64).ravel()
    except Exception as exc:  # the user's function or values
        raise ArgumentError(f"{what}: {type(exc).__name__}: {exc}") from None
    return np.ascontiguousarray(array)


def run_compiled(plan: Plan, groups: Sequence[Group], x0: np.ndarray, istate0: np.ndarray,
                 slip0: np.ndarray, n_ticks: int, substeps: int, every: int,
                 buffer: np.ndarray) -> UserRun:
    """``user_control.run_user`` where every controller is a ``CompiledController``: the
    laws run inside the compiled loop (``sim.core.law_kernel``), in chunks of about 0.1 s of
    wall time (Ctrl-C is seen between them). Each controller's ``params`` and ``state``
    become views of the run's buffer (``state``: its memory where the run ended)."""
    controllers: list[CompiledController] = []
    for g in groups:
        assert isinstance(g.controller, CompiledController)
        controllers.append(g.controller)
    ended = reset_all(groups, lambda g: context_for(plan, g, istate0))
    if ended is not None:  # (a ``params(context)`` or ``state(context)`` of the user's)
        return UserRun(0, STATUS_USER_NONFINITE, 0.0, -1, x0.copy(), istate0.copy(),
                       ended[1], ended[0].name)
    users = tuple(d for g in groups for d in g.drives)
    hook = law_hook(users, tuple((c.law, len(g.drives), c.params.size, c.state.size)
                                 for c, g in zip(controllers, groups, strict=True)))
    layout = buffer_layout(len(users), sum(c.params.size for c in controllers),
                           sum(c.state.size for c in controllers))
    buf = np.zeros(layout["raised"][1])
    p0, s0 = layout["params"][0], layout["state"][0]
    for c in controllers:  # the laws' arrays become views of the run's buffer
        buf[p0:p0 + c.params.size], buf[s0:s0 + c.state.size] = c.params, c.state
        c.params, c.state = buf[p0:p0 + c.params.size], buf[s0:s0 + c.state.size]
        p0, s0 = p0 + c.params.size, s0 + c.state.size
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
        tick = round(t_fail / plan.dt)
        raised = int(buf[layout["raised"][0]])
        group = groups[raised - 1] if raised else next(g for g in groups if where in g.drives)
        drive = plan.line.node_name(plan.line.drives[where])
        run.where, run.controller = -1, group.name
        run.error = controller_error(group, tick, t_fail, None, f"returned a non-finite "
                                     f"torque for {drive}") + _hint(group)
        if raised:
            run.error = _raised(group, groups, tick, t_fail, buf, layout) + _hint(group)
    return run


def _hint(group: Group) -> str:
    """``CHECKED_HINT`` for an unchecked law (nothing for one in checked mode)."""
    ctrl = group.controller
    return "" if isinstance(ctrl, CompiledController) and ctrl.checked else CHECKED_HINT


def _raised(group: Group, groups: Sequence[Group], tick: int, t: float, buf: np.ndarray,
            layout: dict[str, tuple[int, int]]) -> str:
    """The error of ``group``'s law, which raised in the loop at ``tick`` (time ``t`` [s]):
    compiled code keeps no exception, so the law's Python function is run again on copies of
    that tick's arrays to name it (its state as the failed call left it)."""
    first = p0 = s0 = 0
    for g in groups:
        if g is group:
            break
        c = g.controller
        assert isinstance(c, CompiledController)
        first, p0, s0 = first + len(g.drives), p0 + c.params.size, s0 + c.state.size
    ctrl, k = group.controller, len(group.drives)
    assert isinstance(ctrl, CompiledController)
    m, r = layout["meas"][0] + N_MEASURED * first, layout["refs"][0] + N_REFERENCES * first
    py_func = getattr(ctrl.law, "py_func", None)
    try:
        if py_func is not None:
            py_func(t, buf[m:m + N_MEASURED * k].copy(), buf[r:r + N_REFERENCES * k].copy(),
                    ctrl.params.copy(), ctrl.state.copy(), np.zeros(k))
    except ENDINGS as exc:  # the user's law, run in Python: its own error
        return controller_error(group, tick, t, exc)
    return controller_error(group, tick, t, None, "raised an exception in compiled code "
                            "(numba keeps no message; run the law in Python to see it)")
