"""The plan of a branched line: its topology (``model.web_graph``) as flat arrays for the
compiled loop (``sim.branches.loop``), with the PI gains of every drive.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import numpy as np

from webline.control.pi import tune
from webline.model.web_graph import BranchedLine
from webline.profiles import breakpoints
from webline.sim.branches.dancers import (
    dancer_columns,
    dancer_nodes,
    load_rows,
    zone_cells,
    zone_gains,
)
from webline.sim.branches.disturb import break_columns, disturbance_table, eccentricities
from webline.sim.branches.drives.drive_trains import brake_rows, train_columns, tuning_inertia
from webline.sim.branches.laminate_tables import layer_columns
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.control import held_inputs
from webline.sim.branches.loop.dancer_taper import taper_loads
from webline.sim.branches.loop.draw import refs_rows
from webline.sim.branches.loop.kernel import compiled_advance
from webline.sim.branches.loop.plant import node_inertia, work_size
from webline.sim.branches.sensors import sensor_columns
from webline.sim.branches.traction import traction_columns
from webline.sim.branches.web_laws import law_tables
from webline.sim.branches.winder import (
    diameter_columns,
    ramp_column,
    rotating_inertia,
    splice_rows,
    taper_columns,
    winder_columns,
    wound_density,
)
from webline.spec.branched.check import kind_of
from webline.spec.schema import CascadedPISpec, IdleSpec, RewindSpec, UnwindSpec

#: the runaway speed: this factor x the top reference speed, plus a floor [m/s]
RUNAWAY_SPEED_FACTOR, RUNAWAY_SPEED_FLOOR = 3.0, 1.0


@dataclass(frozen=True, eq=False)
class BranchPlan:
    """Flat tables of a branched line (columns: ``sim.branches.loop.layout``). Profile 0 is the
    line speed, then the tension references of the spans that have one, then the drag
    torques. ``radius0``: each drive's calculated radius at the start [m] (0 without a
    diameter calculator). ``wound``: the held inputs, wound-in tension [N] per web then drag
    [N·m] per node (``held`` gives them at a time). ``lawi``, ``lawf``, ``laws``, ``kv``: the
    web laws' terms and Kelvin-Voigt spans (``sim.branches.web_laws``; empty: linear elastic).
    ``fb``, ``refs``: the decentralized families' gains and references (``layout`` FB_*,
    filled by ``decentral.prepare``; the PI drives' draw rows by ``drives.draw``, ``loop.draw``)."""

    line: BranchedLine
    offsets: np.ndarray
    nodes: np.ndarray
    si: np.ndarray
    sf: np.ndarray
    layers: np.ndarray
    rolls: np.ndarray
    webs: np.ndarray
    di: np.ndarray
    df: np.ndarray
    cores: np.ndarray
    clutch: np.ndarray
    cells: np.ndarray
    events: np.ndarray
    dist: np.ndarray
    radius0: np.ndarray
    wound: np.ndarray
    prof_t: np.ndarray
    prof_v: np.ndarray
    prof_off: np.ndarray
    dt: float
    speed_max: float
    lawi: np.ndarray
    lawf: np.ndarray
    laws: np.ndarray
    kv: np.ndarray
    fb: np.ndarray
    refs: np.ndarray

    @property
    def n_x(self) -> int:
        return int(self.offsets[B.O_N])

    @functools.cached_property
    def const(self) -> Any:
        """The integer tables the compiled loop holds as constants (``offsets``, ``si``,
        ``layers``, ``webs``, ``di``, ``cores``, ``lawi``, ``kv``) as read-only views, the
        type numba gives those constants: a compiled function called from Python with them
        (``rhs``, ``node_inertia``, ...) reuses what the loop compiled instead of compiling
        again for writable arrays (issue 37: the first run's compile time). Views: the set-up
        that fills the plan's own tables (observer rows) shows through."""
        return SimpleNamespace(**{name: _read_only(getattr(self, name)) for name in (
            "offsets", "si", "layers", "webs", "di", "cores", "lawi", "kv")})

    def tables(self) -> tuple[np.ndarray, ...]:
        """The tables ``kernel.rhs`` takes after ``wound``, in order (the integer ones from
        ``const``)."""
        c = self.const
        return (c.offsets, self.nodes, c.si, self.sf, c.layers, self.rolls, c.webs, c.di,
                self.df, c.cores, self.clutch, c.lawi, self.lawf, self.laws, c.kv)

    def scratch(self) -> np.ndarray:
        """Scratch for ``kernel.rhs``."""
        return np.zeros(work_size(len(self.line.spans), self.nodes.shape[0]))

    def loop(self, law: Any = None) -> Any:
        """The compiled loop of this plan's structure (``kernel.compiled_advance``; ``law``:
        users' compiled laws in it, as ``compiled_advance`` takes them)."""
        return compiled_advance(self.offsets, self.si, self.layers, self.webs, self.di,
                                self.cells, self.cores, self.lawi, self.kv, law)

    def run(self, x: np.ndarray, istate: np.ndarray, wound: np.ndarray, done: np.ndarray,
            rec: np.ndarray, cmd: np.ndarray, tick0: int, n_ticks: int, substeps: int,
            record_every: int, include_end: bool = True) -> tuple[int, int, float]:
        """Advance ``x``, ``istate``, ``wound`` (wound-in tension per web), ``done`` (roll
        changes made) and ``cmd`` in place by ``n_ticks`` controller periods from tick
        ``tick0``, recording into ``rec`` (``kernel.advance``)."""
        stages = np.empty((5, self.n_x))
        return self.loop()(x, istate, wound, done, rec, stages, cmd, self.scratch(),
                           np.empty_like(wound), tick0,
                           n_ticks, self.dt, substeps, record_every, include_end,
                           self.speed_max,
                           self.nodes, self.sf, self.rolls, self.df, self.clutch, self.events,
                           self.dist, self.prof_t, self.prof_v, self.prof_off, self.lawf,
                           self.laws, self.fb, self.refs)

    def held(self, t: float) -> np.ndarray:
        """The held inputs ``kernel.rhs`` takes at ``t`` [s] without the ripples (their mean):
        wound-in tensions, drag torques and dancers' loads (``kernel.held_inputs``; a load
        through a taper at the rolls' starting radii, ``loop.dancer_taper``)."""
        out = np.empty_like(self.wound)
        drags = self.dist[np.isin(self.dist[:, B.DS_KIND], (B.DIST_DRAG, B.DIST_DANCER_LOAD))]
        held_inputs(t, self.wound, out, self.webs.shape[0], drags, self.prof_t, self.prof_v,
                    self.prof_off)
        if self.offsets[B.O_DANCER] < self.offsets[B.O_DANCER_END]:  # tapered loads at the start
            x = np.zeros(self.n_x)
            x[self.offsets[B.O_RADIUS]:self.offsets[B.O_TORQUE]] = [r.radius for r in
                                                                    self.line.rolls]
            istate = np.zeros((self.di.shape[0], B.I_COLS))
            istate[:, B.I_RADIUS] = [x[self.offsets[B.O_RADIUS] + j] if j >= 0 else 0.0
                                     for j in self.di[:, B.DI_ROLL]]
            taper_loads(out, istate, x, self.offsets, self.nodes, self.di, self.df,
                        self.cells, self.prof_t, self.prof_v, self.prof_off)
        return out

    def profile(self, p: int, t: float) -> float:
        a, b = self.prof_off[p], self.prof_off[p + 1]
        return float(np.interp(t, self.prof_t[a:b], self.prof_v[a:b]))


