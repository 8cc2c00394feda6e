"""The compiled side of a user's Python controller on a branched line (docs/controllers.md,
"On a branched line"; the Python side is ``sim.branches.user``).

A drive of family ``FAMILY_USER`` is measured at its tick exactly as the cascaded PI measures
it (``loop.control``: encoder, noise and resolution, calculated radius, loadcells or dancer),
and ``user_command`` stores those readings in the drive's memory row (``layout`` I_U*) and
issues the command the Python side wrote there (``I_UCMD``), saturated, plus a centre
winder's compensation as on a built-in command. A line without user drives never reaches it:
``DI_FAMILY`` is frozen into the compiled loop.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics import motor, span
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.dancer import position_error
from webline.sim.elements.signals import gaussian, jit, profile_at

_tension: Any = jit(span.tension)
_saturate: Any = jit(motor.saturate)


@jit
def user_command(d: int, t: float, tick: int, v_meas: float, radius: float, inertia: float,
                 speed_ref: float, factor: float, frozen: bool, comp: float, x: np.ndarray,
                 istate: np.ndarray, nodes: np.ndarray, di: np.ndarray, df: np.ndarray,
                 cells: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                 prof_off: np.ndarray, sigma_t: float, seed: int, noisy: bool) -> float:
    """Store user drive ``d``'s readings at tick ``tick`` (time ``t`` [s]) and return its
    torque command [N·m]: the held ``I_UCMD`` saturated at the torque limit, plus ``comp``
    (a centre winder's compensation, saturated again). Its zone's tension is the sum of its
    loadcells (a shaft of lanes: one per lane), with the same noise draws as the built-in
    loop; its reference the sum of theirs times the taper ``factor``; a dancer in position
    control reads reference - (y - y_set), so that reference - reading is the position error
    [m] the built-in loop uses; ``frozen`` (after a detected break, W5): the tension reads its
    reference."""
    tension, reference = 0.0, 0.0
    for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
        ref = factor * profile_at(cells[c, 1], t, prof_t, prof_v, prof_off)
        reference += ref
        if cells.shape[1] > B.CELL_DANCER and cells[c, B.CELL_DANCER] >= 0:
            tension += ref - position_error(cells[c, B.CELL_DANCER], x, nodes)
            continue
        measured = _tension(x[cells[c, 0]])
        if noisy:
            measured += sigma_t * gaussian(seed, tick, 2 * c + 1)
        tension += measured
    if di[d, B.DI_NCELLS] == 0:
        tension, reference = math.nan, math.nan
    elif frozen:
        tension = reference
    istate[d, B.I_USPEED] = v_meas
    istate[d, B.I_UTENSION] = tension
    istate[d, B.I_URADIUS] = radius
    istate[d, B.I_UINERTIA] = inertia
    istate[d, B.I_UVREF] = speed_ref
    istate[d, B.I_UTREF] = reference
    u = _saturate(istate[d, B.I_UCMD], df[d, B.D_LIMIT])
    return u if comp == 0.0 else _saturate(u + comp, df[d, B.D_LIMIT])
