"""Compile a ``Line`` into the flat arrays the numba kernel runs on."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from webline.control.decentralized import SectionDesign
from webline.control.pi import PIGains
from webline.line import Line
from webline.model.operating_point import OperatingPoint, operating_point
from webline.model.tension_ramp import ramp_profile
from webline.physics.span import draw_ratio
from webline.profiles import breakpoints, pwl_slope, pwl_value
from webline.sim.core import dancer as dancers
from webline.sim.core import winder
from webline.sim.core.drive_table import (
    Designs,
    drive_table,
    transmission,
    transmission_columns,
)
from webline.sim.elements import layout as L
from webline.sim.elements import splice
from webline.sim.elements.friction_loop import friction_columns
from webline.sim.elements.sensor_loop import fill_delays, sensor_columns
from webline.spec.nip import shaft_terms
from webline.spec.roll_inertia import roll_constants
from webline.spec.schema import (
    DancerSpec,
    DrivenSpec,
    EccentricRoller,
    IdleSpec,
    MeasurementNoise,
    RewindSpec,
    RollerDrag,
    SpeedRipple,
    UnwindSpec,
    WoundInRipple,
)

#: The physical envelope of a run (``kernel.advance`` checks it every tick; outside it the run
#: is a runaway and stops). Webs yield or break at strains of a few per cent (paper 1-4 %,
#: aluminium foil 1-5 %, PET yields near 3-4 %); at 50 % the linear span law (6.8) means nothing
#: and no real web is intact, so |stretch| > 0.5 EA is a state no run can honestly continue from.
RUNAWAY_STRAIN = 0.5
#: Surface speeds beyond 10 x the fastest speed reference (plus 10 m/s, for a line at rest)
#: are a runaway: controlled lines overshoot their reference by tens of per cent, not ten-fold.
RUNAWAY_SPEED_FACTOR = 10.0
RUNAWAY_SPEED_FLOOR = 10.0  # [m/s]


#: ``Plan.structure_key``: node rows, drive rows and the offsets, as tuples
StructureKey = tuple[tuple[tuple[int, ...], ...], tuple[tuple[int, ...], ...], tuple[int, ...]]


def structure_arrays(key: StructureKey) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The node structure, drive structure and offsets of ``key`` as the int64 arrays a loop
    factory closes over (numba freezes a closure's arrays into the machine code, and its disk
    cache keys each compiled closure on their contents: one cached loop per structure)."""
    node_rows, drive_rows, offset_row = key
    return (np.array(node_rows, dtype=np.int64).reshape(len(node_rows), L.NS_COLS),
            np.array(drive_rows, dtype=np.int64).reshape(len(drive_rows), L.DS_COLS),
            np.array(offset_row, dtype=np.int64))


