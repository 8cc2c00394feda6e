"""The kernel's drive table: one row per driven node with its topology and controller."""

from __future__ import annotations

import numpy as np

from webline.control.decentralized import SectionDesign, design_section
from webline.control.pi import PIGains, tune
from webline.control.sections import SectionModel, section_models
from webline.errors import LineFileError
from webline.line import Line, is_roll
from webline.model.operating_point import OperatingPoint
from webline.sim.elements import layout as L
from webline.spec.nip import shaft_terms
from webline.spec.schema import (
    AdaptiveSpec,
    BeltSpec,
    CascadedPISpec,
    DirectSpec,
    DriveSpec,
    IdleSpec,
    MRACSpec,
    PythonControllerSpec,
    ShaftSpec,
    StateFeedbackSpec,
)

FAMILIES = {CascadedPISpec: L.FAMILY_PI, StateFeedbackSpec: L.FAMILY_STATE_FEEDBACK,
            AdaptiveSpec: L.FAMILY_ADAPTIVE, MRACSpec: L.FAMILY_MRAC,
            PythonControllerSpec: L.FAMILY_USER}


Designs = tuple[SectionDesign | None, ...]


def drive_table(line: Line, op: OperatingPoint,
                sample_rate: float) -> tuple[np.ndarray, tuple[PIGains, ...], Designs]:
    """Rows of the drive table, the PI gains and the decentralized designs of every drive.

    ``op``: the plan's operating point (t = 0, initial radii: node inertias [kg·m²], and the
    speeds and tensions the decentralized designs linearize at); ``sample_rate`` of the
    controllers [Hz]. Reference profiles are numbered as in the plan: 0 the line speed, 1 + z
    the tension of zone z.
    """
    spec = line.spec
    rows = np.zeros((len(line.drives), L.D_COLS))
    gains: list[PIGains] = []
    designs: list[SectionDesign | None] = []
    controllers = [getattr(spec.rollers[i], "controller", None) for i in line.drives]
    decentralized = any(not isinstance(c, CascadedPISpec | PythonControllerSpec)
                        for c in controllers)
    inertia = op.inertia
    models = section_models(line, op) if decentralized else None
    for d, i in enumerate(line.drives):
        roller = spec.rollers[i]
        assert not isinstance(roller, IdleSpec)
        z = line.controlled_zone(i)
        zone = line.zones[z] if z is not None else None
        row = rows[d]
        row[L.D_NODE] = i
        row[L.D_ROLE] = L.ROLE_TENSION if zone else L.ROLE_MASTER
        row[L.D_LOADCELL] = zone.loadcell if zone else -1
        row[L.D_REF] = 1 + z if z is not None else -1
        row[L.D_ZFIRST], row[L.D_ZLAST] = (zone.first, zone.last) if zone else (-1, -1)
        row[L.D_SIGMA] = (-1.0 if zone.first == i else 1.0) if zone else 0.0
        row[L.D_LIMIT] = roller.drive.torque_limit
        row[L.D_LAG] = roller.drive.torque_lag
        row[L.D_INVLAG] = 1.0 / roller.drive.torque_lag
        row[L.D_GAINNORM] = inertia[i] / (roller.drive.ratio * roller.radius)
        row[L.D_UPREF] = -1 if i == 0 else 1 + line.zone_of_span(i - 1)
        controller = roller.controller
        row[L.D_FAMILY] = FAMILIES[type(controller)]
        if isinstance(controller, CascadedPISpec | PythonControllerSpec):
            # a user drive keeps the default PI's gains: its stand-in where a linear model
            # or the integration step needs a built-in controller (sim.user_control)
            gains.append(_pi_columns(row, line, d, inertia[i], sample_rate))
            designs.append(None)
        else:
            assert models is not None
            gains.append(PIGains(0.0, 0.0, 0.0, 0.0))
            designs.append(_decentralized_columns(row, line, d, op.line_speed,
                                                  op.tension, models[d], sample_rate))
        row[L.D_ADAPTIVE] = 1.0 if is_roll(roller) and getattr(
            controller, "inertia_adaptive", True) else 0.0
        estimate = getattr(controller, "friction_estimate", None)
        row[L.D_BMODEL] = shaft_terms(roller)[1] if estimate is None else estimate  # nip too
    return rows, tuple(gains), tuple(designs)


