"""The table of physical ranges of a line file's quantities (``webline.spec.ranges`` reads
it): each key's hard range (outside it: no web line at all, an error) and usual range
(outside it: a warning), with its unit kind and why; ``SECTIONS`` names the sections each
schema model answers to."""

from __future__ import annotations

import math
from dataclasses import dataclass

from webline.units import SI_UNITS

TAU = 2.0 * math.pi


@dataclass(frozen=True)
class Range:
    """Closed hard and usual intervals [SI] of one quantity, its unit kind and why."""

    kind: str
    hard: tuple[float, float]
    usual: tuple[float, float]
    why: str

    @property
    def unit(self) -> str:
        return SI_UNITS.get(self.kind, self.kind)

    def hard_problem(self, value: float) -> str | None:
        """The error for a value outside the hard range, or None."""
        low, high = self.hard
        if low <= value <= high:
            return None
        return (f"{fmt(value)} {self.unit} is outside the physical range "
                f"{fmt(low)} .. {fmt(high)} {self.unit}".replace("  ", " "))

    def usual_problem(self, value: float) -> str | None:
        """The warning for a value outside the usual range (inside the hard one), or None."""
        low, high = self.usual
        if low <= value <= high:
            return None
        return (f"{fmt(value)} {self.unit} is unusual (usual range {fmt(low)} .. "
                f"{fmt(high)} {self.unit}): {self.why}".replace("  ", " "))


def fmt(value: float) -> str:
    """A number as the docs write it (4 significant digits)."""
    return f"{value:.4g}"


def _r(kind: str, hard: tuple[float, float], usual: tuple[float, float], why: str) -> Range:
    assert hard[0] <= usual[0] <= usual[1] <= hard[1], why
    return Range(kind, hard, usual, why)


# Abbreviations for the table.
LEN, FORCE, TORQUE, INERTIA, RDAMP = "length", "force", "torque", "inertia", "rot_damping"
SPEED_RANGE = _r("speed", (0.0, 200.0), (0.0, 50.0),
                 "the fastest paper machines run ~2000 m/min (33 m/s); 3000 m/min is 50 m/s")
TIME_RANGE = _r("time", (0.0, 1e6), (0.0, 86400.0), "times from the start of a run; a day")
BRAKE_RANGE = _r(TORQUE, (0.0, 1e7), (0.0, 1e5), "a brake or drag torque of a web roller")
FRICTION_RANGE = _r(RDAMP, (0.0, 1e5), (0.0, 100.0),
                    "bearing friction of rollers up to large rolls (thesis: 0.005-0.5 lbf·ft·s)")
RADIUS_RANGE = _r(LEN, (1e-3, 5.0), (0.01, 1.0), "idlers 10 mm to 2 m diameter")
ROLL_RADIUS = _r(LEN, (1e-3, 5.0), (0.02, 2.5), "a jumbo paper reel is ~3.5 m across")
TENSION_RANGE = _r(FORCE, (1e-3, 1e8), (1.0, 1e6),
                   "1 N (narrow film) to 1 MN (wide steel strip) of web tension")
FREQ_RANGE = _r("frequency", (1e-5, 1e5), (1e-3, 1000.0), "a disturbance within the model's band")
PHASE_RANGE = _r("angle", (-1e3, 1e3), (-TAU, TAU), "a phase is an angle mod 2π")

