"""The winder functions of a line in words (docs/winder.md): who sets each zone's tension,
dancers, taper, diameter calculation, compensation, open-loop mode, break monitoring and
flying splices, as ``webline show``, the report's tables and the schematic show them."""

from __future__ import annotations

from webline.line import Line, Zone
from webline.physics.roll import roll_inertia
from webline.profiles import breakpoints, pwl_value
from webline.report.text.display import Display, profile_text
from webline.report.text.tables import Table, make_table
from webline.spec.dancer import DancerCarriage
from webline.spec.roll_inertia import roll_constants
from webline.spec.schema import DancerSpec, RewindSpec, UnwindSpec
from webline.spec.splice import FlyingSplice
from webline.spec.winder import WebBreak

#: what the dancer's ``use`` makes of it, in words
DANCER_USES = {"position": "position control (its load sets the tension)",
               "tension": "tension sensor (read as (load - spring·(y - set))/2)",
               "none": "web store and filter (the loadcell is read)"}


def zone_dancer(line: Line, zone: Zone) -> int | None:
    """The dancer node inside ``zone`` (None if it has none)."""
    return next((i for i in range(zone.first + 1, zone.last)
                 if isinstance(line.spec.rollers[i], DancerSpec)), None)


def _open_loop(line: Line, node: int) -> bool:
    winder = getattr(line.spec.rollers[node], "winder", None)
    return winder is not None and winder.mode == "open_loop"


def tension_setter(line: Line, z: int) -> str:
    """The element that sets zone ``z``'s tension, in words: the dancer in position control
    (its load / 2; the drive holds the carriage's position), the drive reading its dancer as
    a tension sensor, an open-loop roll drive (torque T_ref·R/n, nothing measured), or the
    drive's tension loop on its loadcell."""
    zone = line.zones[z]
    drive = line.node_name(zone.controller)
    dancer = zone_dancer(line, zone)
    if dancer is not None:
        use = line.spec.rollers[dancer].dancer.use  # type: ignore[union-attr]
        if use == "position":
            return (f"dancer {line.node_name(dancer)} (its load / 2; drive {drive} holds "
                    f"the dancer's position)")
        if use == "tension":
            return f"drive {drive}, reading dancer {line.node_name(dancer)} as its sensor"
    if _open_loop(line, zone.controller):
        return f"drive {drive}, open loop (torque T_ref·R/n, no measurement)"
    return f"drive {drive} (loadcell on {line.span_name(zone.loadcell)})"


def tension_setter_short(line: Line, z: int) -> str:
    """``tension_setter`` in a few words, for the schematic: 'dancer dancer', 'rewind (open
    loop)', 'infeed'."""
    zone = line.zones[z]
    dancer = zone_dancer(line, zone)
    if dancer is not None and line.spec.rollers[dancer].dancer.use == "position":  # type: ignore[union-attr]
        return f"dancer {line.node_name(dancer)}"
    suffix = " (open loop)" if _open_loop(line, zone.controller) else ""
    return line.node_name(zone.controller) + suffix


def zones_table(line: Line) -> Table:
    """Each tension zone: its nodes, its loadcell, the element that sets its tension and
    the drive that regulates it."""
    rows = []
    for z, zone in enumerate(line.zones):
        dancer = zone_dancer(line, zone)
        use = None if dancer is None else line.spec.rollers[dancer].dancer.use  # type: ignore[union-attr]
        loadcell = line.span_name(zone.loadcell)
        if use in ("position", "tension") or _open_loop(line, zone.controller):
            loadcell += " (monitors only)"
        rows.append([str(z + 1), f"{line.node_name(zone.first)} → {line.node_name(zone.last)}",
                     loadcell, tension_setter(line, z), line.node_name(zone.controller)])
    return make_table("zones", "Tension zones",
                      ["zone", "between", "loadcell on", "tension set by", "drive"], rows)


def dancer_load_text(line: Line, i: int, d: Display) -> str:
    """A dancer's load in words: as given, or '2 x the zone's reference = ...'."""
    carriage: DancerCarriage = line.spec.rollers[i].dancer  # type: ignore[union-attr]
    if carriage.load is not None:
        return profile_text(carriage.load, "force", d)
    zone = next(zone for zone in line.zones if zone.first < i < zone.last)
    ref = profile_text(line.spec.spans[zone.loadcell].tension, "force", d)
    return f"2 × the zone's reference {ref}"


