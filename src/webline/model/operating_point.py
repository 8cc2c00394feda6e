"""Operating point: reference speeds, tensions and equilibrium inputs of every section.

Generalises thesis (6.20, 6.22, 6.28, 6.31, 6.32, 6.36, 6.37) to N sections, idle rollers and
a different tension in each zone. From each span's tension equation (6.8) at equilibrium,
v_k (EA - T_k^up) is the same for every node, T^up being the tension of the span entering
the node (the wound-in tension for the unwind), so

    v_i = v_master · (EA - T_master^up) / (EA - T_i^up)            (6.22, 6.31, 6.36)

(exact mass conservation, ``web.transport = "exact"``: v_k/(1 + ε_k^up) is the same for every
node, v_i = v_master (EA + T_i^up)/(EA + T_master^up), ``physics.span.draw_ratio``)

and each driven node's torque balance gives its equilibrium motor torque

    n_i u_i = J_i dω_i/dt - r_i (T_i^down - T_i^up) + friction(ω_i) + n_i² b_m ω_i
                                                                    (6.20, 6.28, 6.32, 6.37)

with dω/dt = (dv/dt)/r - v (dr/dt)/r² for a roll whose radius changes (6.6). Motor torque is
positive in the web direction, so the unwind's equilibrium torque is negative (braking).
Across an idle roller the tension changes by its friction (and inertia) torque over r.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.errors import ArgumentError, SimulationError
from webline.line import Line, Zone
from webline.model.lines import load_line
from webline.model.tension_ramp import ramp_factor
from webline.physics import roll, roller
from webline.physics.span import draw_ratio
from webline.physics.taper import spec_factor
from webline.profiles import breakpoints, pwl_slope, pwl_value
from webline.spec.nip import shaft_terms
from webline.spec.ranges import argument
from webline.spec.roll_inertia import roll_constants
from webline.spec.schema import IdleSpec, RewindSpec, RollerDrag, UnwindSpec
from webline.spec.sensors import LoadcellSensor


@dataclass(frozen=True)
class OperatingPoint:
    """Equilibrium of a line at one instant of its references (SI throughout)."""

    time: float
    line_speed: float  #: master reference speed [m/s] (its encoder's reading: spec.sensors)
    tension: np.ndarray  #: per span [N]
    speed: np.ndarray  #: web speed per node [m/s]
    omega: np.ndarray  #: angular speed per node [rad/s]
    radius: np.ndarray  #: radius per node [m]
    inertia: np.ndarray  #: inertia per node at the roller shaft [kg·m²]
    accel: np.ndarray  #: angular acceleration per node [rad/s²]
    torque: np.ndarray  #: equilibrium motor torque per drive [N·m] (order of ``drives``)
    drives: tuple[int, ...]  #: node index of each drive
    span_names: tuple[str, ...]
    node_names: tuple[str, ...]

    def as_dict(self) -> dict[str, object]:
        """Plain-data view (for JSON): per-span tension, per-node speed, per-drive torque."""
        return {
            "time_s": self.time,
            "line_speed_m_per_s": self.line_speed,
            "tension_N": dict(zip(self.span_names, self.tension.tolist(), strict=True)),
            "speed_m_per_s": dict(zip(self.node_names, self.speed.tolist(), strict=True)),
            "torque_N_m": {self.node_names[i]: float(u)
                           for i, u in zip(self.drives, self.torque, strict=True)},
        }


def node_radii(line: Line, unwind_radius: float | None = None,
               rewind_radius: float | None = None) -> np.ndarray:
    """Radius of every node [m]: roll radii as given (default: initial), roller radii."""
    radii = np.array([r.radius for r in line.spec.rollers])
    if unwind_radius is not None:
        radii[0] = unwind_radius
    if rewind_radius is not None:
        radii[-1] = rewind_radius
    return radii


def node_inertias(line: Line, radii: np.ndarray) -> np.ndarray:
    """Inertia of every node at its shaft [kg·m²], rolls with their web (6.1, 6.2), rollers
    with a nip's pressure roller reflected (docs/winder.md, Nip)."""
    web = line.spec.web
    out = np.empty(line.n_nodes)
    for i, r in enumerate(line.spec.rollers):
        if isinstance(r, UnwindSpec | RewindSpec):  # totals: spec.roll_inertia (J1)
            core, density = roll_constants(r, web)
            constant = core + r.drive.ratio**2 * r.drive.motor_inertia
            out[i] = roll.roll_inertia(constant, radii[i], r.core_radius, web.width, density)
            continue
        constant = shaft_terms(r)[0]
        if not isinstance(r, IdleSpec):
            constant += r.drive.ratio**2 * r.drive.motor_inertia
        out[i] = constant
    return out


