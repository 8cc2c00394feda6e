"""The step of a user run (``sim.user_control``): one live tick of the compiled loop, then
the next tick's controller sample on a scratch copy (``sim.drives.user_loop``), in one compiled
call
so that a tick costs Python one dispatch.

numba's dispatcher costs about a tenth of a microsecond per argument it unboxes (more for a
tuple), which with the loop's two dozen arrays was most of a tick's cost. So every float array
of the run lives in one buffer and every integer array in another (``Packed``), and the step
takes those two and the records: it cuts its arrays out of them by the segment table at the
head of the integer buffer. Python reads and writes the same memory through ``Packed``'s views.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.sim.core.kernel import advance
from webline.sim.core.plan import StructureKey, structure_arrays
from webline.sim.drives.user_loop import (
    N_MEASURED,
    N_REFERENCES,
    STATUS_USER_NONFINITE,
    U_CMD,
    U_ROWS,
    U_SPEED,
    U_VREF,
)
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit, loop_njit

if TYPE_CHECKING:
    from webline.sim.core.plan import Plan

#: float segments: the live arrays (x, istate, out, stages, refs, work), their scratch copies,
#: one record row, the user's measured / references / commands, the plan's float parameters
#: (nodes, spans, drives, web, wound ripple, speed ripple, profile times and values), the
#: time of a failure [s]
FLOAT_SEGMENTS = ("x", "istate", "out", "stages", "refs", "work",
                  "x_s", "istate_s", "out_s", "stages_s", "refs_s", "work_s", "rec_s",
                  "measured", "references", "commands", "nodes", "spans", "drives", "web",
                  "wound_ripple", "speed_ripple", "prof_t", "prof_v", "t_fail")
#: integer segments: the step's settings and results (``C_*``), live and scratch stick/slip
#: states, the user drives' indices, the profile offsets
INT_SEGMENTS = ("control", "slip", "slip_s", "users", "prof_off")
(C_TICK, C_STORED, C_N_TICKS, C_INCLUDE_END, C_MEASURE, C_SUBSTEPS, C_EVERY, C_N_REC,
 C_STATUS, C_WHERE) = range(10)
#: the segment table: (start, rows, columns) per segment, floats then integers
HEAD = 3 * (len(FLOAT_SEGMENTS) + len(INT_SEGMENTS))
N_CONTROL = 10


@dataclass
class Packed:
    """The run's arrays in two buffers (module docstring); ``views[name]`` is each segment's
    array (1- or 2-d) over the same memory."""

    floats: np.ndarray
    ints: np.ndarray
    views: dict[str, np.ndarray]

    @classmethod
    def of(cls, shapes: dict[str, tuple[tuple[int, int], type]]) -> Packed:
        """Buffers for segments of (rows, columns) and type, in the ``*_SEGMENTS`` order."""
        head = np.zeros(HEAD, dtype=np.int64)
        starts = {float: 0, int: HEAD}
        table = {}
        for k, name in enumerate(FLOAT_SEGMENTS + INT_SEGMENTS):
            (rows, cols), kind = shapes[name]
            table[name] = (starts[kind], rows, cols, kind)
            head[3 * k:3 * k + 3] = (starts[kind], rows, cols)
            starts[kind] += rows * cols
        floats = np.zeros(starts[float])
        ints = np.zeros(starts[int], dtype=np.int64)
        ints[:HEAD] = head
        views = {}
        for name, (start, rows, cols, kind) in table.items():
            buffer = floats if kind is float else ints
            flat = buffer[start:start + rows * cols]
            views[name] = flat if name in ("x", "x_s", "measured", "references", "commands",
                                           "web", "prof_t", "prof_v", "t_fail", "control",
                                           "slip", "slip_s", "users", "prof_off") \
                else flat.reshape(rows, cols)
        return cls(floats, ints, views)


@jit
def _copy(dst: np.ndarray, src: np.ndarray) -> None:
    """``dst[...] = src`` for 1-d arrays of one length, without numba's overlap copy (which
    allocates)."""
    for a in range(src.shape[0]):
        dst[a] = src[a]


def compiled_user_step(plan: Plan) -> Any:
    """The user run's step compiled for ``plan``'s structure (as ``kernel.compiled_loop``:
    one cached step per structure)."""
    return _compiled_step(plan.structure_key())


@functools.cache
def _compiled_step(key: StructureKey) -> Any:
    ns, ds, offsets = structure_arrays(key)
    n_float = len(FLOAT_SEGMENTS)

    @loop_njit
    def step(f: np.ndarray, i: np.ndarray, rec: np.ndarray) -> None:
        """Write the commands into the held command row, run ``C_N_TICKS`` (0 or 1) live
        ticks from ``C_TICK`` (records from row ``C_STORED`` of ``rec``; both advanced), then,
        with ``C_MEASURE``, sample the controllers of the next tick on the scratch copy into
        the measured and references segments; results in ``C_N_REC``, ``C_STATUS``,
        ``C_WHERE`` and the ``t_fail`` segment."""
        c = i[i[3 * n_float]:i[3 * n_float] + N_CONTROL]
        s = i[3 * (n_float + 1):3 * (n_float + 1) + 3]
        slip = i[s[0]:s[0] + s[1] * s[2]]
        s = i[3 * (n_float + 2):3 * (n_float + 2) + 3]
        slip_s = i[s[0]:s[0] + s[1] * s[2]]
        s = i[3 * (n_float + 3):3 * (n_float + 3) + 3]
        users = i[s[0]:s[0] + s[1] * s[2]]
        s = i[3 * (n_float + 4):3 * (n_float + 4) + 3]
        prof_off = i[s[0]:s[0] + s[1] * s[2]]
        # the float segments in FLOAT_SEGMENTS order (k: its index there), sliced inline:
        # without numba's runtime (``_NO_NRT``) a helper cannot return a view
        k = 0
        x = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]]
        k = 1
        istate = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 2
        out = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 3
        stages = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 4
        refs = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 5
        work = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        live_start, scratch_start = i[0], i[3 * 6]
        size = scratch_start - live_start  # the six live segments are contiguous
        k = 12
        rec_s = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 13
        measured = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]]
        k = 14
        references = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]]
        k = 15
        commands = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]]
        k = 16
        nodes = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 17
        spans = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 18
        drives = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 19  # the plan's web table, then the sample period [s] (``packed_run``)
        web = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2] - 1]
        dt = f[i[3 * k] + i[3 * k + 1] * i[3 * k + 2] - 1]
        k = 20
        wound = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 21
        ripple = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]].reshape(
            (i[3 * k + 1], i[3 * k + 2]))
        k = 22
        prof_t = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]]
        k = 23
        prof_v = f[i[3 * k]:i[3 * k] + i[3 * k + 1] * i[3 * k + 2]]
        k = 24
        t_fail = f[i[3 * k]:i[3 * k] + 1]

        tick, n_ticks = c[C_TICK], c[C_N_TICKS]
        for u in range(users.shape[0]):
            if not math.isfinite(commands[u]):
                c[C_N_REC], c[C_STATUS], c[C_WHERE] = 0, STATUS_USER_NONFINITE, u
                t_fail[0] = tick * dt
                return
            out[U_CMD, users[u]] = commands[u]
        c[C_N_REC], c[C_STATUS], c[C_WHERE] = 0, L.STATUS_OK, -1
        for phase in range(2):  # one call site: the loop is inlined once
            if phase == 1:
                if not c[C_MEASURE] or c[C_STATUS] != L.STATUS_OK:
                    break
                _copy(f[scratch_start:scratch_start + size], f[live_start:scratch_start])
                _copy(slip_s, slip)
                # the scratch segments, in the live ones' order and shapes
                x = f[i[18]:i[18] + x.shape[0]]
                istate = f[i[21]:i[21] + istate.size].reshape(istate.shape)
                out = f[i[24]:i[24] + out.size].reshape(out.shape)
                stages = f[i[27]:i[27] + stages.size].reshape(stages.shape)
                refs = f[i[30]:i[30] + refs.size].reshape(refs.shape)
                work = f[i[33]:i[33] + work.size].reshape(work.shape)
            n_rec, status, failed_at, where = advance(
                x, istate, slip if phase == 0 else slip_s,
                rec[c[C_STORED]:] if phase == 0 else rec_s, out, stages, refs, work,
                tick + phase * n_ticks, n_ticks if phase == 0 else 0, dt, c[C_SUBSTEPS],
                c[C_EVERY], c[C_INCLUDE_END] != 0 if phase == 0 else True, ns, ds, offsets,
                nodes, spans, drives, web, wound, ripple, prof_t, prof_v, prof_off, None, None)
            if phase == 0:
                c[C_N_REC], c[C_STATUS], c[C_WHERE] = n_rec, status, where
                c[C_STORED] += n_rec
                c[C_TICK] += n_ticks
                t_fail[0] = failed_at
        if c[C_MEASURE] and c[C_STATUS] == L.STATUS_OK:
            for u in range(users.shape[0]):
                for q in range(N_MEASURED):
                    measured[N_MEASURED * u + q] = out[U_SPEED + q, users[u]]
                for q in range(N_REFERENCES):
                    references[N_REFERENCES * u + q] = out[U_VREF + q, users[u]]

    return step


def packed_run(plan: Plan, x0: np.ndarray, istate0: np.ndarray, slip0: np.ndarray,
               users: np.ndarray, record_width: int) -> Packed:
    """The packed arrays of a user run of ``plan`` from ``x0``, ``istate0``, ``slip0`` with
    user drives ``users`` (indices), its parameters copied in."""
    n_x, n_d, n_n = x0.shape[0], plan.drives.shape[0], plan.nodes.shape[0]
    n_prof = max(plan.prof_off.shape[0] - 1, n_n)
    live = {"x": (1, n_x), "istate": istate0.shape, "out": (U_ROWS, n_d), "stages": (5, n_x),
            "refs": (4, n_prof), "work": (2, 3 * n_n)}
    shapes: dict[str, tuple[tuple[int, int], type]] = {
        name: (shape, float) for name, shape in live.items()}
    shapes |= {f"{name}_s": (shape, float) for name, shape in live.items()}
    shapes |= {"rec_s": ((1, record_width), float),
               "measured": ((1, N_MEASURED * len(users)), float),
               "references": ((1, N_REFERENCES * len(users)), float),
               "commands": ((1, len(users)), float),
               "nodes": (plan.nodes.shape, float), "spans": (plan.spans.shape, float),
               "drives": (plan.drives.shape, float), "web": ((1, plan.web.shape[0] + 1), float),
               "wound_ripple": (plan.wound_ripple.shape, float),
               "speed_ripple": (plan.speed_ripple.shape, float),
               "prof_t": ((1, plan.prof_t.shape[0]), float),
               "prof_v": ((1, plan.prof_v.shape[0]), float), "t_fail": ((1, 1), float),
               "control": ((1, N_CONTROL), int), "slip": ((1, n_n), int),
               "slip_s": ((1, n_n), int), "users": ((1, len(users)), int),
               "prof_off": ((1, plan.prof_off.shape[0]), int)}
    packed = Packed.of(shapes)
    v = packed.views
    v["x"][:], v["istate"][:], v["slip"][:] = x0, istate0, slip0
    v["users"][:] = users
    for name, value in zip(("nodes", "spans", "drives", "wound_ripple", "speed_ripple",
                            "prof_t", "prof_v", "prof_off"),
                           (plan.nodes, plan.spans, plan.drives, plan.wound_ripple,
                            plan.speed_ripple, plan.prof_t, plan.prof_v, plan.prof_off),
                           strict=True):
        v[name][...] = value
    v["web"][:-1] = plan.web
    v["web"][-1] = plan.dt  # the sample period [s] rides after the web table (which the
    # step hands the loop without it: the table may end in a stress-strain law's columns)
    return packed
