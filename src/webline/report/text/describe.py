"""A line described as tables (sections, rollers, spans, drives, controllers, scenarios) in the
chosen units: what ``webline show`` prints and the report's line section shows."""

from __future__ import annotations

from typing import TYPE_CHECKING

from webline.line import Line
from webline.report.text.describe_winder import winder_table, zones_table
from webline.report.text.display import Display, profile_text
from webline.report.text.tables import Table, make_table, node_kind
from webline.spec.roll_inertia import roll_constants
from webline.spec.schema import IdleSpec, RewindSpec, UnwindSpec

if TYPE_CHECKING:  # (a single-path run imports no branched line: tests/unit/test_startup.py)
    from webline.model.web_graph import BranchedLine


def line_tables(line: Line, display: Display) -> list[Table]:
    """Tables describing ``line``: overview, rollers, spans, drives and controllers, zones,
    winder functions (dancers, taper, diameter calculation, compensation, open loop, break
    monitoring), calibrated sensors, disturbances and scenarios, every quantity in the chosen
    units."""
    tables = [_overview(line, display), _rollers(line, display), _spans(line, display),
              _drives(line, display), zones_table(line)]
    winder = winder_table(line, display)
    sensors = ([sensors_table(line, display)] if getattr(line.spec, "sensors", None) else [])
    return tables + ([winder] if winder.rows else []) + sensors + [
        _disturbances(line, display), _scenarios(line)]


def sensors_table(line: Line | BranchedLine, d: Display) -> Table:
    """The calibrated sensors (``spec.sensors``): what each measures and what its controller
    reads there."""
    rows = []
    for s in line.spec.sensors:
        if s.type == "loadcell":
            where = f"span {s.span}"
            sign = "+" if s.offset >= 0 else "-"
            reads = f"{s.gain:g} x T {sign} {d.text(abs(s.offset), 'force')}"
        else:
            where = f"roller {s.roller}"
            reads = f"{s.scale:g} x v"
        if s.delay > 0:
            reads += f", {d.text(s.delay, 'time')} late"
        rows.append([s.name, s.type, where, reads])
    return make_table("sensors", "Sensors (what the controllers read)",
                      ["sensor", "type", "measures", "reads"], rows)


def _overview(line: Line, d: Display) -> Table:
    spec, web = line.spec, line.spec.web
    rows = [("name", spec.name), ("description", spec.description), ("source", spec.source),
            ("file", line.source), ("line speed reference", profile_text(spec.speed, "speed", d)),
            ("web EA", d.text(line.ea, "force")),
            ("web stress-strain law", _law_text(line)),
            ("web thickness", _thickness(web.thickness, d)),
            ("web width", d.text(web.width, "length")),
            ("web density", d.text(web.density, "density")),
            ("control sample rate", f"{spec.control.sample_rate:g} Hz"),
            ("size", f"{line.n_nodes} rollers, {line.n_spans} spans, {len(line.drives)} drives, "
                     f"{len(line.zones)} tension zones")]
    return make_table("line", "Line", ["key", "value"], [r for r in rows if r[1]])


def _law_text(line: Line) -> str:
    """The web's stress-strain law in words (docs/nonlinear-web.md), "" for a linear web."""
    law = line.spec.web.stress_strain
    if law is None or not line.nonlinear:
        return ""
    if law.law == "power":
        text = f"power: σ = E ε_r (ε/ε_r)^{law.exponent:g}, ε_r = {law.reference_strain:g}"
    elif law.law == "bilinear":
        text = f"bilinear: {law.hardening:g} E beyond yield"
    else:
        text = f"table of {len(law.strain or [])} points"
    if law.yield_strain is not None:
        text += f", yield at ε = {100 * law.yield_strain:.3g} %"
    return text


def _thickness(thickness: float, d: Display) -> str:
    """Web thickness [m] in µm (SI) or mil (imperial, 1 mil = 25.4 µm)."""
    if d.system.startswith("imperial"):
        return f"{thickness / 25.4e-6:.4g} mil"
    return f"{thickness * 1e6:.4g} µm"