#: section.field -> Range. Angular frequencies are in rad/s ("6 Hz" is 2π·6 rad/s).
RANGES: dict[str, Range] = {
    # web
    "web.thickness": _r(LEN, (1e-7, 0.02), (1e-6, 5e-3),
                        "1 µm capacitor film to 5 mm board or steel strip"),
    "web.width": _r(LEN, (1e-3, 20.0), (0.01, 10.0), "tapes to the widest paper machines"),
    "web.density": _r("density", (10.0, 25000.0), (100.0, 9000.0),
                      "foams and nonwovens to copper (8960); osmium is 22600"),
    "web.modulus": _r("pressure", (1e5, 1.2e12), (1e7, 4.2e11),
                      "soft elastomers and nonwovens to tungsten (diamond 1.2e12)"),
    "web.ea": _r(FORCE, (1.0, 1e11), (100.0, 5e9), "E·A of thin film strips to steel strip"),
    "web.strength": TENSION_RANGE,
    "web.tension_limit": TENSION_RANGE,
    # the web's stress-strain law (docs/nonlinear-web.md)
    "stress_strain.strain": _r("dimensionless", (0.0, 1.0), (0.0, 0.3),
                               "foils break below 2 %, papers 3-8 %, nonwovens 30 %"),
    "stress_strain.stress": _r("pressure", (0.0, 1e10), (0.0, 2e9),
                               "up to the strength of steel strip"),
    "stress_strain.tension_per_width": _r("force_per_width", (0.0, 1e7), (0.0, 2e5),
                                          "up to the breaking load of heavy board"),
    "stress_strain.exponent": _r("dimensionless", (0.05, 20.0), (0.3, 3.0),
                                 "softening (< 1) or stiffening (> 1) webs"),
    "stress_strain.reference_strain": _r("dimensionless", (1e-7, 1.0), (1e-4, 0.1),
                                         "a strain where the secant modulus is E"),
    "stress_strain.yield_strain": _r("dimensionless", (1e-7, 1.0), (1e-4, 0.1),
                                     "aluminium foil ~0.1-0.5 %, films 1-4 %"),
    "stress_strain.hardening": _r("dimensionless", (0.0, 10.0), (0.001, 1.0),
                                  "the tangent beyond yield over E"),
    # rollers and rolls
    "roll.radius": ROLL_RADIUS,
    "roll.core_radius": _r(LEN, (1e-3, 5.0), (0.01, 0.5), "cores of 20 mm to 1 m diameter"),
    "roller.radius": RADIUS_RANGE,
    "roller.inertia": _r(INERTIA, (1e-9, 1e7), (1e-6, 1e5),
                         "a small idler to a jumbo reel spool with shaft"),
    "roller.friction": FRICTION_RANGE,
    "roller.coulomb_friction": _r(TORQUE, (0.0, 1e6), (0.0, 1000.0), "dry bearing friction"),
    "roller.breakaway_torque": _r(TORQUE, (0.0, 1e6), (0.0, 1000.0), "dry bearing friction"),
    "friction_table.speed": _r("angular_frequency", (0.0, 1e5), (0.0, 1000.0),
                               "shaft speeds up to 10 000 rpm"),
    "friction_table.torque": _r(TORQUE, (0.0, 1e6), (0.0, 1000.0), "dry bearing friction"),
    "roller.wrap": _r("angle", (1e-4, 4 * math.pi), (0.05, TAU), "a web wraps at most once"),
    "unwind.wound_in_tension": TENSION_RANGE,
    # a roll's inertia as totals (docs/winder.md, J1)
    "roll_totals.empty": _r(INERTIA, (1e-9, 1e7), (1e-6, 1e5), "an empty core to a jumbo reel"),
    "roll_totals.full": _r(INERTIA, (1e-9, 1e7), (1e-6, 1e5), "an empty core to a jumbo reel"),
    "roll_totals.empty_diameter": _r(LEN, (2e-3, 10.0), (0.02, 4.0), "cores to reels"),
    "roll_totals.full_diameter": _r(LEN, (2e-3, 10.0), (0.02, 4.0), "cores to reels"),
    "roll_total.total": _r(INERTIA, (1e-9, 1e7), (1e-6, 1e5), "an empty core to a jumbo reel"),
    "roll_total.diameter": _r(LEN, (2e-3, 10.0), (0.02, 4.0), "cores to reels"),
    # dancers (docs/winder.md)
    "dancer.mass": _r("mass", (1e-3, 1e5), (0.1, 2000.0), "a light slide to a heavy arm"),
    "dancer.travel": _r(LEN, (1e-3, 20.0), (0.01, 3.0), "strokes of mm to metres"),
    "dancer.position": _r(LEN, (1e-4, 20.0), (1e-3, 3.0), "within the travel"),
    "dancer.load": TENSION_RANGE,
    "dancer.stiffness": _r("stiffness", (0.0, 1e9), (0.0, 1e6), "air springs to steel"),
    "dancer.damping": _r("linear_damping", (0.0, 1e8), (0.0, 1e5), "dashpots"),
    "dancer.stop_stiffness": _r("stiffness", (1.0, 1e10), (1e3, 1e8), "rubber to steel"),
    "dancer.arm_length": _r(LEN, (1e-3, 20.0), (0.05, 3.0), "pivoting arms"),
    "dancer.arm_inertia": _r(INERTIA, (1e-9, 1e6), (1e-4, 1e4), "pivoting arms"),
    "dancer.strands": _r("integer", (2.0, 200.0), (2.0, 40.0),
                         "a dancer roller (2) to a festoon accumulator's strands"),
    "dancer.angle_in": _r("angle", (0.0, 1.5708), (0.0, 1.3963), "spans at 0 to 80 deg"),
    "dancer.angle_out": _r("angle", (0.0, 1.5708), (0.0, 1.3963), "spans at 0 to 80 deg"),
    "dancer.position_kp": _r("1/s", (0.0, 1e4), (0.0, 100.0), "position-loop gains"),
    "dancer.position_ki": _r("1/s²", (0.0, 1e6), (0.0, 1e4), "position-loop gains"),
    "differential_shaft.slip_torque": _r(TORQUE, (1e-4, 1e5), (0.01, 1000.0),
                                         "slip clutches of narrow tapes to wide lanes"),
    "differential_shaft.overspeed": _r("dimensionless", (0.0, 0.5), (0.005, 0.1),
                                       "shafts run 0.5-10 % over the web speed"),
    "differential_shaft.core_inertia": _r(INERTIA, (1e-9, 100.0), (1e-5, 1.0),
                                          "paper and plastic cores with their rings"),
    "taper.taper": _r("dimensionless", (0.0, 1.0), (0.0, 0.8), "taper of 0 to 80 %"),
    "taper.max_diameter": _r(LEN, (1e-3, 10.0), (0.05, 4.0), "reels up to 4 m"),
    "taper.diameter": _r(LEN, (1e-3, 10.0), (0.02, 4.0), "cores to reels"),
    "taper.factor": _r("dimensionless", (0.0, 1.0), (0.05, 1.0), "a fraction of the reference"),
    "diameter.initial": _r(LEN, (1e-3, 10.0), (0.02, 4.0), "cores to reels"),
    "diameter.filter": _r("time", (1e-4, 100.0), (0.01, 5.0), "a fraction of a revolution"),
    "diameter.rate_limit": _r("speed", (1e-9, 10.0), (1e-6, 0.1), "rolls grow by mm/s"),
    "diameter_preset.at": TIME_RANGE,
    "diameter_preset.diameter": _r(LEN, (1e-3, 10.0), (0.02, 4.0), "cores to reels"),
    "diameter.hold_below": _r("speed", (0.0, 50.0), (0.0, 2.0), "a crawl"),
    "winder.static_friction": _r(TORQUE, (0.0, 1e6), (0.0, 1000.0), "dry bearing friction"),
    "winder.viscous_friction": FRICTION_RANGE,
    "tension_ramp.standstill": _r("dimensionless", (0.0, 1.0), (0.05, 1.0),
                                  "a fraction of the running tension"),
    "tension_ramp.time": _r("time", (1e-3, 1e4), (0.1, 600.0), "seconds to minutes"),
    "tension_ramp.below": _r("speed", (0.0, 50.0), (0.0, 2.0), "a crawl"),
    "web_break.at": TIME_RANGE,
    "flying_splice.at": TIME_RANGE,
    "flying_splice.new_diameter": _r(LEN, (2e-3, 10.0), (0.04, 5.0),
                                     "a 40 mm core to a 5 m jumbo reel"),
    "flying_splice.speed_mismatch": _r("dimensionless", (-0.5, 0.5), (-0.05, 0.05),
                                       "splicers match surface speeds within a few per cent"),
    "flying_splice.slack": _r(LEN, (-1.0, 1.0), (-0.01, 0.05),
                              "a paster's loop or tape overlap: millimetres to centimetres"),
    "web_break.threshold": _r("dimensionless", (0.0, 1.0), (0.05, 0.8), "of the reference"),
    "web_break.stop_time": _r("time", (1e-3, 1e4), (0.1, 600.0), "an emergency ramp"),
    "web_break.diameter_threshold": _r(LEN, (0.0, 10.0), (1e-4, 0.1),
                                       "a few mm, above the calculator's noise"),
    "web_break.standstill_tension": _r("dimensionless", (0.0, 1.0), (0.05, 1.0),
                                       "of the set tension"),
    "web_break.brake_torque_fraction": _r("dimensionless", (1e-3, 10.0), (0.2, 3.0),
                                          "holding brakes near the motor's torque"),
    "winder.speed_limit_offset": _r("dimensionless", (1e-4, 1.0), (0.01, 0.2),
                                    "a few per cent of line speed"),
    "checks.tension_tolerance": _r("dimensionless", (1e-4, 100.0), (0.02, 1.0),
                                   "tension alarms of 5-50 %"),
    "checks.diameter_tolerance": _r("dimensionless", (1e-5, 10.0), (1e-3, 0.2),
                                    "above the calculator's error"),
    "checks.min_duration": _r("time", (0.0, 1e6), (0.0, 600.0), "seconds, not hours"),
    "checks.end_stop_time": _r("time", (0.0, 1e6), (0.0, 600.0), "seconds, not hours"),
    # drives
    "drive.ratio": _r("dimensionless", (1e-3, 1e3), (0.02, 100.0), "gearboxes up to 100:1"),
    "drive.torque_limit": _r(TORQUE, (1e-4, 1e7), (0.01, 1e5), "servo motors to winder drives"),
    "drive.torque_lag": _r("time", (1e-6, 10.0), (1e-4, 0.1),
                           "current loops close in 0.1-10 ms; a lag sets the integration step"),
    "drive.motor_inertia": _r(INERTIA, (0.0, 1e5), (0.0, 1000.0), "motor rotors"),
    "drive.motor_friction": FRICTION_RANGE,
    "drive.brake": BRAKE_RANGE,
    "belt.stiffness": _r("stiffness", (1.0, 1e10), (1e3, 1e8), "timing and V-belt spans"),
    "belt.load_pulley_radius": _r(LEN, (1e-3, 2.0), (0.01, 0.5), "belt pulleys"),
    "belt.damping": _r("linear_damping", (0.0, 1e8), (0.0, 1e5), "belt material damping"),
    "shaft.stiffness": _r("torque", (1e-2, 1e10), (10.0, 1e8),
                          "couplings and shafts, [N·m/rad]"),
    "shaft.damping": _r(RDAMP, (0.0, 1e7), (0.0, 1e4), "torsional damping"),
    "backlash.gap": _r("angle", (0.0, 0.5), (0.0, 0.05), "gear play is a fraction of a degree"),
    "backlash.asymmetry": _r("dimensionless", (0.0, 1.0), (0.0, 1.0), "a fraction of the gap"),
    # controllers
    "cascaded_pi.speed_kp": _r("N·m·s/m", (0.0, 1e9), (0.0, 1e6), "speed-loop gains"),
    "cascaded_pi.speed_ki": _r("N·m/m", (0.0, 1e11), (0.0, 1e8), "speed-loop gains"),
    "cascaded_pi.tension_kp": _r("(m/s)/N", (0.0, 100.0), (0.0, 1.0), "tension-loop gains"),
    "cascaded_pi.tension_ki": _r("(m/s)/(N·s)", (0.0, 1e4), (0.0, 100.0), "tension-loop gains"),
    "cascaded_pi.speed_bandwidth": _r("angular_frequency", (1e-3, 1e5), (1.0, 2000.0),
                                      "below the drive's current loop"),
    "cascaded_pi.tension_bandwidth": _r("angular_frequency", (1e-3, 1e4), (0.1, 500.0),
                                        "below the speed loop"),
    "cascaded_pi.damping": _r("dimensionless", (1e-3, 100.0), (0.3, 5.0),
                              "damping ratios of tuned loops"),
    "decentralized.tension_gain": _r("N·m/N", (-1e6, 1e6), (-1e3, 1e3), "section feedback"),
    "decentralized.speed_gain": _r("N·m·s/m", (-1e9, 1e9), (-1e6, 1e6), "section feedback"),
    "decentralized.tension_scale": _r(FORCE, (1e-6, 1e8), (1e-3, 1e5), "LQ scaling"),
    "decentralized.speed_scale": _r("speed", (1e-6, 200.0), (1e-4, 10.0), "LQ scaling"),
    "decentralized.torque_scale": _r(TORQUE, (1e-6, 1e7), (1e-3, 1e5), "LQ scaling"),
    "decentralized.friction_estimate": FRICTION_RANGE,
    "decentralized.observer_bandwidth": _r("angular_frequency", (1e-3, 1e5), (1.0, 1000.0),
                                           "tension observer poles"),
    "decentralized.observer_ea": _r(FORCE, (1.0, 1e10), (100.0, 1e8), "web stiffness EA"),
    "adaptive.adaptation_gain": _r("angular_frequency", (1e-4, 1e5), (0.1, 1000.0),
                                   "below the speed loop"),
    "adaptive.leakage": _r("dimensionless", (0.0, 1e3), (0.0, 10.0), "σ-modification"),
    "adaptive.parameter_bound": _r("dimensionless", (1e-3, 1e6), (1.0, 1000.0),
                                   "projection bound"),
    "python_controller.params": _r("dimensionless", (-1e300, 1e300), (-1e300, 1e300),
                                   "a compiled law's own parameters, in its own units"),
    "python_controller.states": _r("integer", (0.0, 1e6), (0.0, 1e4),
                                   "a compiled law's memory (integrators, filters)"),
    "mrac.adaptation_gain": _r("angular_frequency", (1e-6, 1e5), (1e-3, 100.0),
                               "scaled adaptation rate"),
    "mrac.leakage": _r("dimensionless", (0.0, 1e3), (0.0, 10.0), "σ-modification"),
    "mrac.parameter_bound": _r("dimensionless", (1e-3, 1e6), (0.1, 100.0),
                               "projection bound (scaled)"),
    # contact
    "traction.friction": _r("dimensionless", (1e-3, 10.0), (0.05, 1.5),
                            "web-roller friction coefficients"),
    "traction.kinetic_friction": _r("dimensionless", (0.0, 10.0), (0.0, 1.5),
                                    "web-roller friction coefficients"),
    "traction.viscous": _r("linear_damping", (1e-3, 1e9), (10.0, 1e6),
                           "air-film traction; small values make slip a stiff mode"),
    # nips (docs/winder.md)
    "nip.load": _r(FORCE, (1e-3, 1e7), (1.0, 1e5),
                   "nip loads of 0.1-20 kN/m over widths of cm to 10 m"),
    "nip.radius": RADIUS_RANGE,
    "nip.inertia": _r(INERTIA, (1e-9, 1e5), (1e-6, 100.0), "rubber-covered pressure rollers"),
    "nip.friction": _r("dimensionless", (1e-3, 10.0), (0.05, 1.5),
                       "web on rubber or steel: 0.1-1"),
    "nip.kinetic_friction": _r("dimensionless", (0.0, 10.0), (0.0, 1.5),
                               "web on rubber or steel: 0.1-1"),
    "nip.bearing_friction": FRICTION_RANGE,
    "nip.bearing_coulomb": _r(TORQUE, (0.0, 1e6), (0.0, 1000.0), "dry bearing friction"),
    # wound-roll stresses (docs/wound-roll.md)
    "roll_stress.k1": _r("pressure", (1.0, 1e9), (100.0, 1e6),
                         "Pfeiffer's K1: 0.1-1000 kPa for paper and film stacks"),
    "roll_stress.k2": _r("dimensionless", (1e-3, 1e5), (5.0, 2000.0),
                         "Pfeiffer's K2: tens to hundreds for paper and film stacks"),
    "roll_stress.radial_modulus": _r("pressure", (1e3, 1e11), (1e5, 1e9),
                                     "a stack's radial modulus: 0.1-1000 MPa"),
    "roll_stress.tangential_modulus": _r("pressure", (1e5, 1e12), (1e7, 3e11),
                                         "in-plane moduli of webs, paper to metal foil"),
    "roll_stress.poisson": _r("dimensionless", (0.0, 0.5), (0.0, 0.1),
                              "ν_rt of a stack: radially far softer than in-plane, near 0"),
    "roll_stress.diameter": _r(LEN, (1e-3, 20.0), (0.05, 4.0), "finished roll diameters"),
    "roll_stress.nip_load": _r(FORCE, (1e-3, 1e7), (1.0, 1e5),
                               "lay-on nips: 0.1-10 kN/m over widths of cm to 10 m"),
    "roll_stress.nip_friction": _r("dimensionless", (0.0, 10.0), (0.0, 1.0),
                                   "layer-to-layer friction of film and paper: 0.1-0.6"),
    "roll_stress.min_hoop": _r("pressure", (-1e10, 1e10), (-1e8, 1e7),
                               "a hoop compression limit (buckling) of 0 to -100 MPa"),
    "roll_stress.max_pressure": _r("pressure", (1.0, 1e10), (1e4, 1e8),
                                   "interlayer pressures that block or emboss: 0.1-10 MPa"),
    "roll_stress.core_rating": _r("pressure", (1.0, 1e11), (1e5, 1e9),
                                  "paper cores 1-10 MPa, steel and fibre cores more"),
    "roll_stress.at_radii": _r(LEN, (1e-3, 10.0), (0.02, 2.0),
                               "radii within rolls of 40 mm to 4 m diameter"),
    "roll_stress.band": _r("dimensionless", (0.0, 1.0), (0.01, 0.5),
                           "a band 1-50 % off the steady roll's pressure"),
    "roll_core.modulus": _r("pressure", (1e5, 1e12), (1e8, 3e11),
                            "paper cores 1-10 GPa, steel 200 GPa"),
    "roll_core.poisson": _r("dimensionless", (0.0, 0.5), (0.0, 0.5), "isotropic materials"),
    "roll_core.inner_radius": _r(LEN, (0.0, 10.0), (0.0, 0.5), "cores and shafts"),
    # spans, speed, control, scenarios
    "span.length": _r(LEN, (1e-3, 1000.0), (0.05, 50.0),
                      "spans of a few cm to dryer sections; a span sets the stiffness EA/L"),
    "span.tension": TENSION_RANGE,
    "span.retardation": _r("time", (0.0, 10.0), (0.0, 0.1),
                           "creep of polymer films within a span's transit; a long one is "
                           "a stiff damper that shortens the integration step"),
    "line.speed": SPEED_RANGE,
    "scenario.speed": SPEED_RANGE,
    "control.sample_rate": _r("frequency", (1.0, 1e6), (50.0, 20000.0),
                              "drive controllers sample at 0.1-20 kHz"),
    "scenario.duration": _r("time", (1e-6, 1e6), (1e-3, 86400.0), "a run of up to a day"),
    "scenario.unwind_radius": ROLL_RADIUS,
    "scenario.rewind_radius": ROLL_RADIUS,
    # profile times
    "ramp.start": TIME_RANGE,
    "ramp.duration": _r("time", (1e-6, 1e6), (1e-3, 86400.0), "a ramp of up to a day"),
    "steps.time": TIME_RANGE,
    "table.time": TIME_RANGE,
    # disturbances
    "wound_in_ripple.amplitude": TENSION_RANGE,
    "wound_in_ripple.frequency": FREQ_RANGE,
    "wound_in_ripple.phase": PHASE_RANGE,
    "eccentric_roller.eccentricity": _r(LEN, (0.0, 1.0), (0.0, 5e-3),
                                        "run-out of a roller is below a few mm"),
    "speed_ripple.amplitude": _r("speed", (0.0, 200.0), (0.0, 5.0), "a ripple on the speed"),
    "speed_ripple.frequency": FREQ_RANGE,
    "speed_ripple.phase": PHASE_RANGE,
    "roller_drag.torque": BRAKE_RANGE,
    "measurement_noise.tension": _r(FORCE, (0.0, 1e6), (0.0, 1e3), "loadcell noise"),
    "measurement_noise.speed": _r("speed", (0.0, 100.0), (0.0, 1.0), "tachometer noise"),
    "measurement_noise.speed_resolution": _r("speed", (0.0, 10.0), (0.0, 0.1),
                                             "an encoder's count per sample"),
    "measurement_noise.seed": _r("integer", (0.0, 2.0**53), (0.0, 2.0**53),
                                 "the plan stores it as a float (exact to 2^53)"),
    "loadcell.gain": _r("dimensionless", (0.01, 100.0), (0.8, 1.25),
                        "a calibrated loadcell reads within a few per cent"),
    "loadcell.offset": _r(FORCE, (-1e6, 1e6), (-1e3, 1e3), "a zero drift of the amplifier"),
    "loadcell.delay": _r("time", (0.0, 10.0), (0.0, 0.05),
                         "an amplifier's filter and a fieldbus: milliseconds"),
    "encoder.delay": _r("time", (0.0, 10.0), (0.0, 0.05), "a fieldbus cycle: milliseconds"),
    "encoder.scale": _r("dimensionless", (0.01, 100.0), (0.8, 1.25),
                        "a roller diameter or pulse count off by a few per cent"),
}

