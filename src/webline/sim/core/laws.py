"""Users' compiled control laws (docs/controllers.md, "Moving a controller into the loop"):
what every line's loop shares of them.

The controller is a control law, a plain Python function (or a ``numba.njit`` one) that numba
compiles::

    def law(t, meas, refs, params, state, out) -> None

``t`` [s] is the tick's time; ``meas`` and ``refs`` are the measurements and references of
the Python protocol (``sim.core.user_protocol``), in its order and units (per drive: speed
[m/s], tension [N], radius [m], inertia [kg·m²]; speed reference [m/s], tension reference
[N]); ``params`` the user's parameters (read them only); ``state`` the law's own memory
(integrators, filters), kept from tick to tick; ``out`` the torque command [N·m] per drive,
which the law writes. All are float64 arrays over the run's memory: the law should allocate
nothing and must keep no reference to them.

Here: ``CompiledController`` (the law, its parameters and state), the laws of a run chained
into one inlined call (``chained_laws``), the run's law buffer (``LawBuffer``: the user
drives' readings and commands, the laws' parameters and states, the flag of a law that
raised) and the words of a law's failure (``law_failure``). Each loop gathers its drives'
readings into the buffer in its own way: the chain's through a hook (``sim.core.law_kernel``),
a branched line's inside its loop (``sim.branches.loop.user``).
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numba as nb
import numpy as np
from numba.core.dispatcher import Dispatcher

from webline.errors import ArgumentError, LawCompileError
from webline.sim.core.user_protocol import ENDINGS, Group, controller_error
from webline.sim.drives.user_loop import N_MEASURED, N_REFERENCES
from webline.sim.elements.signals import _NO_NRT, FAST

#: what ``params`` and ``state`` may be: numbers, or a function of the run's context
Values = Sequence[float] | np.ndarray | Callable[[Any], Any]

_ARRAY = nb.float64[::1]
#: the law's signature: (t, meas, refs, params, state, out)
SIGNATURE = nb.void(nb.float64, _ARRAY, _ARRAY, _ARRAY, _ARRAY, _ARRAY)
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


class CompiledController:
    """A control law numba compiles into the loop (module docstring).

    ``law``: the function (plain or ``numba.njit``); ``params``: its parameters, numbers or
    ``params(context) -> numbers`` (the run's controller context, the chain's
    ``sim.user_control.ControllerContext`` or a branched line's: the drives' gains, limits,
    operating point, sample period); ``state``: the size of its memory (zeros), its initial
    values, or ``state(context) -> values``; ``name``: what errors call it (default the
    function's name). ``params`` and ``state`` after ``reset`` are the arrays
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

    def reset(self, context: Any) -> None:
        """Compile the law and set its parameters and initial state for ``context`` (the
        chain's ``sim.user_control.ControllerContext`` or a branched line's
        ``sim.branches.user.loop.BranchControllerContext``: both ``NamedReadings`` with the
        drives commanded)."""
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


def _floats(given: Values, context: Any, what: str) -> np.ndarray:
    """``given`` (numbers or a function of ``context``) as a fresh 1-d float64 array."""
    try:
        values = given(context) if callable(given) else given
        array = np.array(values, dtype=np.float64).ravel()
    except Exception as exc:  # the user's function or values
        raise ArgumentError(f"{what}: {type(exc).__name__}: {exc}") from None
    return np.ascontiguousarray(array)




#: the laws' helpers: inlined into the loop, no reference counting (every array is the
#: run's), not disk-cached (a closure over a user's law has no stable cache key)
law_njit = nb.njit(fastmath=FAST, error_model="numpy", forceinline=True, **_NO_NRT)


@law_njit
def _no_law(t: float, meas: np.ndarray, refs: np.ndarray, params: np.ndarray,
            state: np.ndarray, out: np.ndarray, raised: np.ndarray) -> None:
    """The start of a chain of laws (``_chained``): nothing."""


def _chained(before: Any, law: Any, group: int, first: int, count: int,
             params: tuple[int, int], state: tuple[int, int]) -> Any:
    """``before``, then ``law`` (of group number ``group``) on the user drives ``first`` ..
    ``first + count - 1`` and its (start, stop) of the parameters and state. A law that
    raises sets ``raised[0]`` to its group number + 1 (the first to raise is kept): compiled
    code without Python's runtime cannot pass an exception on."""
    m0, m1 = N_MEASURED * first, N_MEASURED * (first + count)
    r0, r1 = N_REFERENCES * first, N_REFERENCES * (first + count)
    p0, p1 = params
    s0, s1 = state
    o0, o1 = first, first + count

    @law_njit
    def call(t: float, meas: np.ndarray, refs: np.ndarray, all_params: np.ndarray,
             all_state: np.ndarray, commands: np.ndarray, raised: np.ndarray) -> None:
        before(t, meas, refs, all_params, all_state, commands, raised)
        try:
            law(t, meas[m0:m1], refs[r0:r1], all_params[p0:p1], all_state[s0:s1],
                commands[o0:o1])
        except Exception:  # the user's law: any error stops the run
            if raised[0] == 0.0:
                raised[0] = group + 1.0

    return call


#: a run's laws as ``chained_laws`` takes them: per group its dispatcher, number of drives,
#: of parameters and of state values
LawKey = tuple[tuple[Any, int, int, int], ...]


@functools.cache
def chained_laws(laws: LawKey) -> Any:
    """One inlined compiled call ``call(t, meas, refs, params, state, commands, raised)``
    that runs every law of ``laws`` in group order on its slices of the run's concatenated
    arrays (``LawBuffer``); the same function for the same laws in a process."""
    call, first, p0, s0 = _no_law, 0, 0, 0
    for group, (law, count, n_p, n_s) in enumerate(laws):
        call = _chained(call, law, group, first, count, (p0, p0 + n_p), (s0, s0 + n_s))
        first, p0, s0 = first + count, p0 + n_p, s0 + n_s
    return call


def buffer_layout(n_users: int, n_params: int, n_state: int) -> dict[str, tuple[int, int]]:
    """(start, stop) in a run's law buffer of the user drives' measurements, references and
    commands, the laws' parameters and states (each concatenated in group order), and the
    number + 1 of the first group whose law raised (0: none)."""
    sizes = {"meas": N_MEASURED * n_users, "refs": N_REFERENCES * n_users,
             "commands": n_users, "params": n_params, "state": n_state, "raised": 1}
    layout, start = {}, 0
    for name, size in sizes.items():
        layout[name] = (start, start + size)
        start += size
    return layout


@dataclass(frozen=True)
class LawBuffer:
    """The compiled laws of a run's ``groups`` (each controller a ``CompiledController``,
    already ``reset``), their ``key`` (``chained_laws``), the user drives in group order
    (``users``: indices into the drive table) and where each part lies in the run's law
    buffer (``layout``, ``buffer_layout``; ``size`` values in all)."""

    groups: tuple[Group, ...]
    key: LawKey
    users: tuple[int, ...]
    layout: dict[str, tuple[int, int]]

    @classmethod
    def of(cls, groups: Sequence[Group]) -> LawBuffer:
        """The laws of ``groups`` (compiled by their ``reset``)."""
        controllers = [in_loop(g) for g in groups]
        key = tuple((c.law, len(g.drives), c.params.size, c.state.size)
                    for c, g in zip(controllers, groups, strict=True))
        users = tuple(d for g in groups for d in g.drives)
        return cls(tuple(groups), key, users, buffer_layout(
            len(users), sum(c.params.size for c in controllers),
            sum(c.state.size for c in controllers)))

    @property
    def size(self) -> int:
        return self.layout["raised"][1]

    def attach(self, buf: np.ndarray) -> None:
        """Copy each law's ``params`` and ``state`` into ``buf`` (``size`` values: the run's
        memory) and make them views of it: ``state`` then holds the law's memory as the
        run leaves it."""
        buf[self.layout["raised"][0]] = 0.0
        p0, s0 = self.layout["params"][0], self.layout["state"][0]
        for g in self.groups:
            c = in_loop(g)
            buf[p0:p0 + c.params.size], buf[s0:s0 + c.state.size] = c.params, c.state
            c.params, c.state = buf[p0:p0 + c.params.size], buf[s0:s0 + c.state.size]
            p0, s0 = p0 + c.params.size, s0 + c.state.size

    def failure(self, buf: np.ndarray, where: int, t: float, dt: float,
                drive_name: Callable[[int], str]) -> tuple[str, str]:
        """(the controller's name, the one-line error) of a run stopped at time ``t`` [s]
        (sample period ``dt``) because a law raised (the flag in ``buf``) or gave user drive
        ``where`` (index into the drive table; named by ``drive_name``) a non-finite
        command."""
        tick = round(t / dt)
        raised = int(buf[self.layout["raised"][0]])
        group = (self.groups[raised - 1] if raised
                 else next(g for g in self.groups if where in g.drives))
        if raised:
            return group.name, self._raised(group, tick, t, buf) + _hint(group)
        return group.name, controller_error(group, tick, t, None, f"returned a non-finite "
                                            f"torque for {drive_name(where)}") + _hint(group)

    def _raised(self, group: Group, tick: int, t: float, buf: np.ndarray) -> str:
        """The error of ``group``'s law, which raised in the loop at ``tick`` (time ``t``
        [s]): compiled code keeps no exception, so the law's Python function is run again on
        copies of that tick's arrays to name it (its state as the failed call left it)."""
        first = 0
        for g in self.groups:
            if g is group:
                break
            first += len(g.drives)
        ctrl, k = in_loop(group), len(group.drives)
        m = self.layout["meas"][0] + N_MEASURED * first
        r = self.layout["refs"][0] + N_REFERENCES * first
        py_func = getattr(ctrl.law, "py_func", None)
        try:
            if py_func is not None:
                py_func(t, buf[m:m + N_MEASURED * k].copy(),
                        buf[r:r + N_REFERENCES * k].copy(), ctrl.params.copy(),
                        ctrl.state.copy(), np.zeros(k))
        except ENDINGS as exc:  # the user's law, run in Python: its own error
            return controller_error(group, tick, t, exc)
        return controller_error(group, tick, t, None, "raised an exception in compiled "
                                "code (numba keeps no message; run the law in Python to "
                                "see it)")


def in_loop(group: Group) -> CompiledController:
    """``group``'s controller, a ``CompiledController``."""
    ctrl = group.controller
    assert isinstance(ctrl, CompiledController)
    return ctrl


def all_compiled(groups: Sequence[Group]) -> bool:
    """Whether every controller of ``groups`` is a compiled law (the run then calls them
    inside the compiled loop; mixed with Python controllers, from Python)."""
    return bool(groups) and all(isinstance(g.controller, CompiledController) for g in groups)


def _hint(group: Group) -> str:
    """``CHECKED_HINT`` for an unchecked law (nothing for one in checked mode)."""
    ctrl = group.controller
    return "" if isinstance(ctrl, CompiledController) and ctrl.checked else CHECKED_HINT