def _rollers(line: Line, d: Display) -> Table:
    rows = []
    for i, r in enumerate(line.spec.rollers):
        core = d.text(r.core_radius, "length") if isinstance(r, UnwindSpec | RewindSpec) else ""
        rows.append([str(i), r.name, node_kind(line, i), d.text(r.radius, "length"), core,
                     _inertia_text(r, line, d), d.text(r.friction, "rot_damping"),
                     "" if isinstance(r, IdleSpec) else "yes",
                     nip_text(getattr(r, "nip", None), r.radius, d)])
    columns = ["#", "name", "kind", "radius", "core radius", "inertia", "viscous friction",
               "driven", "nip"]
    if not any(row[-1] for row in rows):  # a nip column only for a line with nips
        columns, rows = columns[:-1], [row[:-1] for row in rows]
    return make_table("rollers", "Rollers (web order)", columns, rows)


def _inertia_text(roller: object, line: Line, d: Display) -> str:
    """A roller's inertia without web; a roll's derived core where the file gave totals."""
    inertia = roller.inertia  # type: ignore[attr-defined]
    if isinstance(inertia, float | int):
        return d.text(inertia, "inertia")
    core, density = roll_constants(roller, line.spec.web)
    return (f"{d.text(core, 'inertia')} (from {inertia.type}; wound "
            f"{d.text(density, 'density')})")


def nip_text(nip: object, radius: float, d: Display) -> str:
    """A roller's nip in words (docs/winder.md, Nip): ``'gripped, 1300 N; pressure roller
    0.06 m, 0.08 kg·m² (adds 0.2222 kg·m²)'``, with μ_n for a traction nip; ``''`` without.
    ``radius`` [m] is the roller's (for the reflected inertia)."""
    if nip is None:
        return ""
    grip = nip.grip  # type: ignore[attr-defined]
    if grip == "traction":
        grip = f"traction μ {nip.friction:g}"  # type: ignore[attr-defined]
    reflected = nip.reflected(radius)[0]  # type: ignore[attr-defined]
    return (f"{grip}, {d.text(nip.load, 'force')}; pressure roller "  # type: ignore[attr-defined]
            f"{d.text(nip.radius, 'length')}, {d.text(nip.inertia, 'inertia')} "  # type: ignore[attr-defined]
            f"(adds {d.text(reflected, 'inertia')})")


def _spans(line: Line, d: Display) -> Table:
    rows = []
    for k, span in enumerate(line.spec.spans):
        rows.append([line.span_name(k), f"{line.node_name(k)} → {line.node_name(k + 1)}",
                     d.text(span.length, "length"), str(line.zone_of_span(k) + 1),
                     profile_text(span.tension, "force", d) or "(no loadcell)",
                     "elastic" if span.model == "elastic" else
                     f"Kelvin-Voigt, τ = {d.text(span.retardation, 'time')}"])
    return make_table("spans", "Spans", ["span", "from → to", "length", "zone",
                                         "tension reference (loadcell)", "web model"], rows)


def _drives(line: Line, d: Display) -> Table:
    rows = []
    for i in line.drives:
        r = line.spec.rollers[i]
        assert not isinstance(r, IdleSpec)
        drive = r.drive
        zone = line.controlled_zone(i)
        task = "line speed (master)" if zone is None else \
            f"tension of {line.span_name(line.zones[zone].loadcell)} (zone {zone + 1})"
        rows.append([r.name, f"{drive.ratio:g}", transmission_text(drive.transmission, d),
                     backlash_text(getattr(drive.transmission, "backlash", None), d),
                     drive.feedback, profile_text(drive.brake, "torque", d) or "none",
                     d.text(drive.torque_limit, "torque"),
                     f"{drive.torque_lag * 1e3:g} ms", d.text(drive.motor_inertia, "inertia"),
                     _controller(r, zone is not None), task])
    return make_table("drives", "Drives and controllers",
                      ["drive", "ratio (motor/roller)", "transmission", "backlash",
                       "speed measured on", "brake", "torque limit", "torque lag",
                       "motor inertia", "controller", "controls"], rows)


def _controller(roller: object, tension_loop: bool) -> str:
    """The drive's controller in words; an open-loop winder's torque law in place of its
    (unused) controller."""
    winder = getattr(roller, "winder", None)
    if tension_loop and winder is not None and winder.mode == "open_loop":
        return "open loop (indirect tension): torque = ±T_ref·R/n, no speed loop"
    return controller_text(roller.controller, tension_loop)  # type: ignore[attr-defined]


