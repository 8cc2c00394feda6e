"""Simulation results: named signals over time, summaries, events and writers."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from webline.sim.core.plan import Plan
from webline.sim.elements import layout as L
from webline.sim.results.events import SlackEvent
from webline.sim.results.failure import Failure
from webline.sim.results.metrics import run_summary
from webline.sim.results.result_dataset import result_variables, to_xarray
from webline.sim.results.result_files import Precision, signal_frame, write_csv, write_netcdf
from webline.sim.results.run_result import RunResult

if TYPE_CHECKING:
    import xarray as xr

    from webline.sim.linear.roll_modes import RollModes
    from webline.sim.results.events import EventStats
    from webline.sim.results.wound_roll import WoundRoll
    from webline.verdict import Verdict



@dataclass(frozen=True, repr=False)
class Result(RunResult):
    """What ``webline.simulate`` computed for a single-path line (``RunResult``'s names and
    methods). Arrays are SI; index signals by name via ``signals`` or the properties below."""

    plan: Plan
    time: np.ndarray  #: [s]
    states: np.ndarray  #: plant state per record, columns ``plan.state_names``
    torque_cmd: np.ndarray  #: [N·m] per drive
    speed_feedforward: np.ndarray  #: [m/s] per drive (line speed x draw + ripple)
    trim: np.ndarray  #: [m/s] per drive (tension-loop output)
    equilibrium_input: np.ndarray  #: [N·m] per drive (decentralized controllers; else 0)
    friction_estimate: np.ndarray  #: adaptive controllers' friction estimate [N·m·s] per drive
    control_radius: np.ndarray  #: radius each drive's controller uses [m] (calculated or true)
    slipping: np.ndarray  #: stick/slip state per node (0 stuck, 1 slipping), held per tick
    #: per record and drive, the MRAC's adapted gains k̂ on the tension deviation [m] and on
    #: the speed deviation [N·s] and its bias ĉ [N·m] (thesis 6.68, E-6.14); NaN for the drives
    #: without an MRAC. Shape (records, drives, 3)
    mrac_gains: np.ndarray
    failure: Failure | None = None  #: why the run stopped early (None: it ran to the end)
    settings: dict[str, float] = field(default_factory=dict)
    #: the web-break monitor at the end (docs/winder.md W5): time [s] it detected a break
    #: (-1: none) and how (``layout.BREAK_TENSION``, ``BREAK_DANCER``, ``BREAK_DIAMETER``)
    break_monitor: tuple[float, int] = (-1.0, 0)

    # --- verdict -------------------------------------------------------------------------

    @cached_property
    def events(self) -> list[EventStats]:
        """Slack, torque-limit, slip, backlash and tension-limit intervals, per element
        (``webline.sim.results.events``): a command within ``TORQUE_LIMIT_RTOL`` of its limit is at
        it
        (the controllers clip to the limit exactly); NaN contact means no backlash."""
        from webline.sim.results.events import TORQUE_LIMIT_RTOL, event_stats

        limit = self.line.spec.web.tension_limit
        at_limit = self.plan.drives[:, L.D_LIMIT] * (1.0 - TORQUE_LIMIT_RTOL)
        traction = self.plan.nodes[:, L.N_TRACTION] != 0.0
        return event_stats(self.time, [
            ("slack", self.span_names, self.stretch < 0.0),
            *([("tension_limit", self.span_names, self.tension > limit)]
              if limit is not None else []),
            ("torque_limit", self.drive_names, np.abs(self.torque_cmd) >= at_limit),
            ("slip", self.node_names, (self.slipping != 0) & traction),
            ("backlash_open", self.drive_names, self.contact == 0.0),
        ])

    @cached_property
    def verdict(self) -> Verdict:
        """The run's verdict: its failure, its events, its splices' slack, strain beyond the
        web's yield and the linear stability of the line at ``analysis_time``
        (``webline.sim.results.findings``)."""
        from webline.sim.results.findings import run_verdict
        from webline.sim.results.splice_findings import splice_findings
        from webline.sim.results.winder_findings import after_stop_from_records, intact_loadcells
        from webline.sim.results.winder_states import winder_state_findings
        from webline.sim.results.yield_findings import yield_findings

        extra = splice_findings(self.line, self.plan.dt, self.time, self.tension)
        extra += winder_state_findings(self)
        extra += yield_findings(self.line, self.time, self.stretch)
        if self.roll_modes is not None:  # a run across a roll: its modes along the way
            extra += self.roll_modes.findings()
        if self.wound_roll is not None:  # the rewind's roll stresses (docs/wound-roll.md)
            extra += self.wound_roll.findings()
        end = float(self.time[-1]) if len(self.time) else 0.0
        intact = intact_loadcells(self.plan)
        return run_verdict(self.plan, self.failure, [e.summary() for e in self.events], end,
                           self.break_monitor,
                           after_stop_from_records(self.time,
                                                   self.surface_speed[:, list(self.line.drives)],
                                                   self.drive_names, self.tension[:, intact],
                                                   [self.line.span_name(k) for k in intact]),
                           extra)

    @cached_property
    def wound_rolls(self) -> dict[str, WoundRoll]:
        """The rewind's wound roll at the end of the run, by the rewind's name (empty without
        a ``roll_stress`` table): wound-on tension per layer, pressure and hoop stress
        (``webline.sim.results.wound_roll``)."""
        from webline.sim.results.wound_roll import run_wound_roll

        roll = run_wound_roll(self)
        return {} if roll is None else {roll.where: roll}

    @cached_property
    def roll_modes(self) -> RollModes | None:
        """The closed-loop modes along the run's recorded roll radii, for a run across a roll
        (``webline.sim.linear.roll_modes.run_roll_modes``), else None."""
        from webline.sim.linear.roll_modes import run_roll_modes

        if np.any(self.plan.drives[:, L.D_FAMILY] == L.FAMILY_USER):
            return None  # a user's controller has no linear model
        rolls = self._block(2, 2)
        return run_roll_modes(self.line, self.time, rolls[:, 0], rolls[:, 1])

    @property
    def failure_text(self) -> str:
        """Why the run stopped early ('' if it ran to its end)."""
        return "" if self.failure is None else self.failure.message

    # --- named views -------------------------------------------------------------------

    @property
    def line(self):
        return self.plan.line

    @cached_property
    def roll_names(self) -> list[str]:
        """The unwind and the rewind (``roll_radius``'s columns)."""
        return [self.node_names[0], self.node_names[-1]]

    @cached_property
    def roll_radius(self) -> np.ndarray:
        """Unwind and rewind radius [m], records x 2."""
        return self._block(2, 2)

    @cached_property
    def span_names(self) -> list[str]:
        return [self.line.span_name(k) for k in range(self.line.n_spans)]

    @cached_property
    def node_names(self) -> list[str]:
        return [self.line.node_name(i) for i in range(self.line.n_nodes)]

    @cached_property
    def drive_names(self) -> list[str]:
        return [self.line.node_name(i) for i in self.line.drives]

    def _block(self, offset_index: int, count: int) -> np.ndarray:
        start = int(self.plan.offsets[offset_index])
        return self.states[:, start:start + count]

    @cached_property
    def stretch(self) -> np.ndarray:
        """Span stretch force AE·strain [N]; negative while a span is slack."""
        return self.states[:, : self.line.n_spans]

    @cached_property
    def tension(self) -> np.ndarray:
        """Span tensions [N], shape (time, span): what the rollers feel (a Kelvin-Voigt
        span's stretch plus its damper, ``sim.core.viscoelastic``)."""
        if self.plan.offsets[L.O_KV]:
            from webline.sim.core.viscoelastic import felt_tension

            return felt_tension(self.plan, self.time, self.states, self.slipping)
        return np.maximum(self.stretch, 0.0)

    @cached_property
    def tension_measured(self) -> np.ndarray:
        """Span tensions [N] as the loadcells show them, without their noise: gain T +
        offset, delayed, on a calibrated loadcell's span (``spec.sensors``), ``tension``
        elsewhere.
        ``tension`` stays the web's true tension."""
        if not self.plan.offsets[L.O_SENSORS]:
            return self.tension
        from webline.sim.elements.sensor_loop import measured_tensions

        return measured_tensions(self.line, self.plan.drives, self.plan.dt, self.time,
                                 self.tension)

    @cached_property
    def tension_ref(self) -> np.ndarray:
        """Tension reference of each loadcell span [N] (NaN on spans without a loadcell), the
        rewind's taper applied to the diameter its controller uses (the calculated one where
        the roll has a calculator, ``control_radius``; docs/winder.md W1), as it sets it."""
        from webline.sim.core.winder import tension_references

        return tension_references(self.line, self.time, self.control_radius)

    @cached_property
    def omega(self) -> np.ndarray:
        """Angular speed of each node [rad/s]."""
        return self._block(1, self.line.n_nodes)

    @cached_property
    def radius(self) -> np.ndarray:
        """Effective radius of each node [m] over time (roll radii, eccentric rollers)."""
        nodes = self.plan.nodes
        out = np.tile(nodes[:, L.N_RADIUS], (len(self.time), 1))
        rolls = self._block(2, 2)
        out[:, 0], out[:, -1] = rolls[:, 0], rolls[:, 1]
        for i in range(self.line.n_nodes):
            state = int(nodes[i, L.N_ECCSTATE])
            if state >= 0:
                out[:, i] += nodes[i, L.N_ECC] * np.cos(self.states[:, state])
        return out

    @cached_property
    def surface_speed(self) -> np.ndarray:
        """Surface speed r ω of each node [m/s]."""
        return self.radius * self.omega

    @cached_property
    def slip_velocity(self) -> np.ndarray:
        """Surface speed minus web speed at each node [m/s] (0 where the web adheres)."""
        from webline.sim.results.derived_signals import slip_velocities

        return slip_velocities(self.plan, self.tension, self.surface_speed, self.slipping)

    @cached_property
    def slip_power(self) -> np.ndarray:
        """Power dissipated by slip at each node [W]: (T_in - T_out)·s, never negative."""
        out = np.zeros_like(self.omega)
        out[:, 1:-1] = (self.tension[:, :-1] - self.tension[:, 1:]) * self.slip_velocity[:, 1:-1]
        return out

    @cached_property
    def dancer_names(self) -> list[str]:
        """Names of the line's dancers, in web order."""
        from webline.sim.core.dancer import dancer_nodes

        return [self.line.node_name(i) for i in dancer_nodes(self.line)]

    @cached_property
    def dancer_position(self) -> np.ndarray:
        """Carriage position of each dancer [m] (records x dancers; 0 and its stroke are the
        end stops), as its position sensor reads it."""
        names = self.plan.state_names
        return self.states[:, [names.index(f"{d}.position") for d in self.dancer_names]]

    @cached_property
    def speed(self) -> np.ndarray:
        """Web speed at each node [m/s]: the surface speed less any slip."""
        return self.surface_speed - self.slip_velocity

    @cached_property
    def speed_measured(self) -> np.ndarray:
        """Web speed at each node [m/s] as the encoders show it, without their noise: its
        scale x ``speed``, delayed, on a driven node with a calibrated encoder
        (``spec.sensors``),
        ``speed`` elsewhere."""
        if not self.plan.offsets[L.O_SENSORS]:
            return self.speed
        from webline.sim.elements.sensor_loop import measured_speeds

        return measured_speeds(self.line, self.plan.drives, self.plan.dt, self.time,
                               self.speed)

    @cached_property
    def speed_ref(self) -> np.ndarray:
        """Speed reference each drive's speed loop tracks [m/s] (feedforward + trim)."""
        return self.speed_feedforward + self.trim

    @cached_property
    def drive_speed(self) -> np.ndarray:
        """Measured web speed of each drive's node [m/s] (nominal radius for rollers)."""
        nodes = self.plan.nodes
        out = np.empty_like(self.trim)
        for d, i in enumerate(self.line.drives):
            radius = self.radius[:, i] if i in (0, self.line.n_nodes - 1) else nodes[i, L.N_RADIUS]
            out[:, d] = radius * self.omega[:, i]
        return out

    @property
    def has_mrac(self) -> np.ndarray:
        """Which drives run the decentralized MRAC (bool per drive)."""
        return self.plan.drives[:, L.D_FAMILY] == L.FAMILY_MRAC

    @cached_property
    def torque(self) -> np.ndarray:
        """Motor torque of each drive [N·m]."""
        return self._block(3, len(self.line.drives))

    @cached_property
    def motor_speed(self) -> np.ndarray:
        """Angular speed of each drive's motor [rad/s] (n x roller speed for a rigid one)."""
        out = np.empty_like(self.torque)
        for d, i in enumerate(self.line.drives):
            state = int(self.plan.drives[d, L.D_TSTATE])
            ratio = self.plan.drives[d, L.D_RATIO]
            out[:, d] = self.states[:, state] if state >= 0 else ratio * self.omega[:, i]
        return out

    @cached_property
    def twist(self) -> np.ndarray:
        """Twist θm/n - θL of each compliant transmission [rad] (NaN for rigid drives)."""
        from webline.sim.results.derived_signals import transmission_twist

        return transmission_twist(self.plan.drives[:, L.D_TSTATE], self.states)

    @cached_property
    def contact(self) -> np.ndarray:
        """Backlash contact of each drive: +1 forward flank, -1 backward flank, 0 in the gap
        (NaN for drives without backlash)."""
        from webline.sim.results.derived_signals import backlash_contact

        drives = self.plan.drives
        return backlash_contact(drives[:, L.D_TSTATE], drives[:, L.D_GAPNEG],
                                drives[:, L.D_GAPPOS], self.twist)

    @cached_property
    def inertia(self) -> np.ndarray:
        """Unwind and rewind inertia at the roll shaft [kg·m²], shape (time, 2)."""
        from webline.physics.roll import roll_inertia

        web = self.line.spec.web
        out = np.empty((len(self.time), 2))
        for col, i in enumerate((0, self.line.n_nodes - 1)):
            out[:, col] = roll_inertia(self.plan.nodes[i, L.N_JCONST], self.radius[:, i],
                                       self.plan.nodes[i, L.N_CORE], web.width,
                                       self.plan.roll_density(i))
        return out

    @cached_property
    def web_unwound(self) -> np.ndarray:
        """Unstrained web that has left the unwind [m]."""
        return self._block(5, 2)[:, 0]

    @cached_property
    def web_rewound(self) -> np.ndarray:
        """Unstrained web that has reached the rewind [m]."""
        return self._block(5, 2)[:, 1]

    @cached_property
    def web_stored(self) -> np.ndarray:
        """Unstrained web held in the spans [m]: L/(1 + ε) with exact transport, L (1 - ε)
        with the thesis's first-order one (``physics.span.stored_length``)."""
        ea = self.line.ea
        if self.line.exact:
            return (self.span_lengths * ea / (ea + self.stretch)).sum(axis=1)
        return (self.span_lengths * (1.0 - self.stretch / ea)).sum(axis=1)

    @cached_property
    def span_lengths(self) -> np.ndarray:
        """Length of every span over time [m]: as in the file, plus the excursion of a dancer
        at either end from its set position (``kernel.span_motion``)."""
        from webline.sim.results.derived_signals import span_lengths

        return span_lengths(self.plan, self.states)

    @cached_property
    def slack_events(self) -> list[SlackEvent]:
        """Every interval in which a span carried no tension."""
        from webline.sim.results.events import slack_intervals

        return slack_intervals(self.time, self.stretch < 0.0, self.span_names)

    # --- summaries and export ------------------------------------------------------------

    def summary(self) -> dict[str, dict[str, dict[str, float]]]:
        """Per span: tension mean, standard deviation and largest error [N]; per drive: the
        mean of its speed reference (an open-loop drive's: its limiter's, docs/winder.md W7)
        and speed error mean, standard deviation and largest error [m/s] against it
        (``webline.sim.results.metrics.run_summary``)."""
        return run_summary(self)

    def to_xarray(self) -> xr.Dataset:
        """Dataset over time with span, node and drive coordinates; units as attributes; the
        resolved line (TOML) and the webline version embedded
        (``webline.sim.results.result_dataset``).
        A new Dataset each call; ``signals`` keeps one."""
        return to_xarray(self)

    def to_netcdf(self, path: str | Path, precision: Precision = "float64") -> Path:
        """Write the dataset to NetCDF-4 (HDF5 via h5netcdf), zlib-compressed and chunked along
        time, atomically (a temporary file renamed into place). ``precision`` "float32" halves
        the float signals (time stays float64). The rewind's wound roll, where the line computes
        one, is the group ``wound_roll`` (per layer). Returns the path."""
        roll = self.wound_roll
        groups = {"wound_roll": roll.group_variables()} if roll is not None else None
        return write_netcdf(result_variables(self), path, precision, groups)

    def to_dataframe(self):
        """The CSV's table as a ``pandas.DataFrame``: one row per record, indexed by ``time``
        [s]; one column per signal and element (``tension[span1]``, ``web_stored``), SI, the
        unit of each column in ``.attrs["units"]`` (``result_files.signal_frame``)."""
        return signal_frame(result_variables(self))

    def to_csv(self, path: str | Path) -> Path:
        """Write one column per named signal (``tension[span1]`` ...) with a units header,
        atomically (a temporary file renamed into place). Returns the path."""
        return write_csv(result_variables(self), path)

    def _repr_html_(self) -> str:
        """Jupyter's display: line, duration, verdict and tension statistics per span."""
        from webline.sim.results.quicklook import result_html

        return result_html(self)
