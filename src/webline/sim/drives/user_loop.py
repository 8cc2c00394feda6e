"""The compiled side of a user's controller (``sim.user_control``): the loop runs one tick at a
time and a Python object computes the command of each user drive in between.

A user drive has the family ``layout.FAMILY_USER``. At its tick ``control_tick`` measures it as
it measures a built-in drive (the same noise, resolution, calculated radius, dancer reading,
frozen tension loop after a detected break) and calls ``user_command``, which stores those
measurements and references in extra rows of the command array ``out`` and issues the command
the Python side wrote there, saturated at the drive's torque limit; the drive's own functions
(a centre winder's compensation, torque off after a break) act on it as on a built-in
command, and the torque lag and zero-order hold follow in the plant.

``sim.core.user_step`` advances the live arrays one tick (``kernel.advance``) and then runs
the next tick's controller sample on a scratch copy of them, which yields exactly the
measurements the live tick will take (measurement noise is a function of seed, tick and
channel; the calculated radius, break monitor and splices are deterministic), so that Python
can compute the command before that tick. ``out`` rows beyond the kernel's four (``U_*``)
exist only in a user run: a built-in line's loop folds the user branch away.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics import motor
from webline.sim.drives.feedforward import speed_feedforward
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit

_saturate: Any = jit(motor.saturate)

#: rows of ``out`` in a user run: the command Python wrote [N·m]; the drive's measured surface
#: speed [m/s], measured tension [N] (NaN without a loadcell), radius its controller uses [m],
#: inertia at its roller from that radius [kg·m²]; its speed and tension references [m/s, N];
#: with compiled laws, the compensation added to the law's command [N·m] (NaN: held, W8)
U_CMD, U_SPEED, U_TENSION, U_RADIUS, U_INERTIA, U_VREF, U_TREF, U_COMP = range(4, 12)
U_ROWS = 12
#: measurements and references per user drive, in ``U_*`` order from ``U_SPEED``
N_MEASURED, N_REFERENCES = 4, 2
#: status of a step whose user command is not finite (the kernel's are >= 0)
STATUS_USER_NONFINITE = -2


@jit
def user_command(d: int, t: float, v_meas: float, t_meas: float, radius: float,
                 inertia: float, ds: np.ndarray, offsets: np.ndarray, drives: np.ndarray,
                 web: np.ndarray, refs: np.ndarray, speed_ripple: np.ndarray,
                 out: np.ndarray) -> None:
    """Store what user drive ``d`` measured at time ``t`` [s] (module docstring) and issue
    its held command, saturated at the torque limit. Its speed reference [m/s] is the cascaded
    PI's feedforward (``controllers.pi_command``): line speed x draw + speed ripple."""
    ref = speed_feedforward(d, t, ds, offsets, web, refs, speed_ripple)
    tension_role = ds[d, L.DS_ROLE] == L.ROLE_TENSION
    out[U_SPEED, d] = v_meas
    out[U_TENSION, d] = t_meas if tension_role else math.nan
    out[U_RADIUS, d] = radius
    out[U_INERTIA, d] = inertia
    out[U_VREF, d] = ref
    out[U_TREF, d] = refs[ds[d, L.DS_REF]] if tension_role else math.nan
    out[0, d] = _saturate(out[U_CMD, d], drives[d, L.D_LIMIT])
    out[1, d] = ref
    out[2, d] = 0.0
    out[3, d] = 0.0


@jit
def user_law_commands(ds: np.ndarray, drives: np.ndarray, out: np.ndarray) -> None:
    """Issue the commands compiled laws wrote into ``out[U_CMD]`` (``controllers.control_tick``
    calls them after measuring every drive): saturated, the compensation added as
    ``control_tick`` adds it to any command; a held drive (``U_COMP`` NaN) keeps its hold."""
    for d in range(ds.shape[0]):
        if ds[d, L.DS_FAMILY] == L.FAMILY_USER and not math.isnan(out[U_COMP, d]):
            out[0, d] = _saturate(out[U_CMD, d], drives[d, L.D_LIMIT])
            if out[U_COMP, d] != 0.0:
                out[0, d] = _saturate(out[0, d] + out[U_COMP, d], drives[d, L.D_LIMIT])


@jit
def user_nonfinite(ds: np.ndarray, out: np.ndarray) -> int:
    """The first user drive whose law command ``out[U_CMD]`` is not finite, else -1."""
    for d in range(ds.shape[0]):
        if ds[d, L.DS_FAMILY] == L.FAMILY_USER and not math.isfinite(out[U_CMD, d]):
            return d
    return -1
