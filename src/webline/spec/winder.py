"""Line-file keys of the winder functions (docs/winder.md): taper tension, diameter
calculation, compensation and open-loop tension control."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, Any, Literal

from pydantic import Field

from webline.spec.friction import MeasuredFriction
from webline.spec.quantities import Inertia, Length, Strict, Torque, si

Fraction = Annotated[float, Field(ge=0.0, le=1.0)]


class DifferentialShaftSpec(Strict):
    """How a rewind's lanes sit on its shaft (docs/branching.md, "Differential shafts"):
    ``"differential"``: each lane's core is driven through its own slip clutch (a friction
    ring), which passes at most ``slip_torque`` [N·m] while it slips; the shaft turns
    ``overspeed`` [-] faster than the fastest lane's core so that every clutch slips and each
    lane's tension is ≈ slip_torque / its radius. ``core_inertia`` [kg·m²]: one lane's core
    with its clutch ring (its wound web is added)."""

    type: Literal["differential"]
    slip_torque: Torque
    overspeed: Annotated[float, Field(gt=0.0, le=0.5)] = 0.02
    core_inertia: Inertia


class TaperSpec(Strict):
    """The rewind's tension reference as a function of its diameter D: the zone's reference
    times a factor f(D) (docs/winder.md, W1). D_c is the core diameter.

    ``"linear"``: f = 1 - taper (D - D_c)/(``max_diameter`` - D_c); ``"hyperbolic"``:
    f = 1 - taper (1 - D_c/D) (taper = 1 is constant torque); ``"table"``: f interpolated
    in (``diameter`` [m], ``factor``), constant beyond its ends.
    """

    type: Literal["linear", "hyperbolic", "table"]
    taper: Fraction = 0.0
    max_diameter: Length | None = None
    diameter: list[Length] = Field(default_factory=list)
    factor: list[Fraction] = Field(default_factory=list)


def check_taper(taper: TaperSpec | None, key: str, fail: Callable[[str, str], Any]) -> None:
    """Fail on a taper that lacks the keys of its type."""
    if taper is None:
        return
    if taper.type == "linear" and taper.max_diameter is None:
        fail(f"{key}.max_diameter", "a linear taper needs the largest diameter")
    if taper.type == "table":
        if not taper.diameter or len(taper.diameter) != len(taper.factor):
            fail(f"{key}.factor", "a taper table needs as many factors as diameters (>= 1)")
        if any(b <= a for a, b in zip(taper.diameter, taper.diameter[1:], strict=False)):
            fail(f"{key}.diameter", "diameters must increase")


class DiameterPreset(Strict):
    """One preset of a diameter calculator while running (docs/winder.md, W2a): at time
    ``at`` [s] the calculated diameter is set to ``diameter`` [m], or to the true one
    (``"measured"``: an operator's measurement)."""

    at: Annotated[float, si("time", ">=0")]
    diameter: Literal["measured"] | Length = "measured"


#: presets a calculator takes (drive-table slots)
MAX_PRESETS = 4


class DiameterSpec(Strict):
    """A roll drive's diameter calculator (docs/winder.md, W2): its controllers use the
    calculated radius, not the true one.

    ``"speed_ratio"``: D = 2 v_line / ω_spindle, low-pass filtered with ``filter`` [s], its
    rate limited to ``rate_limit`` [m/s] of diameter, held while |v_line| < ``hold_below``
    [m/s]. ``line_speed`` is where v_line comes from: ``"master"`` (the master roller's
    measured surface speed), ``"reference"`` (the line-speed reference) or the name of a
    measuring roller (its measured surface speed). Both speeds are measured as the
    controllers measure them (``measurement_noise``: noise and resolution; the spindle's
    encoder, on the motor across a transmission with motor feedback). ``"thickness"``: each
    revolution adds (rewind) or removes (unwind) two web thicknesses. ``initial``:
    ``"measured"`` (the true diameter at the start) or a guessed diameter [m]. ``preset``:
    diameters set while running (after a splice, or measured by the operator), up to four.
    """

    method: Literal["speed_ratio", "thickness"]
    line_speed: Annotated[str, Field(min_length=1, max_length=100)] = "master"
    initial: Literal["measured"] | Length = "measured"
    filter: Annotated[float, si("time", ">0")] = 0.2
    rate_limit: Annotated[float, si("speed", ">0")] | None = None
    hold_below: Annotated[float, si("speed", ">=0")] = 0.05
    preset: list[DiameterPreset] = Field(default_factory=list, max_length=MAX_PRESETS)


def check_diameters(rollers: list[Any], fail: Callable[[str, str], Any]) -> None:
    """Fail on a diameter calculator whose line-speed source names no roller (or its own
    roll)."""
    names = [r.name for r in rollers]
    for i in (0, len(rollers) - 1):
        spec = getattr(rollers[i], "diameter", None)
        if spec is None or spec.line_speed in ("master", "reference"):
            continue
        if spec.line_speed not in names or names.index(spec.line_speed) == i:
            fail(f"rollers[{i}].diameter.line_speed", f"must be 'master', 'reference' or "
                 f"the name of another roller, got {spec.line_speed!r}")


class WinderSpec(Strict):
    """A centre winder's torque functions (docs/winder.md, W3-W4) on a roll's drive.

    ``mode``: ``"closed_loop"`` keeps the roll's controller (its tension loop on the loadcell
    or dancer); ``"open_loop"`` is indirect tension control: torque = T_ref R / ratio plus the
    compensations, no tension measurement and no speed loop. ``inertia_compensation`` adds
    J(D) a_line / (R ratio), J the roll's inertia (core, shaft and motor, and the web from the
    diameter, width and density) and a_line the line-speed reference's acceleration;
    ``static_friction`` [N·m] and ``viscous_friction`` [N·m·s] at the roll shaft add
    (static sign(ω) + viscous ω) / ratio, a ``friction_table`` (``spec.friction``) its
    measured torque at |ω| times sign(ω) / ratio. The radius is the calculated one where the
    roll has a ``diameter`` calculator. ``speed_limit_offset``: an open-loop drive's speed limiter,
    as a fraction of the line's top speed (the largest value of its speed reference) over
    the line-speed reference (a rewind's upper, an unwind's lower limit): its speed
    controller, saturated at the tension torque while the web holds the roll, takes over
    when a freed roll reaches the limit (docs/winder.md W7).
    """

    mode: Literal["closed_loop", "open_loop"] = "closed_loop"
    speed_limit_offset: Annotated[float, Field(gt=0.0, le=1.0)] = 0.05
    inertia_compensation: bool = False
    static_friction: Annotated[float, si("torque", ">=0")] = 0.0
    viscous_friction: Annotated[float, si("rot_damping", ">=0")] = 0.0
    friction_table: MeasuredFriction | None = None


class StartStopTension(Strict):
    """``control.tension_ramp`` (docs/winder.md, R1): every zone's set tension is
    ``standstill`` x its reference while the line stands (speed reference |v| <= ``below``
    [m/s]) and ramps to the full reference in ``time`` [s] when the line starts, and back
    when it stops (``model.tension_ramp``)."""

    standstill: Fraction
    time: Annotated[float, si("time", ">0")]
    below: Annotated[float, si("speed", ">=0")] = 0.05


class WebBreak(Strict):
    """A web break (docs/winder.md, W5): at time ``at`` [s] span ``span`` breaks; every span
    of its tension zone then carries no tension (the free end runs through the idle rollers
    up to the driven ones that grip it). The line's break monitor is on in a run with a
    break: it detects a loadcell tension below ``threshold`` x its reference, a dancer at
    an end stop, or the speed-ratio diameter of a roll running the wrong way (an unwind's
    growing, a rewind's shrinking) by more than ``diameter_threshold`` [m] (0: off) beyond
    its extreme so far, or (``overspeed``) an open-loop roll at its speed limit, and reacts
    by ramping the line to a stop in ``stop_time`` [s], tension loops frozen. Then the
    drives ``hold`` (docs/winder.md W8): ``"stall_tension"``: each roll's drive holds its
    stall tension as a torque, ``standstill_tension`` (a fraction of its zone's set tension)
    x R / n, as winder drives do at standstill (a speed limiter catches a roll the web no
    longer holds), every other drive zero speed; ``"zero_speed"``: every speed loop holds
    zero speed, an open-loop roll's torque limited to its standstill tension on the tension
    side; ``"brakes"``: torque off and a holding brake of
    ``brake_torque_fraction`` x each drive's torque limit set on every driven roller;
    ``"off"``: torque off, nothing holds."""

    type: Literal["web_break"]
    span: Annotated[str, Field(min_length=1, max_length=100)]
    at: Annotated[float, si("time", ">=0")]
    threshold: Fraction = 0.2
    stop_time: Annotated[float, si("time", ">0")] = 2.0
    diameter_threshold: Annotated[float, si("length", ">=0")] = 0.005
    overspeed: bool = True
    hold: Literal["stall_tension", "zero_speed", "brakes", "off"] = "stall_tension"
    standstill_tension: Fraction = 0.5
    brake_torque_fraction: Annotated[float, Field(gt=0.0, le=10.0)] = 1.0


class BreakEvent(WebBreak):
    """A scenario's ``break = { span = "...", at = "12 s" }``: a ``web_break`` disturbance
    added to the scenario's disturbances (``type`` may be left out)."""

    type: Literal["web_break"] = "web_break"


class StateChecksSpec(Strict):
    """Thresholds of the verdict's winder-state findings (docs/winder.md, "Winder states in
    the verdict"): a zone whose tension stays more than ``tension_tolerance`` x its set
    tension off it, or a calculated diameter more than ``diameter_tolerance`` x the true one
    off it, for at least ``min_duration`` [s] in one go; a dancer on an end stop for at
    least ``end_stop_time`` [s] (0: any touch)."""

    tension_tolerance: Annotated[float, Field(gt=0.0)] = 0.2
    diameter_tolerance: Annotated[float, Field(gt=0.0)] = 0.02
    min_duration: Annotated[float, si("time", ">=0")] = 1.0
    end_stop_time: Annotated[float, si("time", ">=0")] = 0.0