def operating_point(line: Line | str, t: float | str = 0.0, *,
                    unwind_radius: float | str | None = None,
                    rewind_radius: float | str | None = None) -> OperatingPoint:
    """Equilibrium of ``line`` for its references at time ``t`` [s], rolls at the given radii
    [m] (default: initial radii). Accounts for a ramping line speed (inertial torque).
    ``t`` and the radii take numbers [SI], strings with units (``"1 s"``) or pint quantities.
    A branched line is refused in one line (``ArgumentError``): its operating point is in
    ``webline analyze`` and ``webline.linearize`` (docs/branching.md, "Linear models")."""
    loaded = load_line(line)
    if loaded.branched:
        raise ArgumentError(f"line: operating_point of {loaded.name!r}: not yet supported for a "
                            "branched line ([[webs]]); its operating point is in 'webline "
                            "analyze' and webline.linearize (docs/branching.md)")
    line = loaded
    t = argument(t, "time", "t", ">=0")
    unwind_radius, rewind_radius = (None if r is None else argument(r, "length", name)
                                    for r, name in ((unwind_radius, "unwind_radius"),
                                                    (rewind_radius, "rewind_radius")))
    return solve_operating_point(line, operating_inputs(line, t, unwind_radius, rewind_radius))


@dataclass(frozen=True)
class OperatingInputs:
    """What the operating point of a line at time ``time`` [s] takes from its references,
    rolls and rollers before the equilibrium is solved (``operating_inputs``): none of it
    reads the web's EA, its thickness, the wound-in tension or the rollers' friction, so a
    study case that changes only those solves its operating point from its base line's
    inputs (``solve_operating_point``; ``sim.core.plan_patch``)."""

    time: float
    v_line: float  #: master reference speed [m/s]
    a_line: float  #: its rate of change [m/s²]
    radii: np.ndarray  #: radius per node [m]
    inertia: np.ndarray  #: inertia per node [kg·m²]
    drags: np.ndarray  #: drag torque per node [N·m]
    tension: tuple[float, ...]  #: zone references per span (the loadcells' readings) [N]
    scale: float  #: the master encoder's scale [1]


def operating_inputs(line: Line, t: float, unwind_radius: float | None = None,
                     rewind_radius: float | None = None) -> OperatingInputs:
    """The ``OperatingInputs`` of ``line`` at time ``t`` [s], rolls at the given radii [m]
    (None: initial)."""
    speed_t, speed_v = breakpoints(line.spec.speed)
    v_line = pwl_value(speed_t, speed_v, t)
    a_line = pwl_slope(speed_t, speed_v, t)
    radii = node_radii(line, unwind_radius, rewind_radius)
    inertia = node_inertias(line, radii)
    drags = drag_torques(line, t)
    tension = np.empty(line.n_spans)
    for zone in line.zones:
        ref = line.spec.spans[zone.loadcell].tension
        tension[list(zone.spans)] = pwl_value(*breakpoints(ref), t) * _taper(line, zone, radii)
    if line.spec.control.tension_ramp is not None:  # the ramp at start and stop (R1)
        tension *= ramp_factor(line, t)
    scale = 1.0  # the master's encoder: its loop holds the reading on the line reference
    for sensor in line.spec.sensors:  # a loop holds its loadcell's reading on the reference
        if isinstance(sensor, LoadcellSensor):
            k = next(k for k in range(line.n_spans) if line.span_name(k) == sensor.span)
            tension[k] = (tension[k] - sensor.offset) / sensor.gain
        elif sensor.roller == line.node_name(line.master):
            scale = sensor.scale
    return OperatingInputs(t, v_line, a_line, radii, inertia, drags, tuple(tension.tolist()),
                           scale)


def solve_operating_point(line: Line, inputs: OperatingInputs) -> OperatingPoint:
    """The operating point of ``line`` from its ``inputs`` (``operating_inputs`` of ``line``,
    or of a line that differs from it only where ``OperatingInputs`` does not read):
    the equilibrium motion (6.22) and each drive's equilibrium torque (6.20)."""
    t, radii, inertia, drags = inputs.time, inputs.radii, inputs.inertia, inputs.drags
    v_line, a_line, scale = inputs.v_line, inputs.a_line, inputs.scale
    rollers = line.spec.rollers
    tension_l, speed_l, omega_l, accel_l = _equilibrium_motion(
        line, list(inputs.tension), v_line / scale, a_line / scale, radii, inertia, drags)
    tension, speed = np.array(tension_l), np.array(speed_l)
    omega, accel = np.array(omega_l), np.array(accel_l)
    if np.any(tension <= 0.0):
        k = int(np.argmin(tension))
        raise SimulationError(f"no equilibrium: idle-roller friction leaves span "
                              f"{line.span_name(k)} with tension {tension[k]:.3g} N <= 0")

    torque = np.empty(len(line.drives))
    j, r_node, drag = inertia.tolist(), radii.tolist(), drags.tolist()  # floats: see above
    for d, i in enumerate(line.drives):
        r = rollers[i]
        assert not isinstance(r, IdleSpec)
        t_out = tension_l[i] if i < line.n_spans else 0.0
        t_in = tension_l[i - 1] if i > 0 else 0.0
        _, viscous, coulomb = shaft_terms(r)  # a nip's bearing included
        friction = roller.friction_torque(omega_l[i], viscous, coulomb)
        friction += roller.friction_torque(omega_l[i], 0.0, drag[i])  # brake (4.12) or drag
        if r.friction_table is not None:  # measured against speed (docs/winder.md F1)
            friction += roller.table_friction(omega_l[i], *r.friction_table.arrays())[0]
        n = r.drive.ratio  # the motor's own friction acts at n ω
        torque[d] = (j[i] * accel_l[i] - r_node[i] * (t_out - t_in) + friction) / n + (
            r.drive.motor_friction * n * omega_l[i])
    return OperatingPoint(
        time=t, line_speed=v_line, tension=tension, speed=speed, omega=omega,
        radius=radii.copy(), inertia=inertia.copy(), accel=accel, torque=torque,
        drives=line.drives,
        span_names=tuple(line.span_name(k) for k in range(line.n_spans)),
        node_names=tuple(line.node_name(i) for i in range(line.n_nodes)),
    )