def _read_only(array: np.ndarray) -> np.ndarray:
    """A read-only view of ``array`` (the plan's own table stays writable for its set-up)."""
    view = array.view()
    view.setflags(write=False)
    return view


def compile_branches(line: BranchedLine, sample_rate: float | None = None) -> BranchPlan:
    """The plan of ``line``; gains are tuned at the initial radii (``control.pi.tune``)."""
    spec = line.spec
    n_n, n_s, n_r, n_d, n_w = (len(spec.rollers), len(line.spans), len(line.rolls),
                               len(line.drives), len(spec.webs))
    off_w = n_s
    off_r = off_w + n_n
    off_tq = off_r + n_r
    off_q = off_tq + n_d
    cores, clutch = _clutch_tables(line)
    eccentric = eccentricities(line)
    off_c = off_q + 2 * n_w
    off_dn = off_c + len(cores) + len(eccentric)  # dancers: 2 states each (docs/branching.md)
    n_dn = len(dancer_nodes(line))
    offsets = np.array([off_w, off_r, off_tq, off_q, off_c, off_c + len(cores),
                        off_dn + 2 * n_dn, -1, 0, 0, 0, off_dn, off_dn + 2 * n_dn, 0, 0,
                        int(line.exact), 0],
                       dtype=np.int64)
    nodes = np.zeros((n_n, B.N_COLS))
    for i, r in enumerate(spec.rollers):
        nodes[i, B.N_RADIUS] = r.radius
        nodes[i, B.N_JCONST] = rotating_inertia(line, i)  # (a roll's totals: J1)
        nodes[i, B.N_VISCOUS], nodes[i, B.N_COULOMB] = r.friction, r.coulomb_friction
        nodes[i, B.N_RATIO] = 1.0
        nodes[i, B.N_DRIVE] = line.drives.index(i) if i in line.drives else -1
        if not isinstance(r, IdleSpec):
            n = r.drive.ratio
            nodes[i, B.N_RATIO] = n
            nodes[i, B.N_JCONST] += n * n * r.drive.motor_inertia
            nodes[i, B.N_VISCOUS] += n * n * r.drive.motor_friction  # at the motor shaft
        if isinstance(r, UnwindSpec | RewindSpec):
            nodes[i, B.N_CORE] = r.core_radius
    nodes[:, B.N_INVJ] = 1.0 / nodes[:, B.N_JCONST]
    nodes[:, B.N_ANGLE] = -1.0
    for e, (i, eccentricity) in enumerate(eccentric.items()):
        nodes[i, B.N_ECC], nodes[i, B.N_ANGLE] = eccentricity, e
    rolls = np.zeros((n_r, B.R_COLS))
    for j, roll in enumerate(line.rolls):
        on_clutch = float(j in cores[:, B.C_ROLL])
        nodes[roll.node, B.N_ROLLS] += 1 - on_clutch
        m = line.materials[roll.web]
        rolls[j] = (roll.node, roll.web, roll.direction, m.thickness, m.width,
                    wound_density(line, j), nodes[roll.node, B.N_CORE], on_clutch)
    si, sf, layers = _span_tables(line)
    rate = spec.control.sample_rate if sample_rate is None else sample_rate
    traction_columns(line, nodes, si, offsets, 1.0 / rate)  # slip, nips, measured friction
    lawi, lawf, laws, kv = law_tables(line, si, sf)
    for c, (_, _, k) in enumerate(cores):
        si[k, B.S_CORE] = c
    si[:, B.S_ECCA] = nodes[si[:, B.S_A], B.N_ANGLE]
    si[:, B.S_ECCB] = nodes[si[:, B.S_B], B.N_ANGLE]
    dancer_columns(line, offsets, nodes, si, sf)
    webs = np.array([[line.web_spans(w)[0], line.web_spans(w)[-1]] for w in range(n_w)],
                    dtype=np.int64).reshape(n_w, B.WB_COLS)
    profiles = [breakpoints(spec.speed)]
    ref_of = {}
    for k in range(n_s):
        tension = line.span_tension_spec(k)
        if tension is not None:
            ref_of[k] = len(profiles)
            profiles.append(breakpoints(tension))
    wound = np.zeros(n_w + n_n)  # wound-in tension per web, drag per node (held_inputs)
    for w, web in enumerate(spec.webs):
        first = spec.rollers[line.node_index[web.path[0]]]
        if isinstance(first, UnwindSpec):
            wound[w] = first.wound_in_tension
    di = np.zeros((n_d, B.DI_COLS), dtype=np.int64)
    df = np.zeros((n_d, B.D_COLS))
    cells: list[tuple[int, int, int, int]] = []
    for d, i in enumerate(line.drives):
        zone = line.zones.get(i)
        di[d, B.DI_NODE] = i
        di[d, B.DI_CELLS] = len(cells)
        zone_rows = zone_cells(line, zone, ref_of)  # loadcells, or its dancer's position
        di[d, B.DI_NCELLS] = len(zone_rows)
        cells += zone_rows
        di[d, B.DI_ROLL] = _speed_roll(line, i, zone.loadcells if zone else ())
        di[d, B.DI_FAMILY] = B.FAMILIES.get(getattr(spec.rollers[i], "controller", None)
                                            .type, B.FAMILY_PI)  # type: ignore[union-attr]
        df[d, B.D_SIGMA] = zone.sigma if zone and i not in cores[:, B.C_NODE] else 0.0
    events = np.zeros((0, B.E_COLS))
    change = line.roll_change
    if change is not None:
        node = line.node_index[change.roller]
        j = next(j for j, r in enumerate(line.rolls) if r.node == node)
        w = line.rolls[j].web
        new = wound[w] if change.wound_in_tension is None else change.wound_in_tension
        events = np.array([[change.time, j, change.radius, new, w, B.EVENT_ROLL_CHANGE, 1.0,
                            0.0]])
    dist = np.vstack([disturbance_table(line, profiles), brake_rows(line, profiles)])
    train_columns(line, offsets, nodes, di, df)  # compliant transmissions (drive_trains)
    layer_columns(line, si, offsets, lawi, lawf)  # bonded layers' states: the state's end
    if break_columns(line, sf, df):  # a web break: after the drags each span's broken flag,
        offsets[B.O_BREAK] = 1  # then each node's holding brake [N·m]
        wound = np.concatenate([wound, np.zeros(n_s + n_n)])
    first_load = len(wound)  # dancers' loads: the last held inputs
    wound = np.concatenate([wound, np.zeros(n_dn)])
    dist = np.vstack([dist, load_rows(line, first_load, profiles, ref_of)])
    taper_columns(line, df, profiles)
    radius0 = diameter_columns(line, df, di)
    winder_columns(line, di, df, profiles)  # centre winders: compensation, open loop, ramp
    offsets[B.O_RAMP] = ramp_column(line, profiles)
    sensor_columns(line, offsets, sf, di, df, cells, 1.0 / rate)  # (spec.sensors)
    events = np.vstack([events, np.reshape(splice_rows(line, 1.0 / (
        spec.control.sample_rate if sample_rate is None else sample_rate)), (-1, B.E_COLS))])
    offs = np.cumsum([0] + [len(t) for t, _ in profiles]).astype(np.int64)
    top = max(float(np.max(np.abs(v))) for v in [breakpoints(spec.speed)[1]])
    plan = BranchPlan(line, offsets, nodes, si, sf, layers, rolls, webs, di, df, cores, clutch,
                      np.array(cells, dtype=np.int64).reshape(-1, B.CELL_COLS), events, dist,
                      radius0, wound,
                      np.concatenate([t for t, _ in profiles]),
                      np.concatenate([v for _, v in profiles]), offs, 1.0 / rate,
                      RUNAWAY_SPEED_FACTOR * top + RUNAWAY_SPEED_FLOOR, lawi, lawf, laws, kv,
                      np.zeros((n_d, B.FB_COLS)),
                      np.zeros((refs_rows(n_s, n_d), 1 + len(cells))))
    _tune(plan)
    zone_gains(line, plan.di, plan.df, plan.cells, zone_compliance)
    return plan