#: schema model name -> the sections of ``RANGES`` its fields look up, first match first
SECTIONS: dict[str, tuple[str, ...]] = {
    "WebSpec": ("web",),
    "StressStrainSpec": ("stress_strain",),
    "BacklashSpec": ("backlash",),
    "BeltSpec": ("belt",),
    "ShaftSpec": ("shaft",),
    "DriveSpec": ("drive",),
    "CascadedPISpec": ("cascaded_pi",),
    "StateFeedbackSpec": ("decentralized",),
    "AdaptiveSpec": ("adaptive", "decentralized"),
    "MRACSpec": ("mrac", "decentralized"),
    "PythonControllerSpec": ("python_controller",),
    "TractionSpec": ("traction",),
    "NipSpec": ("nip",),
    "UnwindSpec": ("unwind", "roll", "roller"),
    "RewindSpec": ("roll", "roller"),
    "DrivenSpec": ("roller",),
    "IdleSpec": ("roller",),
    "DancerSpec": ("roller",),
    "DancerCarriage": ("dancer",),
    "RollTotals": ("roll_totals",),
    "MeasuredFriction": ("friction_table",),
    "RollTotal": ("roll_total",),
    "TaperSpec": ("taper",),
    "RollStressSpec": ("roll_stress",),
    "RollCoreSpec": ("roll_core",),
    "DifferentialShaftSpec": ("differential_shaft",),
    "DiameterSpec": ("diameter",),
    "DiameterPreset": ("diameter_preset",),
    "WinderSpec": ("winder",),
    "StartStopTension": ("tension_ramp",),
    "WebBreak": ("web_break",),
    "StateChecksSpec": ("checks",),
    "BreakEvent": ("web_break",),
    "FlyingSplice": ("flying_splice",),
    "SpliceEvent": ("flying_splice",),
    "SpanSpec": ("span",),
    "WoundInRipple": ("wound_in_ripple",),
    "EccentricRoller": ("eccentric_roller",),
    "SpeedRipple": ("speed_ripple",),
    "RollerDrag": ("roller_drag",),
    "MeasurementNoise": ("measurement_noise",),
    "LoadcellSensor": ("loadcell",),
    "EncoderSensor": ("encoder",),
    "ControlSpec": ("control",),
    "ScenarioSpec": ("scenario",),
    "BranchedLineSpec": ("line",),
    "WebPathSpec": ("web",),
    "BranchedScenarioSpec": ("scenario",),
    "RollChangeSpec": ("steps", "roll", "unwind"),
    "LineSpec": ("line",),
    "Ramp": ("ramp",),
    "Step": ("steps",),
    "Steps": ("steps",),
    "Table": ("table",),
}

#: Fields holding no quantity of their own: profile values take the range of the profile's key.
PROFILE_VALUE_FIELDS = {"initial", "final", "value", "steps"}