def _pi_columns(row: np.ndarray, line: Line, d: int, inertia: float,
                sample_rate: float) -> PIGains:
    i = line.drives[d]
    roller = line.spec.rollers[i]
    c = roller.controller  # type: ignore[union-attr]
    if isinstance(c, PythonControllerSpec):
        c = CascadedPISpec()
    assert isinstance(c, CascadedPISpec)
    drive = roller.drive  # type: ignore[union-attr]
    z = line.controlled_zone(i)
    zone_length = 1.0 if z is None else sum(line.spec.spans[k].length for k in line.zones[z].spans)
    auto = tune(inertia, drive.ratio, roller.radius, zone_length, line.ea, c.speed_bandwidth,
                c.tension_bandwidth, c.damping)
    # Above a compliant transmission's resonance a motor-side speed loop sees only the motor:
    # keep that loop's crossover within what the torque lag and the sampling allow, scaling
    # kp and ki together (the PI zero stays where the tuning put it).
    seen = inertia
    if drive.transmission.type != "direct" and drive.feedback == "motor":
        seen = drive.ratio**2 * drive.motor_inertia
    limit = min(0.2 / drive.torque_lag, 2 * np.pi * sample_rate / 20)
    scale = min(1.0, limit * seen / (drive.ratio * roller.radius) / auto.speed_kp)
    has_zone = z is not None
    g = PIGains(
        speed_kp=scale * auto.speed_kp if c.speed_kp is None else c.speed_kp,
        speed_ki=scale * auto.speed_ki if c.speed_ki is None else c.speed_ki,
        tension_kp=(auto.tension_kp if c.tension_kp is None else c.tension_kp) if has_zone else 0,
        tension_ki=(auto.tension_ki if c.tension_ki is None else c.tension_ki) if has_zone else 0,
    )
    row[L.D_KPS], row[L.D_KIS] = g.speed_kp, g.speed_ki
    row[L.D_KPT], row[L.D_KIT] = g.tension_kp, g.tension_ki
    return g


def _decentralized_columns(row: np.ndarray, line: Line, d: int, line_speed: float,
                           tension: np.ndarray, model: object,
                           sample_rate: float) -> SectionDesign:
    i = line.drives[d]
    roller = line.spec.rollers[i]
    c = roller.controller  # type: ignore[union-attr]
    assert isinstance(c, StateFeedbackSpec | AdaptiveSpec | MRACSpec)
    z = line.controlled_zone(i)
    t_scale = c.tension_scale or (0.01 * tension[line.zones[z].loadcell] if z is not None else 1.0)
    v_scale = c.speed_scale or max(0.01 * abs(line_speed), 0.01)
    u_scale = c.torque_scale or 0.1 * roller.drive.torque_limit  # type: ignore[union-attr]
    # the section models leave out the torque lag and the sampling: keep the loop well inside
    max_bandwidth = min(0.2 / roller.drive.torque_lag, 2 * np.pi * sample_rate / 20)  # type: ignore[union-attr]
    design = design_section(model, t_scale, v_scale, u_scale, max_bandwidth)  # type: ignore[arg-type]
    gain = design.gain.copy()
    if c.tension_gain is not None:
        gain[0] = c.tension_gain
    if c.speed_gain is not None:
        gain[1] = c.speed_gain
    row[L.D_KT], row[L.D_KV] = gain
    if isinstance(c, AdaptiveSpec):
        row[L.D_GAMMA], row[L.D_LEAK] = c.adaptation_gain, c.leakage
        # the bound: a friction torque at the initial speed of parameter_bound x torque scale
        row[L.D_BMAX] = c.parameter_bound * u_scale / max(abs(line_speed) / roller.radius, 1.0)
    if isinstance(c, MRACSpec):
        _mrac_columns(row, c, design, t_scale, v_scale, u_scale)
    if c.tension_feedback == "observer":
        observer_columns(row, line, d, model, c.observer_bandwidth)  # type: ignore[arg-type]
        row[L.D_OBS_EA] = line.ea if c.observer_ea is None else c.observer_ea
    return design