def _span_tables(line: BranchedLine) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    spec = line.spec
    si = np.zeros((len(line.spans), B.S_COLS), dtype=np.int64)
    sf = np.zeros((len(line.spans), B.SF_COLS))
    layers: list[int] = []
    for span in line.spans:
        web = spec.webs[span.web]
        k = span.index
        si[k, B.S_A], si[k, B.S_B], si[k, B.S_WEB] = span.a, span.b, span.web
        si[k, B.S_CORE] = -1
        si[k, B.S_ARMA] = line.roll_of(span.a, span.web)
        si[k, B.S_ARMB] = line.roll_of(span.b, span.web)
        sf[k, B.SF_LENGTH] = span.length
        sf[k, B.SF_INVLENGTH] = 1.0 / span.length
        sf[k, B.SF_EA] = line.materials[span.web].ea
        sf[k, B.SF_INVEA] = 1.0 / sf[k, B.SF_EA]
        if span.k > 0:
            si[k, B.S_SRC], si[k, B.S_FROM] = B.SRC_PREVIOUS, k - 1
        elif kind_of(web) == "laminate":
            si[k, B.S_SRC], si[k, B.S_FROM] = B.SRC_LAYERS, len(layers)
            names = web.layers or []
            layers += [line.web_spans(line.web_index[n])[-1] for n in names]
            si[k, B.S_COUNT] = len(names)
        elif kind_of(web) == "lane":
            base = line.web_index[web.slit_from or ""]
            si[k, B.S_SRC], si[k, B.S_FROM] = B.SRC_SLIT, line.web_spans(base)[-1]
            sf[k, B.SF_SHARE] = line.materials[span.web].ea / line.materials[base].ea
        else:
            si[k, B.S_SRC] = B.SRC_WOUND
    return si, sf, np.array(layers, dtype=np.int64)