def dancer_text(line: Line, i: int, d: Display) -> str:
    """A dancer's carriage in words: use, load, stroke, set position, moving mass, spring,
    damper (and its position gains where the file gives them)."""
    c: DancerCarriage = line.spec.rollers[i].dancer  # type: ignore[union-attr]
    parts = [DANCER_USES[c.use], f"load {dancer_load_text(line, i, d)}",
             f"stroke {d.text(c.travel, 'length')}",
             f"position set point {d.text(c.position, 'length')}",
             f"moving mass {d.text(c.moving_mass, 'mass')}"]
    if c.stiffness:
        parts.append(f"spring {d.text(c.stiffness, 'stiffness')}")
    if c.damping:
        parts.append(f"damper {d.text(c.damping, 'linear_damping')}")
    if c.position_kp is not None or c.position_ki is not None:
        parts.append(f"position PI kp {c.position_kp or 0:g} 1/s, ki {c.position_ki or 0:g} "
                     "1/s²")
    return "; ".join(parts)


def taper_text(taper: object, d: Display) -> str:
    """A rewind's taper in words: form, amount and its diameters."""
    kind = taper.type  # type: ignore[attr-defined]
    if kind == "table":
        points = ", ".join(f"{d.text(dia, 'length', 3)}: {f:g}" for dia, f in
                           zip(taper.diameter, taper.factor, strict=True))  # type: ignore[attr-defined]
        return f"table of factors against diameter ({points})"
    text = f"{kind}: {100 * taper.taper:g} % less than the zone's set tension"  # type: ignore[attr-defined]
    if kind == "linear":
        return text + f" at {d.text(taper.max_diameter, 'length')}, none at the core"  # type: ignore[attr-defined]
    return text + " at an infinite diameter (f = 1 - taper (1 - D_core/D))"


def diameter_text(line: Line, spec: object, d: Display) -> str:
    """A diameter calculator in words: method, its source, filter, limits, start."""
    if spec.method == "speed_ratio":  # type: ignore[attr-defined]
        text = (f"speed ratio (line speed from the master roller "
                f"{line.node_name(line.master)} over the spindle speed), filter "
                f"{d.text(spec.filter, 'time')}")  # type: ignore[attr-defined]
        if spec.rate_limit is not None:  # type: ignore[attr-defined]
            text += f", rate limit {d.text(spec.rate_limit, 'speed')}"  # type: ignore[attr-defined]
        text += f", held below {d.text(spec.hold_below, 'speed')}"  # type: ignore[attr-defined]
    else:
        text = "thickness integration (two web thicknesses a revolution, from the spindle speed)"
    initial = spec.initial  # type: ignore[attr-defined]
    start = "the measured diameter" if initial == "measured" else d.text(initial, "length")
    return f"{text}; starts from {start}"


def compensation_text(winder: object, d: Display) -> str:
    """A roll drive's compensations in words ('' without)."""
    parts = []
    if winder.inertia_compensation:  # type: ignore[attr-defined]
        parts.append("inertia J(D)·a_line/R")
    if winder.static_friction:  # type: ignore[attr-defined]
        parts.append(f"static friction {d.text(winder.static_friction, 'torque')}")  # type: ignore[attr-defined]
    if winder.viscous_friction:  # type: ignore[attr-defined]
        parts.append(f"viscous friction {d.text(winder.viscous_friction, 'rot_damping')}")  # type: ignore[attr-defined]
    return ", ".join(parts)


def break_text(item: WebBreak, d: Display) -> str:
    """A web break and its monitor in words."""
    diameter = (f", a speed-ratio diameter running the wrong way by "
                f"{d.text(item.diameter_threshold, 'length')}" if item.diameter_threshold
                else "")
    return (f"{item.span} breaks at {d.text(item.at, 'time')}; monitor: a loadcell below "
            f"{100 * item.threshold:g} % of its reference, a dancer on an end stop{diameter}; "
            f"reaction: ramp to a stop in {d.text(item.stop_time, 'time')}")