def observer_columns(row: np.ndarray, line: Line, d: int, model: SectionModel,
                     bandwidth: float) -> None:
    """The tension observer of drive ``d`` (``sim.drives.observer``): its zone must be one span
    next
    to its roller, its drive rigid. Gains from the section model at the operating point:
    error matrix [[-v/L, -l_T], [s r/J, -β - l_ω]] (s = +1 if the roller is the span's
    upstream end; β = the model's speed damping) with both poles at -``bandwidth`` [rad/s]."""
    i = line.drives[d]
    z = line.controlled_zone(i)
    key = f"rollers[{i}].controller.tension_feedback"
    if z is None or len(line.zones[z].spans) != 1:
        raise LineFileError(line.source, key, f"roller {line.node_name(i)!r}: 'observer' needs "
                            "a zone of one span (no idle rollers)")
    if line.spec.rollers[i].drive.transmission.type != "direct":  # type: ignore[union-attr]
        raise LineFileError(line.source, key, f"roller {line.node_name(i)!r}: 'observer' needs "
                            "a rigid drive")
    k = line.zones[z].spans[0]
    # model.a in (T, V): a[0,0] = -v/L; a[1,0] = ±r/J per N in m/s²; a[1,1] = -β
    a = model.a
    radius = line.spec.rollers[i].radius
    decay, coupling, damping = -a[0, 0], a[1, 0] / radius, -a[1, 1]  # coupling: rad/s² per N
    l_w = 2.0 * bandwidth - decay - damping
    l_t = (bandwidth**2 - decay * (damping + l_w)) / coupling
    row[L.D_OBS], row[L.D_OBS_LT], row[L.D_OBS_LW] = 1.0, l_t, l_w
    row[L.D_OBS_OTHER] = k + 1 if k == i else k
    row[L.D_OBS_LENGTH] = line.spec.spans[k].length


def _mrac_columns(row: np.ndarray, c: MRACSpec, design: SectionDesign, t_scale: float,
                  v_scale: float, u_scale: float) -> None:
    """The MRAC's law in physical units from the scaled design: s = eᵀ P b = PBT e_T + PBV e_V
    (P b scaled, divided by the scales), dk̂_j/dt = γ u_s/scale_j² s x_j, d(bias)/dt = γ u_s s,
    and the projection half-widths ρ u_s/scale_j, ρ u_s."""
    scales = np.array([t_scale, v_scale])
    pb = design.pb_scaled / scales
    row[L.D_PBT], row[L.D_PBV] = pb
    row[L.D_GKT], row[L.D_GKV] = c.adaptation_gain * u_scale / scales**2
    row[L.D_GBIAS] = c.adaptation_gain * u_scale
    row[L.D_KBT], row[L.D_KBV] = c.parameter_bound * u_scale / scales
    row[L.D_CBOUND] = c.parameter_bound * u_scale
    row[L.D_GAMMA], row[L.D_LEAK] = c.adaptation_gain, c.leakage


def transmission(line: Line, i: int) -> DirectSpec | BeltSpec | ShaftSpec:
    """The transmission of the drive on node ``i``."""
    return line.spec.rollers[i].drive.transmission  # type: ignore[union-attr]


def transmission_columns(row: np.ndarray, drive: DriveSpec, state: int) -> None:
    """Fill the transmission columns of a drive row; ``state`` is the index of its (motor
    speed, twist) states or -1 for a rigid one."""
    t = drive.transmission
    row[L.D_RATIO] = drive.ratio
    row[L.D_JMOTOR] = drive.motor_inertia
    row[L.D_BMOTOR] = drive.motor_friction
    row[L.D_FEEDBACK] = 1.0 if drive.feedback == "motor" else 0.0
    row[L.D_TSTATE] = state
    row[L.D_COMPLIANT] = 0.0 if isinstance(t, DirectSpec) else 1.0
    if isinstance(t, BeltSpec):  # the tight side seen from the load shaft
        row[L.D_KTRANS] = t.stiffness * t.load_pulley_radius**2
        row[L.D_CTRANS] = t.damping * t.load_pulley_radius**2
    elif isinstance(t, ShaftSpec):
        row[L.D_KTRANS], row[L.D_CTRANS] = t.stiffness, t.damping
    if not isinstance(t, DirectSpec) and t.backlash is not None:
        row[L.D_GAPNEG] = 2.0 * t.backlash.gap * t.backlash.asymmetry
        row[L.D_GAPPOS] = 2.0 * t.backlash.gap * (1.0 - t.backlash.asymmetry)
