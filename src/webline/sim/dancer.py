"""Dancers in the compiled plan (docs/winder.md): node columns, the zone drive's columns,
the equilibrium position and the linear model's rows.

A dancer node i carries two states, its carriage position y [m] and velocity [m/s]; the two
spans it joins are ``length + (y - position)`` long. The kernel's equations are in
``webline.sim.kernel.rhs`` (span lengthening) and ``sim.dancer_loop`` (span lengths, force
balance); the linear model's rows are in ``sim.dancer_linear``.
"""

from __future__ import annotations

import numpy as np

from webline.line import Line
from webline.profiles import breakpoints
from webline.sim import layout as L
from webline.spec.dancer import DancerCarriage
from webline.spec.schema import DancerSpec

#: damping ratio of an end stop while the carriage presses on it: a rubber buffer, which
#: stops the carriage without bouncing it back at full speed
STOP_DAMPING_RATIO = 0.7


def dancer_nodes(line: Line) -> list[int]:
    """Indices of the dancer rollers of ``line``, in web order."""
    return [i for i, r in enumerate(line.spec.rollers) if isinstance(r, DancerSpec)]


def dancer_zone(line: Line, i: int) -> int:
    """The tension zone whose spans the dancer on node ``i`` joins."""
    return next(z for z, zone in enumerate(line.zones) if zone.first < i < zone.last)


def load_profile(line: Line, i: int) -> tuple[np.ndarray, np.ndarray]:
    """Breakpoints of the load [N] on the dancer on node ``i``: as given, or twice its zone's
    tension reference (the set position is then an equilibrium)."""
    carriage = _carriage(line, i)
    if carriage.load is not None:
        return breakpoints(carriage.load)
    zone = line.zones[dancer_zone(line, i)]
    t, v = breakpoints(line.spec.spans[zone.loadcell].tension)
    g_in, g_out = carriage.gains
    return t, (g_in + g_out) * v


def node_columns(row: np.ndarray, line: Line, i: int, state: int, profile: int) -> None:
    """Fill the dancer columns of node ``i``'s row: its position state index ``state`` and
    the index ``profile`` of its load profile."""
    c = _carriage(line, i)
    mass = c.moving_mass
    row[L.N_DANCER] = state
    row[L.N_DINVM] = 1.0 / mass
    row[L.N_DK], row[L.N_DC] = c.stiffness, c.damping
    row[L.N_DSET], row[L.N_DTRAVEL] = c.position, c.travel
    row[L.N_DSTOP] = c.stop_stiffness
    row[L.N_DSTOPC] = 2.0 * STOP_DAMPING_RATIO * np.sqrt(c.stop_stiffness * mass)
    row[L.N_DLOAD] = profile
    row[L.N_DGIN], row[L.N_DGOUT] = c.gains
    row[L.N_DGEOM] = 0.0 if c.gains == (1.0, 1.0) else 1.0


def drive_columns(drives: np.ndarray, line: Line) -> None:
    """Point each zone drive whose zone has a dancer in use at it; a position loop gets the
    zone's tension gains scaled by 2 EA / (zone length), the ratio between the rates of the
    two errors (d(T_ref - T)/dt = EA/L_zone (v_in - v_out), d(y - y_set)/dt = (v_in - v_out)/2),
    so that both loops close at the same bandwidth, unless the file gives the gains."""
    drives[:, L.D_DANCER] = -1
    for i in dancer_nodes(line):
        c = _carriage(line, i)
        if c.use == "none":
            continue
        zone = line.zones[dancer_zone(line, i)]
        d = line.drives.index(zone.controller)
        drives[d, L.D_DANCER] = i
        if c.use == "tension":
            drives[d, L.D_DUSE] = L.DANCER_TENSION
            continue
        drives[d, L.D_DUSE] = L.DANCER_POSITION
        g_in, g_out = c.gains  # y moves by (v_in - v_out) / (g_in + g_out)
        scale = (g_in + g_out) * line.ea / sum(line.spec.spans[k].length for k in zone.spans)
        drives[d, L.D_KPT] = scale * drives[d, L.D_KPT] if c.position_kp is None else (
            c.position_kp)
        drives[d, L.D_KIT] = scale * drives[d, L.D_KIT] if c.position_ki is None else (
            c.position_ki)


def equilibrium_position(line: Line, i: int, tension_in: float, tension_out: float,
                         load: float) -> float:
    """Carriage position [m] where the load ``load`` [N] balances the spans' tensions [N]
    and the spring; the set position where there is no spring (a position loop holds it)."""
    c = _carriage(line, i)
    if c.stiffness == 0.0:
        return c.position
    g_in, g_out = c.gains
    return c.position + (load - g_in * tension_in - g_out * tension_out) / c.stiffness


def _carriage(line: Line, i: int) -> DancerCarriage:
    roller = line.spec.rollers[i]
    assert isinstance(roller, DancerSpec)
    return roller.dancer

