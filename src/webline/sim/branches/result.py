"""The result of a branched line's run: an xarray Dataset of named signals and a verdict per
web and lane computed from them."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from webline.sim.branches.dancer_views import end_stop_findings, span_lengths
from webline.sim.branches.dancers import dancer_nodes
from webline.sim.branches.drives.drive_trains import train_signals
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
#: used it until this release); kept in ``dataset``, left out of files and tables
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
        return self.dataset["tension"].values

    @cached_property
    def tension_measured(self) -> np.ndarray:
        """Span tensions [N] as the loadcells show them, without their noise: gain T + offset,
        delayed, on a calibrated loadcell's span (``spec.sensors``), ``tension`` elsewhere."""
        if not self.plan.offsets[B.O_SENSORS]:
            return self.tension
        return self.dataset["tension_measured"].values

    @cached_property
    def speed_measured(self) -> np.ndarray:
        """Surface speed at each node [m/s] as the encoders show it, without their noise:
        scale x speed, delayed, on a driven node (``spec.sensors``), ``speed`` elsewhere."""
        if not self.plan.offsets[B.O_SENSORS]:
            return self.dataset["speed"].values
        return self.dataset["speed_measured"].values

    @cached_property
    def tension_ref(self) -> np.ndarray:
        """Tension reference of each loadcell (or dancer) span [N] as its drive sets it: the
        taper applied to the radius its controller uses (``findings.winder_states``, as
        ``Result.tension_ref``); NaN on spans without one."""
        out = np.full(self.tension.shape, np.nan)
        plan, ds = self.plan, self.dataset
        for d in range(len(self.line.drives)):
            used = drive_radius(plan, d, ds["radius"].values, ds["control_radius"].values)
            first = int(plan.di[d, B.DI_CELLS])
            for c in range(first, first + int(plan.di[d, B.DI_NCELLS])):
                out[:, int(plan.cells[c, 0])] = set_tension(plan, d, c, self.time, used)
        return out

    @cached_property
    def torque(self) -> np.ndarray:
        return self.dataset["torque"].values

    @cached_property
    def torque_cmd(self) -> np.ndarray:
        return self.dataset["torque_cmd"].values

    @cached_property
    def drive_speed(self) -> np.ndarray:
        """Surface speed of each drive's roller [m/s] (a shaft's: the lane its drive
        measures)."""
        return self.dataset["speed"].values[:, self.line.drives]

    @cached_property
    def speed_ref(self) -> np.ndarray:
        """Each drive's speed reference [m/s]: not recorded by a branched line's loop (NaN),
        so ``summary()``'s speed errors are NaN."""
        return np.full(self.torque.shape, np.nan)

    @cached_property
    def roll_radius(self) -> np.ndarray:
        return self.dataset["radius"].values

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

        ds = self.dataset
        return branch_wound_rolls(self.plan, self.time, ds["radius"].values,
                                  ds["tension"].values)

    def summary(self) -> dict[str, dict[str, dict[str, float]]]:
        """Per span: tension mean, standard deviation and, with a loadcell, its errors [N];
        per drive: its largest torque [N·m] (its speed errors NaN: ``speed_ref``)
        (``webline.sim.results.metrics.run_summary``)."""
        from webline.sim.results.metrics import run_summary

        return run_summary(self)

    @cached_property
    def dataset(self) -> xr.Dataset:
        """Signals with units (attrs ``units``): tension and strain per span, layer tensions of
        laminate spans, node angular and surface speeds, roll radii, torques per drive, web
        length in/out and stored per web."""
        import xarray as xr  # here: a single-path run's report imports this module, not xarray

        plan, line = self.plan, self.plan.line
        x = self.states
        n_s, n_n, n_d = len(line.spans), plan.nodes.shape[0], len(line.drives)
        o = plan.offsets
        ea = plan.sf[:, B.SF_EA]
        tension = felt_records(plan, self.time, x)  # (the clipped stretch of linear webs)
        omega = x[:, o[B.O_OMEGA]:o[B.O_OMEGA] + n_n]
        radius = x[:, o[B.O_RADIUS]:o[B.O_TORQUE]]
        torque = x[:, o[B.O_TORQUE]:o[B.O_WEB]]
        q = x[:, o[B.O_WEB]:o[B.O_CORE]]
        core_omega = x[:, o[B.O_CORE]:o[B.O_ANGLE]]
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
        drives = [line.spec.rollers[i].name for i in line.drives]
        arm = np.tile(plan.nodes[:, B.N_RADIUS], (len(x), 1))  # a roll: its first web's radius
        for j in reversed(range(len(line.rolls))):
            arm[:, line.rolls[j].node] = radius[:, j]
        for d, i in enumerate(line.drives):  # a shaft: the lane its drive measures speed on
            if plan.di[d, B.DI_ROLL] >= 0:
                arm[:, i] = radius[:, plan.di[d, B.DI_ROLL]]
        t = self.time

        def var(dims: tuple[str, ...], values: np.ndarray, units: str, text: str) -> xr.Variable:
            return xr.Variable(("time", *dims), values, {"units": units, "long_name": text})

        data = {
            "tension": var(("span",), tension, "N", "span tension"),
            "strain": var(("span",), x[:, :n_s] / ea, "1", "span strain EA·ε / EA"),
            "layer_tension": var(("layer_span",), np.array(layer_values).T.reshape(
                len(t), len(layer_names)), "N", "layer tension in a laminate span"),
            "layer_strain": var(("layer_span",), np.array(layer_strains).T.reshape(
                len(t), len(layer_names)), "1", "layer's own strain in a laminate span"),
            "omega": var(("node",), omega, "rad/s", "roller angular speed"),
            "speed": var(("node",), arm * omega, "m/s", "surface speed of a roller (of a "
                         "shaft: the lane its drive measures)"),
            "radius": var(("roll",), radius, "m", "wound radius of a roll or lane"),
            "torque": var(("drive",), torque, "N*m", "motor torque"),
            "torque_cmd": var(("drive",), self.rec[:, 1 + plan.n_x:1 + plan.n_x + n_d], "N*m",
                              "torque command"),
            "control_radius": var(("drive",), self.rec[:, 1 + plan.n_x + n_d:], "m",
                                  "radius a diameter calculator gives its drive (0: none)"),
            "web_in": var(("web",), q[:, 0::2], "m", "unstrained web in at the path's start"),
            "web_out": var(("web",), q[:, 1::2], "m", "unstrained web out at the path's end"),
            "web_stored": var(("web",), stored, "m", "unstrained web in the path's spans"),
            "layer_in": var(("layer_web",), layer_in, "m", "unstrained layer in at its "
                            "laminate's start"),
            "layer_out": var(("layer_web",), layer_out, "m", "unstrained layer out at its "
                             "laminate's end"),
            "layer_stored": var(("layer_web",), layer_stored, "m", "unstrained layer in its "
                                "laminate's spans"),
            "core_omega": var(("core",), core_omega, "rad/s",
                              "angular speed of a lane's core on a differential shaft"),
        }
        if plan.offsets[B.O_SENSORS]:  # what the calibrated sensors show (spec.sensors)
            shown_t, shown_v = measured_signals(plan, t, tension, arm * omega)
            data["tension_measured"] = var(("span",), shown_t, "N", "span tension as its "
                                           "loadcell shows it (gain, offset, delay; no noise)")
            data["speed_measured"] = var(("node",), shown_v, "m/s", "surface speed as its "
                                         "drive's encoder shows it (scale, delay; no noise)")
        if np.any(plan.di[:, B.DI_TSTATE] >= 0):  # compliant transmissions (drive_trains)
            data.update(train_signals(plan.offsets, plan.di, plan.df, x, var))
        coords = {"time": ("time", t, {"units": "s"}),
                  "span": [s.name for s in line.spans],
                  "span_web": ("span", [line.spec.webs[s.web].name for s in line.spans]),
                  "layer_span": layer_names, "layer_web": layer_webs,
                  "node": [r.name for r in line.spec.rollers],
                  "roll": roll_names, "drive": drives,
                  "core": [roll_names[j] for j in plan.cores[:, B.C_ROLL]],
                  "web": [w.name for w in line.spec.webs]}
        data[OLD_CONTROL_RADIUS] = data["control_radius"].copy()
        data[OLD_CONTROL_RADIUS].attrs["deprecated"] = "renamed control_radius"
        dancers = dancer_nodes(line)
        if dancers:  # (only where there are: the built-in lines' records stay as they were)
            data["dancer_position"] = var(("dancer",), x[:, o[B.O_DANCER]:o[B.O_DANCER_END]:2], "m",
                                          "dancer carriage position y (0 .. travel)")
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
        return self.dataset

    @property
    def _filed(self) -> xr.Dataset:
        """The dataset as files and tables give it (without the deprecated names)."""
        return self.dataset.drop_vars(OLD_CONTROL_RADIUS)

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
        file in attribute ``line_spec`` (TOML, SI), each wound roll per layer in the group
        ``wound_roll/ROLLER/WEB`` (``wound_rolls``), atomically. Returns the path
        (``sim.results.dataset_files``)."""
        from webline.sim.results.dataset_files import write_dataset
        from webline.spec.load import dump_spec

        filed = self._filed.assign_attrs(line_spec=dump_spec(self.plan.line.spec))
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
        ds = self.dataset
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
            tension = ds["tension"].values[:, spans]
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
        findings += splice_findings(line, self.plan.dt, self.time, ds["tension"].values)
        findings += yield_findings(self.plan, self.time, self.states)
        findings += compressed_findings(self.plan, self.time, self.states)
        findings += break_findings(self.plan, self.time, ds["speed"].values, self.settings,
                                   ds["tension"].values)
        findings += slip_findings(self.plan.line, self.plan.nodes, self.plan.si)
        findings += end_stop_findings(self.plan, self.time, self.states)
        findings += tension_findings(self.plan, self.time, ds["tension"].values,  # [checks]
                                     ds["radius"].values, ds["control_radius"].values)
        findings += diameter_findings(self.plan, self.time, ds["radius"].values,
                                      ds["control_radius"].values)
        rolls = self.wound_rolls
        for j, roll in enumerate(line.rolls):  # each roll's under its web or lane (its
            wound = rolls.get(roll_name(self.plan, j))  # message names the roll)
            if wound is not None:
                owner = line.spec.webs[roll.web].name
                findings += [replace(f, where=owner) for f in wound.findings()]
        limits = self.plan.df[:, B.D_LIMIT]
        for d, name in enumerate(ds["drive"].values):  # a drive at its torque limit
            at_limit = np.nonzero(np.abs(ds["torque_cmd"].values[:, d]) >= limits[d])[0]
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
