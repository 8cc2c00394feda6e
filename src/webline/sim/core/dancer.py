"""Dancers in the compiled plan (docs/winder.md): node columns, the zone drive's columns,
the equilibrium position and the linear model's rows.

A dancer node i carries two states, its carriage position y [m] and velocity [m/s]; the two
spans it joins are ``length + (y - position)`` long. The kernel's equations are in
``webline.sim.core.kernel.rhs`` (span lengthening) and ``sim.elements.dancer_loop`` (span lengths,
force
balance); the linear model's rows are in ``sim.linear.dancer_linear``.
"""

from __future__ import annotations

import numpy as np

from webline.control.zone_tuning import (
    KP_SPANS,
    loop_plant_gain,
    nominal_plant_gain,
    tension_gains,
    zone_damper,
    zone_dancers,
)
from webline.line import Line
from webline.physics.taper import spec_factor
from webline.profiles import breakpoints
from webline.sim.elements import layout as L
from webline.spec.dancer import DancerCarriage
from webline.spec.schema import CascadedPISpec, DancerSpec

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
    """Point each zone drive whose zone has a dancer in use at it, and design its tension loop
    for the zone's real stiffness (docs/winder.md Z1-Z4, ``control.zone_tuning``): a
    position loop's gains are the tension loop's scaled by EA / L_zone over G (Z2; the file's
    tension gains so scaled too, unless it gives the position gains); a tension loop (dancer
    as sensor, or a loadcell beside a sprung dancer) is placed on K_e = 1/C and, for the
    loadcell, the dancer's damper (Z4), where the file leaves its gains out."""
    drives[:, L.D_DANCER] = -1
    for z, zone in enumerate(line.zones):
        if not zone_dancers(line, z):
            continue
        d = line.drives.index(zone.controller)
        controller = getattr(line.spec.rollers[zone.controller], "controller", None)
        if not isinstance(controller, CascadedPISpec):
            _point_at_dancer(drives, line, z, d)
            continue
        _, plant = loop_plant_gain(line, z)
        position = _point_at_dancer(drives, line, z, d)
        if position is not None:
            scale = nominal_plant_gain(line, z) / plant
            c = _carriage(line, position)
            drives[d, L.D_KPT] = scale * drives[d, L.D_KPT] if c.position_kp is None else (
                c.position_kp)
            drives[d, L.D_KIT] = scale * drives[d, L.D_KIT] if c.position_ki is None else (
                c.position_ki)
            continue
        if plant == 0.0:
            continue  # an air-loaded dancer sets the tension: nothing to design (validate)
        bandwidth, damping = controller.tension_bandwidth, controller.damping
        if drives[d, L.D_DANCER] < 0:  # a loadcell: it feels the damper and, fast, the spans
            kp, ki = tension_gains(plant, zone_damper(line, z), bandwidth, damping,
                                   KP_SPANS * 2.0 * damping * bandwidth
                                   / nominal_plant_gain(line, z))
        else:  # the dancer as tension sensor: its spring's force
            kp, ki = tension_gains(plant, 0.0, bandwidth, damping)
        if controller.tension_kp is None:
            drives[d, L.D_KPT] = kp
        if controller.tension_ki is None:
            drives[d, L.D_KIT] = ki


def _point_at_dancer(drives: np.ndarray, line: Line, z: int, d: int) -> int | None:
    """Point drive ``d`` at the dancer of zone ``z`` its loop reads (position control or
    tension sensor); the node of a position-controlled one, else None."""
    for i in zone_dancers(line, z):
        c = _carriage(line, i)
        if c.use == "none":
            continue
        drives[d, L.D_DANCER] = i
        if c.use == "tension":
            drives[d, L.D_DUSE] = L.DANCER_TENSION
            return None
        drives[d, L.D_DUSE] = L.DANCER_POSITION
        return i
    return None


def load_taper(line: Line, drives: np.ndarray, i: int, radius: float) -> float:
    """Factor [-] on the load of the dancer on node ``i`` at the controller's roll radius
    ``radius`` [m] (``sim.drives.dancer_taper.load_factor``, in Python): the rewind's taper where
    its drive runs this dancer in position control, else 1."""
    d = line.drives.index(line.n_nodes - 1)
    rewind = line.rewind
    if (drives[d, L.D_DANCER] != i or drives[d, L.D_DUSE] != L.DANCER_POSITION
            or drives[d, L.D_TAPER] <= 0.0 or rewind.taper is None):
        return 1.0
    return spec_factor(rewind.taper, rewind.core_radius, radius)


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