def _clutch_tables(line: BranchedLine) -> tuple[np.ndarray, np.ndarray]:
    """The clutch cores of every differential shaft, one per lane wound on it: int rows
    (roll, shaft node, lane span), float rows (slip torque, core inertia, overspeed)."""
    rows, values = [], []
    for j, roll in enumerate(line.rolls):
        roller = line.spec.rollers[roll.node]
        shaft = getattr(roller, "shaft", None)
        if isinstance(roller, RewindSpec) and shaft is not None:
            rows.append((j, roll.node, line.web_spans(roll.web)[-1]))
            values.append((shaft.slip_torque, shaft.core_inertia, shaft.overspeed))
    return (np.array(rows, dtype=np.int64).reshape(-1, B.C_COLS),
            np.array(values, dtype=float).reshape(-1, B.CF_COLS))


def _speed_roll(line: BranchedLine, i: int, loadcells: tuple[int, ...]) -> int:
    """The roll whose radius converts drive ``i``'s surface speed to ω: the first loadcell's
    web's roll on this node, else its first roll; -1 for a roller."""
    for k in loadcells:
        j = line.roll_of(i, line.spans[k].web)
        if j >= 0:
            return j
    return next((j for j, r in enumerate(line.rolls) if r.node == i), -1)


def zone_compliance(line: BranchedLine, i: int) -> float:
    """L/EA [m/N] the tension loop of drive ``i`` sees: 1 / sum over its loadcells of EA/L,
    L the length of the zone's spans on that loadcell's web (one web: the chain's L/EA)."""
    zone = line.zones[i]
    stiffness = 0.0
    for k in zone.loadcells:
        web = line.spans[k].web
        length = sum(line.spans[s].length for s in zone.spans if line.spans[s].web == web)
        stiffness += line.materials[web].ea / length
    return 1.0 / stiffness