def _equilibrium_motion(line: Line, tension: list[float], v_line: float, a_line: float,
                        radii: np.ndarray, inertia: np.ndarray, drags: np.ndarray,
                        ) -> tuple[list[float], list[float], list[float], list[float]]:
    """(tension [N] per span, web speed [m/s], ω [rad/s] and dω/dt [rad/s²] per node) at
    equilibrium, from the zones' reference ``tension`` (loadcell spans right, the others a
    first guess): speeds from mass flow (6.22), the idle rollers' tension drops from those
    speeds, repeated until the tensions stop changing. Plain floats: every sweep case's plan
    runs this on a handful of nodes, where numpy's per-call overhead was most of the cost."""
    ea, t0, master = line.ea, line.unwind.wound_in_tension, line.master
    v_line, a_line = float(v_line), float(a_line)
    thickness = line.spec.web.thickness
    r, j, drag = radii.tolist(), inertia.tolist(), drags.tolist()
    friction = [shaft_terms(roller)[1:] for roller in line.spec.rollers]  # a nip's included
    tables = [None if r_.friction_table is None else r_.friction_table.arrays()
              for r_ in line.spec.rollers]
    last = line.n_nodes - 1

    def idle_drop(i: int) -> float:  # tension rise across idle roller i: (J dω/dt + f)/r
        viscous, coulomb = friction[i]
        torque = roller.friction_torque(omega[i], viscous, coulomb + drag[i])
        table = tables[i]
        if table is not None:  # measured against speed (docs/winder.md F1)
            torque += roller.table_friction(omega[i], *table)[0]
        return (j[i] * accel[i] + torque) / r[i]

    for _ in range(50):
        upstream = [t0, *tension]
        if line.nonlinear:  # mass flow carries strain: the stretch EA·ε of each tension
            upstream = [line.stretch_of(up) for up in upstream]
        ratio = [draw_ratio(ea, up, upstream[master], line.exact) for up in upstream]
        speed = [v_line * q for q in ratio]
        omega = [v / r_i for v, r_i in zip(speed, r, strict=True)]
        accel = [a_line * q / r_i for q, r_i in zip(ratio, r, strict=True)]
        for i, direction in ((0, -1.0), (last, 1.0)):
            r_dot = roll.radius_rate(speed[i], r[i], thickness, direction)
            accel[i] -= speed[i] * r_dot / r[i] ** 2
        previous = list(tension)
        for zone in line.zones:
            for i in range(zone.loadcell + 1, zone.last):  # idle rollers downstream of loadcell
                tension[i] = tension[i - 1] + idle_drop(i)
            for i in range(zone.loadcell, zone.first, -1):  # and upstream of it
                tension[i - 1] = tension[i] - idle_drop(i)
        if all(abs(a - b) <= 1e-15 * abs(b) for a, b in zip(tension, previous, strict=True)):
            break
    return tension, speed, omega, accel


def drag_torques(line: Line, t: float) -> np.ndarray:
    """Torque [N·m] opposing each roller's rotation at time ``t`` [s]: drive brakes (4.12) and
    ``roller_drag`` disturbances."""
    out = np.zeros(line.n_nodes)
    for i, r in enumerate(line.spec.rollers):
        brake = getattr(getattr(r, "drive", None), "brake", None)
        if brake is not None:
            out[i] = pwl_value(*breakpoints(brake), t)
    for d in line.spec.disturbances:
        if isinstance(d, RollerDrag):
            i = next(k for k, r in enumerate(line.spec.rollers) if r.name == d.roller)
            out[i] = pwl_value(*breakpoints(d.torque), t)
    return out


def analysis_time(line: Line) -> float:
    """Time [s] at which to analyse ``line``: 0, or for a start from rest the end of the
    speed ramp (a line standing still has no web-transport dynamics to speak of)."""
    times, values = breakpoints(line.spec.speed)
    if values[0] > 0.01 * float(np.max(values)):
        return 0.0
    return float(times[-1])


def _taper(line: Line, zone: Zone, radii: np.ndarray) -> float:
    """Taper factor on the reference of ``zone`` (docs/winder.md): the rewind's, if it
    controls the zone, at its radius."""
    rewind = line.rewind
    if zone.controller != line.n_nodes - 1 or rewind.taper is None:
        return 1.0
    return spec_factor(rewind.taper, rewind.core_radius, radii[-1])