def transmission_text(transmission: object, d: Display) -> str:
    """A drive's transmission in words: ``'direct'``, ``'belt 2e+05 N/m, load pulley radius
    0.0508 m'``, ``'shaft 500 N·m/rad'`` (damping added where set)."""
    kind = getattr(transmission, "type", "direct")
    if kind == "belt":
        text = (f"belt {d.text(transmission.stiffness, 'stiffness')}, load pulley radius "  # type: ignore[attr-defined]
                f"{d.text(transmission.load_pulley_radius, 'length')}")  # type: ignore[attr-defined]
        damping = transmission.damping  # type: ignore[attr-defined]
        return text + (f", damping {d.text(damping, 'linear_damping')}" if damping else "")
    if kind == "shaft":
        text = f"shaft {d.text(transmission.stiffness, 'torque')}/rad"  # type: ignore[attr-defined]
        damping = transmission.damping  # type: ignore[attr-defined]
        return text + (f", damping {d.text(damping, 'rot_damping')}/rad" if damping else "")
    return "direct"


def backlash_text(backlash: object, d: Display) -> str:
    """A backlash in words: ``'±0.01 rad'`` (the load's free travel either way, at the load
    shaft), ``'-0.004 rad / +0.016 rad'`` when asymmetric; ``'none'``."""
    if backlash is None:
        return "none"
    gap, a = backlash.gap, backlash.asymmetry  # type: ignore[attr-defined]
    if a == 0.5:
        return f"±{d.text(gap, 'angle')}"
    return f"-{d.text(2 * gap * a, 'angle')} / +{d.text(2 * gap * (1 - a), 'angle')}"


def controller_text(controller: object, tension_loop: bool) -> str:
    """A controller in words: its type and its settings (SI), e.g. ``'cascaded_pi: speed loop
    40 rad/s, tension loop 8 rad/s, ζ = 1'``."""
    kind = getattr(controller, "type", "?")
    if kind == "cascaded_pi":
        text = f"cascaded_pi: speed loop {controller.speed_bandwidth:g} rad/s"  # type: ignore[attr-defined]
        if tension_loop:
            text += f", tension loop {controller.tension_bandwidth:g} rad/s"  # type: ignore[attr-defined]
        return text + f", ζ = {controller.damping:g}"  # type: ignore[attr-defined]
    return kind + _settings(controller)


def _settings(item: object) -> str:
    """``': key = value, ...'`` for the keys of a spec that are set (type excluded)."""
    dump = getattr(item, "model_dump", None)
    values = dump(exclude_none=True) if dump else {}
    parts = [f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
             for k, v in values.items() if k != "type"]
    return ": " + ", ".join(parts) if parts else ""


def disturbance_text(item: object, d: Display) -> str:
    """One disturbance in words, in the chosen units."""
    kind = getattr(item, "type", "")
    if kind == "wound_in_ripple":
        return (f"wound-in tension ripple {d.text(item.amplitude, 'force')} at "  # type: ignore[attr-defined]
                f"{item.frequency:g} Hz")  # type: ignore[attr-defined]
    if kind == "eccentric_roller":
        return (f"eccentric roller {item.roller}: "  # type: ignore[attr-defined]
                f"{d.text(item.eccentricity, 'length')}")  # type: ignore[attr-defined]
    if kind == "flying_splice":
        return (f"flying splice of {item.roll} at {d.text(item.at, 'time')} onto a "  # type: ignore[attr-defined]
                f"{d.text(item.new_diameter, 'length')} roll, surface speed "  # type: ignore[attr-defined]
                f"{100 * item.speed_mismatch:+.3g} %, slack {d.text(item.slack, 'length')}")  # type: ignore[attr-defined]
    if kind == "speed_ripple":
        return (f"speed ripple on {item.roller}: {d.text(item.amplitude, 'speed')} at "  # type: ignore[attr-defined]
                f"{item.frequency:g} Hz")  # type: ignore[attr-defined]
    return f"{kind}{_settings(item)} (SI)"


def _disturbances(line: Line, d: Display) -> Table:
    rows = [[str(j + 1), disturbance_text(item, d)]
            for j, item in enumerate(line.spec.disturbances)]
    return make_table("disturbances", "Disturbances", ["#", "disturbance"], rows)


def _scenarios(line: Line) -> Table:
    rows = [[name, f"{s.duration:g} s", s.description]
            for name, s in line.spec.scenarios.items()]
    return make_table("scenarios", "Scenarios", ["scenario", "duration", "description"], rows)