def splice_text(line: Line, item: FlyingSplice, d: Display) -> str:
    """A flying splice in words, with the time the new roll's drive needs at least to bring
    it to line speed at its torque limit: J(R_new) ω / (n τ_limit), ω = v_line(at) / R_new."""
    roll = line.spec.rollers[0 if item.roll == line.node_name(0) else -1]
    radius = item.new_diameter / 2.0
    drive = roll.drive  # type: ignore[union-attr]
    core, density = roll_constants(roll, line.spec.web)  # the web's, or the totals' (J1)
    inertia = roll_inertia(core + drive.ratio**2 * drive.motor_inertia, radius,
                           roll.core_radius, line.spec.web.width,  # type: ignore[union-attr]
                           density)
    t, v = breakpoints(line.spec.speed)
    omega = abs(float(pwl_value(t, v, item.at))) / radius
    slack = f"slack {d.text(item.slack, 'length')}" if item.slack else "no slack"
    return (f"at {d.text(item.at, 'time')} onto a {d.text(item.new_diameter, 'length')} roll, "
            f"surface speed {100 * item.speed_mismatch:+.3g} %, {slack}; the new roll "
            f"({d.text(inertia, 'inertia')}) reaches {omega:.4g} rad/s in "
            f"{inertia * omega / (drive.ratio * drive.torque_limit):.3g} s at the least "
            "(its drive's torque limit)")


def winder_rows(line: Line, d: Display) -> list[list[str]]:
    """[element, function, setting] of every winder function the line has."""
    rows: list[list[str]] = []
    for i, roller in enumerate(line.spec.rollers):
        if isinstance(roller, DancerSpec):
            rows.append([roller.name, "dancer", dancer_text(line, i, d)])
        if not isinstance(roller, UnwindSpec | RewindSpec):
            continue
        winder = roller.winder
        if winder is not None and winder.mode == "open_loop":
            rows.append([roller.name, "open-loop (indirect) tension",
                         "torque = ±T_ref·R/n plus compensations; no loadcell, no speed loop"])
        if isinstance(roller, RewindSpec) and roller.taper is not None:
            rows.append([roller.name, "taper", taper_text(roller.taper, d)])
        if roller.diameter is not None:
            rows.append([roller.name, "diameter calculation",
                         diameter_text(line, roller.diameter, d)])
        if winder is not None and compensation_text(winder, d):
            rows.append([roller.name, "compensation", compensation_text(winder, d)])
    for item in line.spec.disturbances:
        if isinstance(item, WebBreak):
            rows.append([item.span, "web break and break monitoring", break_text(item, d)])
        if isinstance(item, FlyingSplice):
            rows.append([item.roll, "flying splice", splice_text(line, item, d)])
    return rows


def winder_table(line: Line, d: Display) -> Table:
    """The winder functions table (``winder_rows``)."""
    return make_table("winder", "Winder functions", ["element", "function", "setting"],
                      winder_rows(line, d))


def roll_labels(line: Line, i: int) -> list[str]:
    """Short labels of roll ``i``'s winder functions for the schematic."""
    roller = line.spec.rollers[i]
    labels: list[str] = []
    winder = getattr(roller, "winder", None)
    if winder is not None and winder.mode == "open_loop":
        labels.append("open loop")
    taper = getattr(roller, "taper", None)
    if taper is not None:
        labels.append(f"taper {taper.type}" + (f" {100 * taper.taper:g} %"
                                                if taper.type != "table" else ""))
    diameter = getattr(roller, "diameter", None)
    if diameter is not None:
        labels.append("D calc: " + diameter.method.replace("_", " "))
    if winder is not None and winder.inertia_compensation:
        labels.append("inertia comp.")
    if winder is not None and (winder.static_friction or winder.viscous_friction):
        labels.append("friction comp.")
    labels += [f"splice at {s.at:g} s" for s in line.spec.disturbances
               if isinstance(s, FlyingSplice) and s.roll == roller.name]
    return labels


def dancer_label(line: Line, i: int, d: Display) -> str:
    """The dancer's label on the schematic: use, load, stroke and set position."""
    c: DancerCarriage = line.spec.rollers[i].dancer  # type: ignore[union-attr]
    load = (profile_text(c.load, "force", d) if c.load is not None else "2 T_ref")
    return (f"dancer: {c.use}\nload {load}\nstroke {d.text(c.travel, 'length', 3)}, "
            f"set {d.text(c.position, 'length', 3)}")