def _tune(plan: BranchPlan) -> None:
    """PI gains of every drive (the chain's ``sim.core.drive_table._pi_columns`` rule)."""
    line = plan.line
    x = np.zeros(plan.n_x)
    for j, roll in enumerate(line.rolls):
        x[plan.offsets[B.O_RADIUS] + j] = roll.radius
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        assert not isinstance(roller, IdleSpec)
        pi = roller.controller if isinstance(roller.controller, CascadedPISpec) else (
            CascadedPISpec())  # a decentralized drive: its PI columns stay unused
        c, drive = pi, roller.drive
        j = plan.di[d, B.DI_ROLL]
        radius = x[plan.offsets[B.O_RADIUS] + j] if j >= 0 else roller.radius
        inertia, seen = tuning_inertia(plan.di, plan.df, d, float(
            node_inertia(i, x, plan.const.offsets, plan.nodes, plan.rolls)))
        zone = i in line.zones
        compliance = zone_compliance(line, i) if zone else 1.0
        auto = tune(inertia, drive.ratio, radius, compliance, 1.0, c.speed_bandwidth,
                    c.tension_bandwidth, c.damping)
        limit = min(0.2 / drive.torque_lag, 2 * math.pi / plan.dt / 20)
        scale = min(1.0, limit * seen / (drive.ratio * radius) / auto.speed_kp)
        row = plan.df[d]
        row[B.D_RATIO] = drive.ratio
        row[B.D_KPS] = scale * auto.speed_kp if c.speed_kp is None else c.speed_kp
        row[B.D_KIS] = scale * auto.speed_ki if c.speed_ki is None else c.speed_ki
        if zone and i not in plan.cores[:, B.C_NODE]:  # (a differential shaft: speed only)
            row[B.D_KPT] = auto.tension_kp if c.tension_kp is None else c.tension_kp
            row[B.D_KIT] = auto.tension_ki if c.tension_ki is None else c.tension_ki
        row[B.D_LIMIT] = drive.torque_limit
        row[B.D_INVLAG] = 1.0 / drive.torque_lag
        row[B.D_GAINNORM] = inertia / (drive.ratio * radius)
        row[B.D_ADAPTIVE] = 1.0 if isinstance(roller, UnwindSpec | RewindSpec) and (
            c.inertia_adaptive) else 0.0
