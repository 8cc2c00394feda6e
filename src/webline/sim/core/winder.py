"""Winder functions in the compiled plan (docs/winder.md): taper, diameter calculator,
compensation and web-break columns."""

from __future__ import annotations

import math

import numpy as np

from webline.line import Line
from webline.physics.roller import table_magnitude
from webline.physics.taper import KINDS
from webline.sim.elements import layout as L
from webline.spec.winder import WebBreak

HOLDS = {"off": L.HOLD_OFF, "zero_speed": L.HOLD_ZERO_SPEED, "brakes": L.HOLD_BRAKES,
         "stall_tension": L.HOLD_STALL}


def taper_profiles(line: Line) -> list[tuple[np.ndarray, np.ndarray]]:
    """The rewind's taper table as a profile over diameter [m] (none for other tapers)."""
    taper = line.rewind.taper
    if taper is None or taper.type != "table":
        return []
    return [(np.array(taper.diameter, dtype=float), np.array(taper.factor, dtype=float))]


def taper_columns(drives: np.ndarray, line: Line, profile: int) -> None:
    """Fill the taper columns of the rewind's drive row (if it controls a zone and has a
    taper); ``profile``: the index of its table's profile (``taper_profiles``)."""
    rewind = line.rewind
    last = line.n_nodes - 1
    if rewind.taper is None or line.controlled_zone(last) is None:
        return
    row = drives[line.drives.index(last)]
    row[L.D_TAPER] = KINDS[rewind.taper.type]
    row[L.D_TAPERK] = rewind.taper.taper
    row[L.D_TAPERDC] = 2.0 * rewind.core_radius
    d_max = rewind.taper.max_diameter
    row[L.D_TAPERDM] = math.inf if d_max is None else d_max
    row[L.D_TAPERP] = profile


def diameter_columns(drives: np.ndarray, line: Line) -> None:
    """Fill the diameter-calculator columns of the roll drives that have one."""
    for i in (0, line.n_nodes - 1):
        spec = line.spec.rollers[i].diameter  # type: ignore[union-attr]
        if spec is None:
            continue
        row = drives[line.drives.index(i)]
        row[L.D_DCALC] = (L.DCALC_SPEED_RATIO if spec.method == "speed_ratio"
                          else L.DCALC_THICKNESS)
        row[L.D_DFILTER] = spec.filter
        row[L.D_DRATE] = math.inf if spec.rate_limit is None else spec.rate_limit
        row[L.D_DHOLD] = spec.hold_below
        row[L.D_DINIT] = 0.0 if spec.initial == "measured" else float(spec.initial)
        sources = {"master": L.DSOURCE_MASTER, "reference": L.DSOURCE_REFERENCE}
        row[L.D_DSOURCE] = sources.get(spec.line_speed, next(
            (j for j, r in enumerate(line.spec.rollers) if r.name == spec.line_speed), -1))
        row[L.D_PRESETN] = len(spec.preset)
        for k, preset in enumerate(spec.preset):
            row[L.D_PRESETT + k] = preset.at
            row[L.D_PRESETD + k] = 0.0 if preset.diameter == "measured" else preset.diameter


def initial_radius(drives: np.ndarray, d: int, true_radius: float) -> float:
    """The radius [m] drive ``d``'s controller starts from: the calculator's guess, else the
    true radius."""
    guess = drives[d, L.D_DINIT]
    return guess / 2.0 if drives[d, L.D_DCALC] > 0 and guess > 0 else true_radius


def compensation_columns(drives: np.ndarray, line: Line) -> None:
    """Fill the compensation columns of the roll drives with a ``winder`` table; an open-loop
    one becomes the family ``FAMILY_OPEN_LOOP`` (if it controls a zone)."""
    for i in (0, line.n_nodes - 1):
        spec = line.spec.rollers[i].winder  # type: ignore[union-attr]
        if spec is None:
            continue
        row = drives[line.drives.index(i)]
        row[L.D_COMPJ] = 1.0 if spec.inertia_compensation else 0.0
        row[L.D_COMPCS], row[L.D_COMPB] = spec.static_friction, spec.viscous_friction
        if spec.mode == "open_loop" and line.controlled_zone(i) is not None:
            row[L.D_FAMILY] = L.FAMILY_OPEN_LOOP
            row[L.D_SPEEDLIM] = spec.speed_limit_offset * top_speed(line)


