"""The result of a branched line's run: an xarray Dataset of named signals and a verdict per
web and lane computed from them."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from webline.sim.branches.dancer_views import end_stop_findings, span_lengths
from webline.sim.branches.dancers import dancer_nodes
from webline.sim.branches.drives.drive_trains import train_motor_omega
from webline.sim.branches.findings.break_verdict import break_findings, intact, without_cut_jump
from webline.sim.branches.findings.layer_findings import compressed_findings
from webline.sim.branches.findings.web_findings import felt_records, layer_tension, yield_findings
from webline.sim.branches.findings.winder_states import (
    diameter_findings,
    drive_radius,
    set_tension,
    tension_findings,
)
from webline.sim.branches.findings.wound_rolls import roll_name
from webline.sim.branches.laminates import layer_lengths, layer_strain
from webline.sim.branches.loop import layout as B
from webline.sim.branches.sensor_views import measured_signals
from webline.sim.branches.traction import slip_findings
from webline.sim.branches.winder import splice_findings
from webline.sim.results.run_result import RunResult
from webline.spec.branched.check import kind_of
from webline.verdict import Finding, Verdict
from webline.version import __version__

#: the notebook's view of a branched run, resolved by name (``webline.line.HTML_VIEW``)
HTML_VIEW = "webline.report.branch_report:branch_result_html"

if TYPE_CHECKING:
    from pathlib import Path

    import xarray as xr

    from webline.model.web_graph import BranchedLine
    from webline.sim.branches.plan import BranchPlan
    from webline.sim.results.events import EventStats
    from webline.sim.results.wound_roll import WoundRoll

#: the deprecated name of ``control_radius`` in a branched run's dataset (docs/branching.md
#: used it until this release): the calculator's radius (0 without one), where
#: ``control_radius`` is now the radius the drive uses, as a single-path run's; kept in
#: ``dataset``, left out of files and tables
OLD_CONTROL_RADIUS = "radius_calc"


@dataclass(frozen=True, eq=False, repr=False)
class BranchResult(RunResult):
    """Records ``rec`` (rows [t, x..., torque command...]) of a run of ``plan``; ``failure``
    says why it stopped early (None: it ran to its end). The names and methods of every run
    (``RunResult``): ``status``, ``signals``, ``metrics()``, ``summary()``, ``plot()``."""

    plan: BranchPlan
    rec: np.ndarray
    failure: str | None
    settings: dict[str, float] = field(default_factory=dict)
    time: np.ndarray = field(init=False)  #: [s] (the records' first column)

    def __post_init__(self) -> None:
        object.__setattr__(self, "time", self.rec[:, 0])

    @property
    def states(self) -> np.ndarray:
        return self.rec[:, 1:1 + self.plan.n_x]

    # --- the named views of every run (RunResult) -------------------------------------------

    @property
    def line(self) -> BranchedLine:
        return self.plan.line

    @property
    def failure_text(self) -> str:
        return self.failure or ""

    @cached_property
    def span_names(self) -> list[str]:
        return [s.name for s in self.line.spans]

    @cached_property
    def node_names(self) -> list[str]:
        return [r.name for r in self.line.spec.rollers]

    @cached_property
    def drive_names(self) -> list[str]:
        return [self.node_names[i] for i in self.line.drives]

    @cached_property
    def roll_names(self) -> list[str]:
        """Each roll as ``roller/web`` (a shaft's lanes one each)."""
        return [str(name) for name in self.dataset["roll"].values]

    @cached_property
    def tension(self) -> np.ndarray:
        """Span tensions [N] the rollers feel (the clipped stretch of linear webs,
        ``findings.web_findings.felt_records``), records x spans."""
        return felt_records(self.plan, self.time, self.states)

    @cached_property
    def tension_measured(self) -> np.ndarray:
        """Span tensions [N] as the loadcells show them, without their noise: gain T + offset,
        delayed, on a calibrated loadcell's span (``spec.sensors``), ``tension`` elsewhere."""
        if not self.plan.offsets[B.O_SENSORS]:
            return self.tension
        return self._shown[0]

    @cached_property
    def speed_measured(self) -> np.ndarray:
        """Surface speed at each node [m/s] as the encoders show it, without their noise:
        scale x speed, delayed, on a driven node (``spec.sensors``), ``speed`` elsewhere."""
        if not self.plan.offsets[B.O_SENSORS]:
            return self.surface_speed
        return self._shown[1]

    @cached_property
    def _shown(self) -> tuple[np.ndarray, np.ndarray]:
        """(tensions, speeds) the sensors show (``sensor_views.measured_signals``)."""
        return measured_signals(self.plan, self.time, self.tension, self.surface_speed)

    @cached_property
    def tension_ref(self) -> np.ndarray:
        """Tension reference of each loadcell (or dancer) span [N] as its drive sets it: the
        taper applied to the radius its controller uses (``findings.winder_states``, as
        ``Result.tension_ref``); NaN on spans without one."""
        out = np.full(self.tension.shape, np.nan)
        plan = self.plan
        for d in range(len(self.line.drives)):
            used = self.control_radius[:, d]
            first = int(plan.di[d, B.DI_CELLS])
            for c in range(first, first + int(plan.di[d, B.DI_NCELLS])):
                out[:, int(plan.cells[c, 0])] = set_tension(plan, d, c, self.time, used)
        return out

    @cached_property
    def torque(self) -> np.ndarray:
        """Motor torque of each drive [N·m], records x drives."""
        o = self.plan.offsets
        return self.states[:, o[B.O_TORQUE]:o[B.O_WEB]]

    @cached_property
    def torque_cmd(self) -> np.ndarray:
        """Motor torque command of each drive [N·m], records x drives."""
        n_x, n_d = self.plan.n_x, len(self.line.drives)
        return self.rec[:, 1 + n_x:1 + n_x + n_d]

    @cached_property
    def calculated_radius(self) -> np.ndarray:
        """Radius a diameter calculator gives each drive [m] (0: none), records x drives, as
        the loop records it."""
        return self.rec[:, 1 + self.plan.n_x + len(self.line.drives):]

    @cached_property
    def control_radius(self) -> np.ndarray:
        """Radius each drive's controllers use [m], records x drives: its calculator's where
        it has one, else its roll's (lane's) true radius, else its roller's (as
        ``Result.control_radius``; ``findings.winder_states.drive_radius``)."""
        if not len(self.line.drives):
            return self.calculated_radius
        return np.stack([drive_radius(self.plan, d, self.roll_radius, self.calculated_radius)
                         for d in range(len(self.line.drives))], axis=1)

    @cached_property
    def omega(self) -> np.ndarray:
        """Angular speed of each roller [rad/s], records x nodes."""
        off = self.plan.offsets[B.O_OMEGA]
        return self.states[:, off:off + self.plan.nodes.shape[0]]

    @cached_property
    def arm(self) -> np.ndarray:
        """Mean radius [m] at which each roller carries its web, records x nodes: a roll's
        wound radius (its first web's), a shaft's the lane its drive measures speed on, a
        roller's own radius (without an out-of-round roller's eccentricity)."""
        plan, line = self.plan, self.line
        arm = np.tile(plan.nodes[:, B.N_RADIUS], (len(self.time), 1))
        for j in reversed(range(len(line.rolls))):
            arm[:, line.rolls[j].node] = self.roll_radius[:, j]
        for d, i in enumerate(line.drives):
            if plan.di[d, B.DI_ROLL] >= 0:
                arm[:, i] = self.roll_radius[:, plan.di[d, B.DI_ROLL]]
        return arm

    @cached_property
    def surface_speed(self) -> np.ndarray:
        """Surface speed r ω of each roller [m/s], records x nodes, with an out-of-round
        roller's radius r + e cos(angle) (docs/winder.md E1) as the web sees it."""
        plan, o = self.plan, self.plan.offsets
        radius = self.arm.copy()
        for i in np.flatnonzero(plan.nodes[:, B.N_ECC]):
            angle = self.states[:, o[B.O_ANGLE] + int(plan.nodes[i, B.N_ANGLE])]
            radius[:, i] += plan.nodes[i, B.N_ECC] * np.cos(angle)
        return radius * self.omega

    @cached_property
    def drive_speed(self) -> np.ndarray:
        """Web speed each drive measures [m/s]: its roller's mean arm x ω (a shaft's: the
        lane its drive measures), records x drives."""
        drives = list(self.line.drives)
        return self.arm[:, drives] * self.omega[:, drives]

    @cached_property
    def speed_ref(self) -> np.ndarray:
        """Each drive's speed reference [m/s]: not recorded by a branched line's loop (NaN),
        so ``summary()``'s speed errors are NaN."""
        return np.full(self.torque.shape, np.nan)

    @cached_property
    def roll_radius(self) -> np.ndarray:
        """Wound radius of each roll or lane [m], records x rolls."""
        o = self.plan.offsets
        return self.states[:, o[B.O_RADIUS]:o[B.O_TORQUE]]

    @cached_property
    def events(self) -> list[EventStats]:
        """Slack (a span's stretch below zero while it is whole), torque-limit (a command at
        its drive's limit, as the verdict counts it) and slip intervals per element
        (``sim.results.events``; the branched loop's contacts stick or slip for the whole
        run, a finding of the verdict, so no slip interval)."""
        from webline.sim.results.events import event_stats

        stretch = self.states[:, :len(self.span_names)]
        return event_stats(self.time, [
            ("slack", self.span_names, (stretch < 0.0) & intact(self.plan, self.time)),
            ("torque_limit", self.drive_names,
             np.abs(self.torque_cmd) >= self.plan.df[:, B.D_LIMIT]),
            ("slip", self.node_names, np.zeros((len(self.time), len(self.node_names)), bool)),
        ])

    @cached_property
    def wound_rolls(self) -> dict[str, WoundRoll]:
        """The roll of each rewind with a ``roll_stress`` table, and of each lane on a shared
        shaft, by roll name ``roller/web`` (``findings.wound_rolls``, the chain's roll from
        this roll's own records)."""
        from webline.sim.branches.findings.wound_rolls import branch_wound_rolls

        return branch_wound_rolls(self.plan, self.time, self.roll_radius, self.tension)

    def summary(self) -> dict[str, dict[str, dict[str, float]]]:
        """Per span: tension mean, standard deviation and, with a loadcell, its errors [N];
        per drive: its largest torque [N·m] (its speed errors NaN: ``speed_ref``)
        (``webline.sim.results.metrics.run_summary``)."""
        from webline.sim.results.metrics import run_summary

        return run_summary(self)

    @cached_property
    def inertia(self) -> np.ndarray:
        """Inertia about each roll's shaft [kg·m²], records x rolls: the roller's rotating
        parts plus every roll wound on it (thesis 6.1; a lane on a clutch core: the core's
        and its own roll's), as the loop's ``plant.rhs`` sums them."""
        from webline.physics.roll import roll_inertia

        plan, line = self.plan, self.line
        rolls, radius = plan.rolls, self.roll_radius
        web = np.stack([roll_inertia(0.0, radius[:, j], rolls[j, B.R_CORE],
                                     rolls[j, B.R_WIDTH], rolls[j, B.R_RHO])
                        for j in range(len(line.rolls))], axis=1)
        out = np.empty_like(radius)
        clutch = {int(plan.cores[c, B.C_ROLL]): c for c in range(plan.cores.shape[0])}
        for j, roll in enumerate(line.rolls):
            if j in clutch:
                out[:, j] = plan.clutch[clutch[j], B.CF_INERTIA] + web[:, j]
                continue
            shared = [m for m, other in enumerate(line.rolls)
                      if other.node == roll.node and m not in clutch]
            out[:, j] = plan.nodes[roll.node, B.N_JCONST] + web[:, shared].sum(axis=1)
        return out

    @cached_property
    def dataset(self) -> xr.Dataset:
        """Signals with units and long names (attrs ``units``, ``long_name``: the names of a
        single-path run, ``sim.results.signal_attrs``): tension, its reference, slack and
        strain per span, layer tensions of laminate spans, node angular, surface and web
        speeds (and slip where no roller can slip), roll radii and inertias, torques, motor
        speed, twist and backlash contact per drive, web length in/out and stored per web.
        The verdict reads it; ``to_xarray`` adds the run's global attributes."""
        import xarray as xr  # here: a single-path run's report imports this module, not xarray

        from webline.sim.results.derived_signals import backlash_contact, transmission_twist
        from webline.sim.results.signal_attrs import signal_attrs

        plan, line = self.plan, self.plan.line
        x = self.states
        n_s, n_n = len(line.spans), plan.nodes.shape[0]
        o = plan.offsets
        ea = plan.sf[:, B.SF_EA]
        tension = self.tension
        q = x[:, o[B.O_WEB]:o[B.O_CORE]]
        lengths = span_lengths(plan, x)  # beside a dancer: L + g (y - y_set)
        held = (ea / (ea + x[:, :n_s]) if line.exact  # L/(1 + ε), else L (1 - ε) (E-6.6)
                else 1.0 - x[:, :n_s] / ea)
        stored = np.stack([np.sum(lengths[:, s] * held[:, s], axis=1)
                           for s in (line.web_spans(w) for w in range(len(line.spec.webs)))],
                          axis=1)
        layer_names, layer_values, layer_strains = [], [], []
        for span in line.spans:  # each layer's tension in the laminate at its strain
            web = line.spec.webs[span.web]
            for name in web.layers or []:
                layer_names.append(f"{span.name}/{name}")
                layer_values.append(layer_tension(plan, line.web_index[name], span.index,
                                                  x, tension[:, span.index]))
                layer_strains.append(layer_strain(plan, line.web_index[name], span.index, x))
        layer_webs, layer_in, layer_out, layer_stored = layer_lengths(plan, x, lengths)
        roll_names = [f"{line.spec.rollers[r.node].name}/{line.spec.webs[r.web].name}"
                      for r in line.rolls]
        t = self.time
        n_d = len(line.drives)
        tstate = plan.di[:, B.DI_TSTATE]
        twist = transmission_twist(tstate, x)
        motor = np.empty((len(t), n_d))  # the motor's shaft: n ω of its roller when rigid
        for d, i in enumerate(line.drives):
            state = int(tstate[d])
            motor[:, d] = x[:, state] if state >= 0 else plan.df[d, B.D_RATIO] * self.omega[:, i]

        def var(dims: tuple[str, ...], values: np.ndarray, name: str,
                **attrs: str) -> xr.Variable:
            return xr.Variable(("time", *dims), values, signal_attrs(name) | attrs)

        def layers(values: list[np.ndarray]) -> np.ndarray:
            return np.array(values).T.reshape(len(t), len(layer_names))

        slips = bool(np.any(plan.nodes[:, B.N_TRACTION]))  # (its slip is not recorded)
        data = {
            "tension": var(("span",), tension, "tension"),
            "tension_ref": var(("span",), self.tension_ref, "tension_ref"),
            "slack": var(("span",), ((x[:, :n_s] < 0.0) & intact(plan, t)).astype(np.int8),
                         "slack"),
            "strain": var(("span",), x[:, :n_s] / ea, "strain"),
            "layer_tension": var(("layer_span",), layers(layer_values), "layer_tension"),
            "layer_strain": var(("layer_span",), layers(layer_strains), "layer_strain"),
            "omega": var(("node",), self.omega, "omega"),
            "speed": var(("node",), self.surface_speed, "speed", **({"long_name": (
                "roller surface speed (the web's slip over a traction roller is not "
                "recorded)")} if slips else {})),
            "surface_speed": var(("node",), self.surface_speed, "surface_speed"),
            "radius": var(("roll",), self.roll_radius, "radius",
                          long_name="wound radius of a roll or lane"),
            "inertia": var(("roll",), self.inertia, "inertia"),
            "torque": var(("drive",), self.torque, "torque"),
            "torque_cmd": var(("drive",), self.torque_cmd, "torque_cmd"),
            "motor_speed": var(("drive",), motor, "motor_speed"),
            "twist": var(("drive",), twist, "twist"),
            "contact": var(("drive",), backlash_contact(
                tstate, plan.df[:, B.D_GAPNEG], plan.df[:, B.D_GAPPOS], twist), "contact"),
            "control_radius": var(("drive",), self.control_radius, "control_radius"),
            "web_in": var(("web",), q[:, 0::2], "web_in"),
            "web_out": var(("web",), q[:, 1::2], "web_out"),
            "web_stored": var(("web",), stored, "web_stored"),
            "layer_in": var(("layer_web",), layer_in, "layer_in"),
            "layer_out": var(("layer_web",), layer_out, "layer_out"),
            "layer_stored": var(("layer_web",), layer_stored, "layer_stored"),
            "core_omega": var(("core",), x[:, o[B.O_CORE]:o[B.O_ANGLE]], "core_omega"),
        }
        if not slips:  # no roller the web can slip over: it sticks at every node
            zeros = np.zeros((len(t), n_n))
            data |= {"slipping": var(("node",), zeros.astype(np.int8), "slipping"),
                     "slip_velocity": var(("node",), zeros, "slip_velocity"),
                     "slip_power": var(("node",), zeros, "slip_power")}
        if plan.offsets[B.O_SENSORS]:  # what the calibrated sensors show (spec.sensors)
            data["tension_measured"] = var(("span",), self.tension_measured,
                                           "tension_measured")
            data["speed_measured"] = var(("node",), self.speed_measured, "speed_measured")
        if np.any(tstate >= 0):  # compliant transmissions: the motor at the load shaft
            data["motor_omega"] = var(("drive",), train_motor_omega(plan.offsets, plan.di,
                                                                    plan.df, x), "motor_omega")
        coords = {"time": ("time", t, {"units": "s"}),
                  "span": [s.name for s in line.spans],
                  "span_web": ("span", [line.spec.webs[s.web].name for s in line.spans]),
                  "layer_span": layer_names, "layer_web": layer_webs,
                  "node": [r.name for r in line.spec.rollers],
                  "roll": roll_names, "drive": [line.spec.rollers[i].name for i in line.drives],
                  "core": [roll_names[j] for j in plan.cores[:, B.C_ROLL]],
                  "web": [w.name for w in line.spec.webs]}
        data[OLD_CONTROL_RADIUS] = var(("drive",), self.calculated_radius, "control_radius",
                                       long_name="radius a diameter calculator gives its "
                                       "drive (0: none)",
                                       deprecated="control_radius: the radius the drive uses")
        dancers = dancer_nodes(line)
        if dancers:  # (only where there are: the built-in lines' records stay as they were)
            data["dancer_position"] = var(("dancer",), x[:, o[B.O_DANCER]:o[B.O_DANCER_END]:2],
                                          "dancer_position")
            coords["dancer"] = [line.spec.rollers[i].name for i in dancers]
        return xr.Dataset(data, coords, attrs={
            "line": line.name, "scenario": line.scenario or "", "webline_version": __version__,
            "failure": self.failure or "", **{k: float(v) for k, v in self.settings.items()}})

    def _repr_html_(self) -> str:
        """A notebook's view: headline, status and the verdict per web and lane, drawn by
        ``HTML_VIEW``."""
        from webline.model.web_graph import _view

        return str(_view(HTML_VIEW)(self))

    def to_xarray(self) -> xr.Dataset:
        """``dataset`` with a single-path run's global attributes (CF conventions, title,
        history, the resolved line file ``line_spec_toml``, status, message, verdict, the
        settings as ``setting_NAME``: ``sim.results.result_dataset.result_attrs``), its
        scenario and failure, and each coordinate's ``long_name``. A new Dataset each call;
        ``signals`` keeps one."""
        from webline.sim.results.result_dataset import (
            COORD_NAMES,
            TIME_ATTRS,
            WEB_ROLL_NAME,
            result_attrs,
        )

        ds = self.dataset.copy()
        ds.attrs = {"scenario": ds.attrs["scenario"], "failure": ds.attrs["failure"],
                    **result_attrs(self)}
        for name in ds.coords:
            ds[name].attrs = (dict(TIME_ATTRS) if name == "time" else
                              {"long_name": WEB_ROLL_NAME if name == "roll"
                               else COORD_NAMES[str(name)]})
        return ds

    @property
    def _filed(self) -> xr.Dataset:
        """The dataset as files and tables give it (without the deprecated names)."""
        return self.signals.drop_vars(OLD_CONTROL_RADIUS)

    def to_dataframe(self) -> Any:
        """One row per record indexed by ``time`` [s], one column per signal and element
        (``tension[film_zone]``, ``web_stored[film]``), SI, each column's unit in
        ``.attrs["units"]`` (``sim.results.dataset_files.dataset_frame``)."""
        from webline.sim.results.dataset_files import dataset_frame

        return dataset_frame(self._filed)

    def to_netcdf(self, path: str | Path, precision: Literal["float64", "float32"] = "float64"
                  ) -> Path:
        """Write every signal to NetCDF-4, compressed and chunked along time as a single-path
        run's file, float signals as ``precision`` (time stays float64), the resolved line
        file in attribute ``line_spec_toml`` (TOML, SI), each wound roll per layer in the group
        ``wound_roll/ROLLER/WEB`` (``wound_rolls``), atomically. Returns the path
        (``sim.results.dataset_files``)."""
        from webline.sim.results.dataset_files import write_dataset

        filed = self._filed
        rolls = {f"wound_roll/{name}": roll.to_xarray()
                 for name, roll in self.wound_rolls.items()}
        return write_dataset(filed, path, "netcdf", precision, rolls)

    def to_csv(self, path: str | Path) -> Path:
        """Write one column per signal and element (``tension[film_zone] [N]`` ...), time
        first, atomically. Returns the path."""
        from webline.sim.results.dataset_files import write_dataset

        return write_dataset(self._filed, path, "csv")

    @cached_property
    def verdict(self) -> Verdict:
        """Per web and lane: slack (tension 0 in a span) and tension above the web's
        ``tension_limit`` are warnings; so is a drive's command at its torque limit; a run
        stopped early is a failure."""
        line = self.plan.line
        findings = []
        if self.failure is not None:
            kind = "nonfinite" if "finite" in self.failure else (
                "unwind_empty" if "unwind" in self.failure else "interrupted"
                if "interrupted" in self.failure else "strength_exceeded"
                if "strength" in self.failure else "diverged")
            level: Literal["failed", "interrupted"] = (
                "interrupted" if kind == "interrupted" else "failed")
            findings.append(Finding(level, kind, line.name, f"the run stopped: "
                                    f"{self.failure}", float(self.time[-1]) if len(
                                        self.time) else 0.0))
        for w, web in enumerate(line.spec.webs):
            spans = line.web_spans(w)
            tension = self.tension[:, spans]
            taut = np.where(intact(self.plan, self.time)[:, spans], tension, np.inf)
            label = f"{kind_of(web)} {web.name}"  # (a broken span: the break's finding)
            slack = np.nonzero(np.any(taut <= 0.0, axis=1))[0]
            if len(slack):
                findings.append(Finding("warning", "slack", web.name, f"{label} goes slack at "
                                        f"t = {self.time[slack[0]]:.4g} s", float(
                                            self.time[slack[0]])))
            material = web.web or (line.spec.web if kind_of(web) == "web" else None)
            limit = material.tension_limit if material is not None else None
            if limit is not None and np.max(tension) > limit:
                first = int(np.nonzero(np.any(tension > limit, axis=1))[0][0])
                findings.append(Finding("warning", "tension_limit", web.name,
                                        f"{label} exceeds its tension limit {limit:.4g} N "
                                        f"(max {np.max(tension):.4g} N)",
                                        float(self.time[first])))
        findings += splice_findings(line, self.plan.dt, self.time, self.tension)
        findings += yield_findings(self.plan, self.time, self.states)
        findings += compressed_findings(self.plan, self.time, self.states)
        findings += break_findings(self.plan, self.time, self.arm * self.omega, self.settings,
                                   self.tension)
        findings += slip_findings(self.plan.line, self.plan.nodes, self.plan.si)
        findings += end_stop_findings(self.plan, self.time, self.states)
        findings += tension_findings(self.plan, self.time, self.tension,  # [checks]
                                     self.roll_radius, self.calculated_radius)
        findings += diameter_findings(self.plan, self.time, self.roll_radius,
                                      self.calculated_radius)
        rolls = self.wound_rolls
        for j, roll in enumerate(line.rolls):  # each roll's under its web or lane (its
            wound = rolls.get(roll_name(self.plan, j))  # message names the roll)
            if wound is not None:
                owner = line.spec.webs[roll.web].name
                findings += [replace(f, where=owner) for f in wound.findings()]
        limits = self.plan.df[:, B.D_LIMIT]
        for d, name in enumerate(self.drive_names):  # a drive at its torque limit
            at_limit = np.nonzero(np.abs(self.torque_cmd[:, d]) >= limits[d])[0]
            if len(at_limit):
                when = float(self.time[at_limit[0]])
                findings.append(Finding(
                    "warning", "torque_limit", str(name), f"drive {name} at its torque limit "
                    f"{limits[d]:.4g} N·m in {len(at_limit)} of {len(self.time)} records, first "
                    f"at t = {when:.4g} s", when, {"records": len(at_limit)}))
        return Verdict.of(findings)

    def web_summary(self) -> list[dict[str, object]]:
        """Per web: its kind, tension min/max/final per span [N] (a loadcell's also its largest
        deviation from its reference) and the drift of its length balance [m] (a cut web's
        without its jump at the break: ``break_verdict.without_cut_jump``)."""
        line = self.plan.line
        ds = self.dataset
        out = []
        for w, web in enumerate(line.spec.webs):
            spans = line.web_spans(w)
            balance = without_cut_jump(self.plan, self.time, ds["web_stored"].values[:, w]
                                       + ds["web_out"].values[:, w]
                                       - ds["web_in"].values[:, w], w)
            table: dict[str, dict[str, float]] = {}
            for k in spans:
                tension = ds["tension"].values[:, k]
                row = {"min_N": float(tension.min()), "max_N": float(tension.max()),
                       "final_N": float(tension[-1])}
                cell = np.nonzero(self.plan.cells[:, 0] == k)[0]
                if len(cell):  # a loadcell: its deviation from its reference over the run
                    p = int(self.plan.cells[cell[0], 1])
                    ref = np.array([self.plan.profile(p, t) for t in self.time])
                    row["max_deviation_N"] = float(np.max(np.abs(tension - ref)))
                table[line.spans[k].name] = row
            out.append({
                "web": web.name, "kind": kind_of(web), "spans": table,
                "length_balance_drift_m": float(np.max(np.abs(balance - balance[0]))),
            })
        return out