@dataclass(frozen=True)
class Plan:
    """Arrays describing one line for the kernel, plus the names of what they hold.

    ``op`` is the line's operating point at t = 0 with its initial roll radii, computed once
    when the plan is compiled; the drive table, the section models, the initial state, the
    plan's linear models and its fastest mode (``webline.sim.linear.linearize``) all take it from
    here. ``memo`` caches what is derived from the plan (linear models, fastest mode).
    """

    line: Line
    nodes: np.ndarray
    spans: np.ndarray
    drives: np.ndarray
    web: np.ndarray
    wound_ripple: np.ndarray
    speed_ripple: np.ndarray
    prof_t: np.ndarray
    prof_v: np.ndarray
    prof_off: np.ndarray
    offsets: np.ndarray
    node_structure: np.ndarray
    drive_structure: np.ndarray
    gains: tuple[PIGains, ...]
    designs: tuple[SectionDesign | None, ...]
    state_names: tuple[str, ...]
    dt: float
    op: OperatingPoint
    #: the rewind taper's profile index (``winder.taper_columns``), kept for ``patch_plan``
    taper_profile: int = field(default=0, compare=False, repr=False)
    #: derived objects cached per plan (``webline.sim.linear.linearize``), never part of equality
    memo: dict[object, object] = field(default_factory=dict, compare=False, repr=False)

    @property
    def n_x(self) -> int:
        return len(self.state_names)

    def structure(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The integer tables the kernel is compiled against: node structure, drive structure
        and offsets (``webline.sim.elements.layout``)."""
        return self.node_structure, self.drive_structure, self.offsets

    def structure_key(self) -> StructureKey:
        """The integer tables as nested tuples: hashable, the key of one compiled loop (each
        loop factory is cached on it and rebuilds the arrays with ``structure_arrays``)."""
        ns, ds, offsets = self.structure()
        return (tuple(map(tuple, ns.tolist())), tuple(map(tuple, ds.tolist())),
                tuple(offsets.tolist()))

    def params(self) -> tuple[np.ndarray, ...]:
        """Parameter arrays in the order the compiled loop takes them after its settings."""
        return (self.nodes, self.spans, self.drives, self.web, self.wound_ripple,
                self.speed_ripple, self.prof_t, self.prof_v, self.prof_off)

    def profile_value(self, p: int, t: float) -> float:
        """Value at time ``t`` [s] of the plan's reference profile number ``p``."""
        a, b = self.prof_off[p], self.prof_off[p + 1]
        return float(pwl_value(self.prof_t[a:b], self.prof_v[a:b], t))

    def profile_slope(self, p: int, t: float) -> float:
        """Rate of change [unit/s] at time ``t`` [s] of the plan's profile number ``p``."""
        a, b = self.prof_off[p], self.prof_off[p + 1]
        return float(pwl_slope(self.prof_t[a:b], self.prof_v[a:b], t))

    def roll_density(self, i: int) -> float:
        """Density [kg/m³] of the web wound on roll node ``i``: derived from its totals
        (``spec.roll_inertia``), else the web's."""
        return float(self.nodes[i, L.N_RHO])

    def linear_motor_state(self, d: int) -> int | None:
        """Index of drive ``d``'s motor speed in the linear model's states, if compliant."""
        if "motor_states" not in self.memo:  # once per plan: it is asked per drive and model
            line = self.line
            first = line.n_spans + line.n_nodes + len(line.drives)
            compliant = np.flatnonzero(self.drives[:, L.D_TSTATE] >= 0).tolist()
            self.memo["motor_states"] = {d: first + 2 * j for j, d in enumerate(compliant)}
        return self.memo["motor_states"].get(d)  # type: ignore[attr-defined]

    def initial_state(self, op: OperatingPoint) -> tuple[np.ndarray, np.ndarray]:
        """Plant state and controller integrators at the equilibrium ``op``."""
        off = self.offsets
        x = np.zeros(self.n_x)
        x[: self.line.n_spans] = op.tension
        if self.line.nonlinear:  # the state is the stretch EA·ε the law gives each tension
            x[: self.line.n_spans] = [self.line.stretch_of(t) for t in op.tension]
        x[off[1]: off[1] + self.line.n_nodes] = op.omega
        x[off[2]] = op.radius[0]
        x[off[2] + 1] = op.radius[-1]
        limits = self.drives[:, L.D_LIMIT]
        x[off[3]: off[3] + len(op.torque)] = np.clip(op.torque, -limits, limits)
        for d, i in enumerate(op.drives):
            self._transmission_state(x, d, i, op)
        for i in dancers.dancer_nodes(self.line):
            state = int(self.nodes[i, L.N_DANCER])
            load = self.profile_value(int(self.nodes[i, L.N_DLOAD]), op.time)
            load *= dancers.load_taper(self.line, self.drives, i, winder.initial_radius(
                self.drives, self.line.drives.index(self.line.n_nodes - 1), op.radius[-1]))
            x[state] = dancers.equilibrium_position(self.line, i, op.tension[i - 1],
                                                    op.tension[i], load)
        istate = np.zeros((len(op.torque), L.I_COLS))
        istate[:, L.I_SPEED] = x[off[3]: off[3] + len(op.torque)]
        for d, i in enumerate(op.drives):  # the compensations carry their part of the torque
            istate[d, L.I_SPEED] -= winder.compensation_torque(
                self.drives[d], op.inertia[i], op.radius[i], op.omega[i],
                self.profile_slope(0, op.time))
        istate[:, L.I_FRICTION] = self.drives[:, L.D_BMODEL]
        istate[:, L.I_KT] = self.drives[:, L.D_KT]  # the MRAC's k̂ starts at the design
        istate[:, L.I_KV] = self.drives[:, L.D_KV]
        for d, i in enumerate(op.drives):  # the tension observers start at the equilibrium
            loadcell = int(self.drives[d, L.D_LOADCELL])
            istate[d, L.I_THAT] = op.tension[loadcell] if loadcell >= 0 else 0.0
            istate[d, L.I_WHAT] = op.omega[i]
        istate[:, L.I_DETECT] = -1.0  # no web break detected
        for d, i in enumerate(op.drives):
            istate[d, L.I_RADIUS] = winder.initial_radius(self.drives, d, op.radius[i])
        ea = self.line.ea
        ramp = 1.0 if self.web[L.W_TRAMP] == 0 else self.profile_value(
            int(self.web[L.W_TRAMP]), op.time)  # the tension ramp, as the kernel applies it
        t_master = self.profile_value(int(off[6]), op.time) * ramp
        for d, i in enumerate(op.drives):
            up = int(self.drives[d, L.D_UPREF])
            t_up = self.web[L.W_T0] if up < 0 else self.profile_value(up, op.time) * ramp
            if self.line.exact:  # (``physics.span.draw_ratio``)
                feedforward = op.line_speed * draw_ratio(ea, t_up, t_master, True)
            else:  # (6.22, as written before exact transport: the same last bits)
                feedforward = op.line_speed * (ea - t_master) / (ea - t_up)
            measured = self.drives[d, L.D_VSCALE] * op.speed[i]  # as its encoder reads it
            istate[d, L.I_TENSION] = self.drives[d, L.D_SIGMA] * (measured - feedforward)
        if self.offsets[L.O_SENSORS]:  # the delayed readings start at the initial state's
            loadcells = self.drives[:, L.D_LOADCELL].astype(int)
            fill_delays(self.drives, istate, np.where(loadcells >= 0, op.tension[loadcells],
                                                      np.nan),
                        istate[:, L.I_RADIUS] * op.omega[list(op.drives)])
        return x, istate


    def _transmission_state(self, x: np.ndarray, d: int, i: int, op: OperatingPoint) -> None:
        """Motor speed and twist of a compliant transmission at equilibrium: the twist that
        passes the load-side torque n τ - n² (J_m dω/dt + b_m ω)."""
        row = self.drives[d]
        state = int(row[L.D_TSTATE])
        if state < 0:
            return
        n = row[L.D_RATIO]
        x[state] = n * op.omega[i]
        load = n * x[int(self.offsets[3]) + d] - n**2 * (row[L.D_JMOTOR] * op.accel[i]
                                                        + row[L.D_BMOTOR] * op.omega[i])
        x[state + 1] = load / row[L.D_KTRANS] + (
            row[L.D_GAPPOS] if load > 0 else (-row[L.D_GAPNEG] if load < 0 else 0.0))




def compile_plan(line: Line, *, sample_rate: float | None = None) -> Plan:
    """Flatten ``line`` for the kernel; controller gains are tuned where the file leaves them.

    Plans are memoised on the (immutable) line, per sample rate.
    """
    key = ("plan", sample_rate)
    if key not in line.memo:
        line.memo[key] = _compile(line, sample_rate)
    return line.memo[key]  # type: ignore[return-value]


def _compile(line: Line, sample_rate: float | None) -> Plan:
    spec = line.spec
    rollers = spec.rollers
    n_nodes, n_spans, n_drives = line.n_nodes, line.n_spans, len(line.drives)
    eccentric = {d.roller: d.eccentricity for d in spec.disturbances
                 if isinstance(d, EccentricRoller)}

    names = [f"{line.span_name(k)}.stretch" for k in range(n_spans)]
    names += [f"{r.name}.omega" for r in rollers]
    names += [f"{rollers[0].name}.radius", f"{rollers[-1].name}.radius"]
    names += [f"{rollers[i].name}.torque" for i in line.drives]
    ecc_nodes = [i for i, r in enumerate(rollers) if r.name in eccentric]
    names += [f"{rollers[i].name}.angle" for i in ecc_nodes]
    compliant = [i for i in line.drives if transmission(line, i).type != "direct"]
    for i in compliant:
        names += [f"{rollers[i].name}.motor_omega", f"{rollers[i].name}.twist"]
    dancer_nodes = dancers.dancer_nodes(line)
    for i in dancer_nodes:
        names += [f"{rollers[i].name}.position", f"{rollers[i].name}.velocity"]
    names += ["web.unwound", "web.rewound"]
    off_w = n_spans
    off_r = off_w + n_nodes
    off_tq = off_r + 2
    off_th = off_tq + n_drives
    off_tr = off_th + len(ecc_nodes)
    off_dn = off_tr + 2 * len(compliant)
    off_q = off_dn + 2 * len(dancer_nodes)

    op = operating_point(line)  # the plan's one operating point (t = 0, initial radii)
    inertia = op.inertia
    nodes = np.zeros((n_nodes, L.N_COLS))
    kinds = {UnwindSpec: L.KIND_UNWIND, DrivenSpec: L.KIND_DRIVEN, IdleSpec: L.KIND_IDLE,
             DancerSpec: L.KIND_IDLE, RewindSpec: L.KIND_REWIND}
    own_density = False  # a roll whose wound density comes from its totals (J1)
    for i, r in enumerate(rollers):
        row = nodes[i]
        row[L.N_KIND] = kinds[type(r)]
        row[L.N_RADIUS] = r.radius
        _, row[L.N_VISCOUS], row[L.N_COULOMB] = shaft_terms(r)  # a nip's bearing included
        row[L.N_DRIVE] = line.drives.index(i) if i in line.drives else -1
        row[L.N_RATIO] = 1.0 if isinstance(r, IdleSpec) else r.drive.ratio
        motor = 0.0  # a compliant transmission keeps the motor's inertia on the motor side
        if i in compliant:
            motor = r.drive.ratio**2 * r.drive.motor_inertia  # type: ignore[union-attr]
        row[L.N_JCONST] = inertia[i] - motor
        row[L.N_INVJ] = 1.0 / row[L.N_JCONST]
        if isinstance(r, UnwindSpec | RewindSpec):
            row[L.N_CORE] = r.core_radius
            core, density = roll_constants(r, spec.web)  # the web's density, or totals'
            row[L.N_RHO] = density  # the web's, or derived from the totals (J1)
            own_density = own_density or density != spec.web.density
            row[L.N_JCONST] = core + r.drive.ratio**2 * r.drive.motor_inertia - motor
        contact = getattr(r, "contact", None)
        if contact is not None and contact.type == "traction":
            row[L.N_TRACTION], row[L.N_WRAP] = 1.0, r.wrap  # type: ignore[union-attr]
            row[L.N_MU] = contact.friction
            row[L.N_MUK] = contact.friction if contact.kinetic_friction is None else (
                contact.kinetic_friction)
            row[L.N_SLIPB] = contact.viscous
            if r.nip is not None:  # type: ignore[union-attr]
                row[L.N_NIPS], row[L.N_NIPK] = r.nip.capacity()  # type: ignore[union-attr]
        row[L.N_DRAG] = -1
        row[L.N_DANCER] = -1
        row[L.N_ECC] = eccentric.get(r.name, 0.0)
        row[L.N_ECCSTATE] = off_th + ecc_nodes.index(i) if i in ecc_nodes else -1

    profiles = [breakpoints(spec.speed)]
    profiles += [breakpoints(spec.spans[z.loadcell].tension) for z in line.zones]
    drags = {i: rollers[i].drive.brake for i in line.drives  # type: ignore[union-attr]
             if rollers[i].drive.brake is not None}  # type: ignore[union-attr]
    drags |= {_node(line, d.roller): d.torque for d in spec.disturbances
              if isinstance(d, RollerDrag)}
    for i in sorted(drags):
        nodes[i, L.N_DRAG] = len(profiles)
        profiles.append(breakpoints(drags[i]))
    for j, i in enumerate(dancer_nodes):
        dancers.node_columns(nodes[i], line, i, off_dn + 2 * j, len(profiles))
        profiles.append(dancers.load_profile(line, i))
    taper_profile = len(profiles)
    profiles += winder.taper_profiles(line)
    spliced = splice.splice_columns(nodes, line, len(profiles))
    profiles += splice.splice_profiles(line)
    ramp_profile_index = 0  # the tension ramp's factor (docs/winder.md R1), 0: none
    if spec.control.tension_ramp is not None:
        ramp_profile_index = len(profiles)
        profiles.append(ramp_profile(spec.speed, spec.control.tension_ramp))
    prof_off = np.cumsum([0] + [len(t) for t, _ in profiles]).astype(np.int64)

    rate = sample_rate if sample_rate is not None else spec.control.sample_rate
    drives, gains, designs, friction, sensors = _drive_rows(line, op, rate, nodes, off_tr,
                                                            taper_profile)
    master_up = 1 + line.zone_of_span(line.master - 1)
    web, noisy = _web_row(line, ramp_profile_index)
    need_eq = bool(np.any((drives[:, L.D_FAMILY] != L.FAMILY_PI)
                          & (drives[:, L.D_FAMILY] != L.FAMILY_USER)))
    span_table = np.array([[s.length, 1.0 / s.length, 0.0, s.retardation or 0.0]
                           for s in spec.spans])
    breaks = winder.break_columns(line, span_table, web)
    # the rollers feel a tension other than the stretch: a damper, a nonlinear law, or both
    felt = bool(np.any(span_table[:, L.S_TAU] > 0.0)) or line.nonlinear
    offsets = np.array([0, off_w, off_r, off_tq, off_th, off_q, master_up, line.master,
                        off_tr, noisy, need_eq, breaks, felt, spliced, friction,
                        own_density, line.nonlinear, line.exact, sensors],
                       dtype=np.int64)
    wound = np.array([[d.amplitude, d.frequency, d.phase] for d in spec.disturbances
                      if isinstance(d, WoundInRipple)]).reshape(-1, 3)
    ripple = np.array([[line.drives.index(_node(line, d.roller)), d.amplitude, d.frequency,
                        d.phase] for d in spec.disturbances
                       if isinstance(d, SpeedRipple)]).reshape(-1, 4)
    return Plan(
        line=line, nodes=nodes, drives=drives,
        spans=span_table,
        web=np.concatenate((web, line.law)), wound_ripple=wound, speed_ripple=ripple,
        prof_t=np.concatenate([t for t, _ in profiles]),
        prof_v=np.concatenate([v for _, v in profiles]), prof_off=prof_off, offsets=offsets,
        node_structure=nodes[:, list(L.NODE_STRUCTURE)].astype(np.int64),
        drive_structure=drives[:, list(L.DRIVE_STRUCTURE)].astype(np.int64),
        gains=gains, designs=designs, state_names=tuple(names), dt=1.0 / rate, op=op,
        taper_profile=taper_profile,
    )


def patch_plan(base: Plan, line: Line, op: OperatingPoint) -> Plan | None:
    """The plan of ``line`` (at its file's sample rate) made from ``base``, the plan of a line
    that differs from ``line`` only in values that the drive table, the web's row and the
    operating point read (``sim.core.plan_patch`` says which paths qualify): the drive table
    and the web's row are computed again at ``op``, ``line``'s operating point, by the
    functions ``compile_plan`` uses; every other table is ``base``'s. None where the patched
    flags or structure columns would differ from ``base``'s (a full plan is needed). Memoised
    on ``line`` as ``compile_plan``'s plan."""
    rate = line.spec.control.sample_rate
    nodes = base.nodes.copy()  # friction_columns writes its columns again (the same values)
    drives, gains, designs, friction, sensors = _drive_rows(
        line, op, rate, nodes, int(base.offsets[8]), base.taper_profile)
    web, noisy = _web_row(line, int(base.web[L.W_TRAMP]))
    spans = base.spans.copy()
    breaks = winder.break_columns(line, spans, web)
    need_eq = bool(np.any((drives[:, L.D_FAMILY] != L.FAMILY_PI)
                          & (drives[:, L.D_FAMILY] != L.FAMILY_USER)))
    flags = {L.O_NOISE: noisy, L.O_NEED_EQ: need_eq, L.O_BREAK: breaks, L.O_FRICTION: friction,
             L.O_LAW: line.nonlinear, L.O_EXACT: line.exact, L.O_SENSORS: sensors}
    drive_structure = drives[:, list(L.DRIVE_STRUCTURE)].astype(np.int64)
    if (any(int(base.offsets[k]) != int(v) for k, v in flags.items())
            or 1.0 / rate != base.dt
            or not np.array_equal(drive_structure, base.drive_structure)
            or not np.array_equal(nodes, base.nodes) or not np.array_equal(spans, base.spans)
            or line.law.size != base.web.size - L.W_COLS):
        return None
    plan = Plan(
        line=line, nodes=base.nodes, drives=drives, spans=base.spans,
        web=np.concatenate((web, line.law)), wound_ripple=base.wound_ripple,
        speed_ripple=base.speed_ripple, prof_t=base.prof_t, prof_v=base.prof_v,
        prof_off=base.prof_off, offsets=base.offsets, node_structure=base.node_structure,
        drive_structure=base.drive_structure, gains=gains, designs=designs,
        state_names=base.state_names, dt=1.0 / rate, op=op, taper_profile=base.taper_profile,
    )
    line.memo[("plan", None)] = plan
    return plan


def _drive_rows(line: Line, op: OperatingPoint, rate: float, nodes: np.ndarray, off_tr: int,
                taper_profile: int,
                ) -> tuple[np.ndarray, tuple[PIGains, ...], Designs, bool, bool]:
    """The drive table of ``line`` at ``op`` for controllers sampled at ``rate`` [Hz], its PI
    gains and decentralized designs, and whether friction tables (written into ``nodes``
    too) and calibrated sensors are used; ``off_tr``: the first transmission state,
    ``taper_profile``: the rewind taper's profile index."""
    rollers = line.spec.rollers
    compliant = [i for i in line.drives if transmission(line, i).type != "direct"]
    drives, gains, designs = drive_table(line, op, rate)
    for d, i in enumerate(line.drives):
        state = off_tr + 2 * compliant.index(i) if i in compliant else -1
        transmission_columns(drives[d], rollers[i].drive, state)  # type: ignore[union-attr]
    dancers.drive_columns(drives, line)
    winder.taper_columns(drives, line, taper_profile)
    winder.diameter_columns(drives, line)
    winder.compensation_columns(drives, line)
    friction = friction_columns(nodes, drives, line, 1.0 / rate)
    sensors = sensor_columns(drives, line, 1.0 / rate)  # calibrated loadcells, encoders
    return drives, gains, designs, friction, sensors


def _web_row(line: Line, ramp_profile_index: int) -> tuple[np.ndarray, bool]:
    """The web's row of ``line`` (before the break columns and its law) and whether its
    measurements are noisy; ``ramp_profile_index``: the tension ramp's profile (0: none)."""
    spec = line.spec
    web = np.zeros(L.W_COLS)
    web[L.W_EA] = line.ea
    web[L.W_THICK] = spec.web.thickness
    web[L.W_WIDTH] = spec.web.width
    web[L.W_DENSITY] = spec.web.density
    web[L.W_T0] = line.unwind.wound_in_tension
    web[L.W_RHOA] = spec.web.density * spec.web.width * spec.web.thickness
    web[L.W_TRAMP] = ramp_profile_index
    web[L.W_STRENGTH] = math.inf if spec.web.strength is None else spec.web.strength
    if line.nonlinear:  # the kernel checks the stretch: the one where the law reaches it
        web[L.W_STRENGTH] = line.stretch_of(web[L.W_STRENGTH])
    web[L.W_STRETCH_MAX] = RUNAWAY_STRAIN * line.ea
    top_speed = float(np.max(np.abs(breakpoints(spec.speed)[1])))
    web[L.W_SPEED_MAX] = RUNAWAY_SPEED_FACTOR * top_speed + RUNAWAY_SPEED_FLOOR
    noisy = False
    for noise in (d for d in spec.disturbances if isinstance(d, MeasurementNoise)):
        web[L.W_NOISE_T], web[L.W_NOISE_V], web[L.W_SEED] = noise.tension, noise.speed, noise.seed
        web[L.W_RES_V] = noise.speed_resolution
        noisy = noise.tension > 0 or noise.speed > 0 or noise.speed_resolution > 0
    return web, noisy


def _node(line: Line, name: str) -> int:
    return next(i for i, r in enumerate(line.spec.rollers) if r.name == name)


def equilibrium_plan_state(plan: Plan, t: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Initial state and integrators at the line's operating point at time ``t`` [s] (the
    plan's own ``op`` at t = 0)."""
    return plan.initial_state(plan.op if t == 0.0 else operating_point(plan.line, t))