def top_speed(line: Line) -> float:
    """The line's top speed [m/s]: the largest magnitude of its speed reference's values."""
    from webline.profiles import breakpoints

    return float(np.abs(breakpoints(line.spec.speed)[1]).max())


def compensation_torque(row: np.ndarray, inertia: float, radius: float, omega: float,
                        a_line: float) -> float:
    """Motor torque [N·m] of a drive's compensations (``sim.drives.winder_loop.compensation``, the
    same formula) at shaft inertia ``inertia`` [kg·m²], radius [m], speed [rad/s] and line
    acceleration [m/s²]."""
    torque = row[L.D_COMPJ] * inertia * a_line / radius
    torque += row[L.D_COMPCS] * float(np.sign(omega)) + row[L.D_COMPB] * omega
    n = int(row[L.D_COMPFN])
    if n > 0 and omega != 0.0:  # the measured friction table (F1)
        torque += float(np.sign(omega)) * table_magnitude(
            abs(omega), row[L.D_COMPFW:L.D_COMPFW + n], row[L.D_COMPFT:L.D_COMPFT + n])
    return float(torque / row[L.D_RATIO])


def linear_rows(row: np.ndarray, direction: float, radius: float, omega_state: int,
                ref: int, kx: np.ndarray, kr: np.ndarray) -> bool:
    """Add a roll drive's viscous compensation b ω / n to its row ``kx`` of the linear
    controller (static friction and the line acceleration are constant at an equilibrium)
    and, for open-loop tension control, ±R/n on its reference ``ref`` in ``kr``; True if the
    drive is open-loop (its row is then complete)."""
    kx[omega_state] += row[L.D_COMPB] / row[L.D_RATIO]
    if row[L.D_FAMILY] != L.FAMILY_OPEN_LOOP:
        return False
    kr[ref] += direction * radius / row[L.D_RATIO]
    return True


def break_columns(line: Line, spans: np.ndarray, web: np.ndarray) -> bool:
    """Mark the time each span breaks (every span of a broken span's zone) and the monitor's
    settings; True if the web breaks in this run."""
    spans[:, L.S_BREAK] = math.inf
    breaks = [d for d in line.spec.disturbances if isinstance(d, WebBreak)]
    names = [line.span_name(k) for k in range(line.n_spans)]
    for b in breaks:
        zone = line.zones[line.zone_of_span(names.index(b.span))]
        for k in zone.spans:
            spans[k, L.S_BREAK] = min(spans[k, L.S_BREAK], b.at)
        web[L.W_BTHRESH], web[L.W_BSTOP] = b.threshold, b.stop_time
        web[L.W_BDIAM] = b.diameter_threshold
        web[L.W_BOVER] = 1.0 if b.overspeed else 0.0
        web[L.W_BHOLD] = HOLDS[b.hold]
        web[L.W_BSTALL], web[L.W_BBRAKE] = b.standstill_tension, b.brake_torque_fraction
    return bool(breaks)


def tension_references(line: Line, time: np.ndarray, control_radius: np.ndarray) -> np.ndarray:
    """Set tension of each loadcell span [N] at ``time`` [s] (NaN on spans without one): its
    zone's profile times the tension ramp at start and stop (docs/winder.md R1), the rewind's
    taper applied at the radius its controller uses (``control_radius`` [m], records x
    drives: calculated or true), as the controller sets it (``Result.tension_ref``)."""
    from webline.model.tension_ramp import ramp_factor
    from webline.physics.taper import spec_factor
    from webline.profiles import breakpoints

    out = np.full((len(time), line.n_spans), np.nan)
    for zone in line.zones:
        times, values = breakpoints(line.spec.spans[zone.loadcell].tension)
        out[:, zone.loadcell] = np.interp(time, times, values)
    if line.spec.control.tension_ramp is not None:
        out *= np.asarray(ramp_factor(line, time))[:, None]
    rewind = line.rewind
    z = line.controlled_zone(line.n_nodes - 1)
    if rewind.taper is not None and z is not None:
        d = line.drives.index(line.n_nodes - 1)
        out[:, line.zones[z].loadcell] *= [spec_factor(rewind.taper, rewind.core_radius, r)
                                           for r in control_radius[:, d]]
    return out
