"""Tables of a branched line (docs/branching.md) and of its run, as text cells that both the
terminal (``webline show``) and the HTML report show: the line, its webs, rollers, spans and
drives with their zones; per web and lane the run's tensions and the verdict's findings."""

from __future__ import annotations

from webline.model.web_graph import BranchedLine
from webline.report.text.describe import backlash_text, sensors_table, transmission_text
from webline.report.text.display import Display, number_text, profile_text
from webline.report.text.tables import Table, make_table
from webline.sim.branches.result import BranchResult
from webline.spec.branched.check import kind_of
from webline.spec.roll_inertia import RollTotal, RollTotals
from webline.spec.schema import DrivenSpec, DriveSpec, IdleSpec, RewindSpec, UnwindSpec

SI = Display("si")
#: the drives table's columns of a line with a compliant transmission or a brake
TRAIN_COLUMNS = ["transmission", "backlash", "speed measured on", "brake"]
#: small lengths (radii, widths) and thicknesses: (factor from m, unit) per unit system
SMALL = {"si": (1e3, "mm"), "imperial": (1.0 / 0.0254, "in")}
THIN = {"si": (1e6, "µm"), "imperial": (1.0 / 25.4e-6, "mil")}


def small_length(display: Display) -> tuple[float, str]:
    """(factor from m, unit) of radii and widths in ``display``'s system: mm or in."""
    return SMALL["imperial" if display.system.startswith("imperial") else "si"]


def thin_length(display: Display) -> tuple[float, str]:
    """(factor from m, unit) of thicknesses in ``display``'s system: µm or mil."""
    return THIN["imperial" if display.system.startswith("imperial") else "si"]


def roller_kind(line: BranchedLine, i: int) -> str:
    """'unwind', 'rewind', 'idle', 'master' or 'tension'; a junction adds 'lamination nip'
    (webs end there and a laminate starts) or 'slitter' (a web ends there and lanes start), a
    shaft the lanes wound on it."""
    roller = line.spec.rollers[i]
    kind = roller.role if isinstance(roller, DrivenSpec) else roller.type
    extra = [junction_kind(line, i)]
    lanes = shaft_lanes(line).get(i)
    if lanes:
        extra.append("lanes on one shaft: " + " + ".join(line.spec.webs[w].name for w in lanes))
    return ", ".join([kind, *(e for e in extra if e)])


def junction_kind(line: BranchedLine, i: int) -> str:
    """'lamination nip', 'slitter' or '' for node ``i`` (``BranchedLine.junctions``)."""
    if i not in line.junctions:
        return ""
    name = line.spec.rollers[i].name
    starting = [w for w in line.spec.webs if w.path[0] == name]
    return "lamination nip" if any(kind_of(w) == "laminate" for w in starting) else "slitter"


def shaft_lanes(line: BranchedLine) -> dict[int, list[int]]:
    """Roll node -> the webs wound or unwound on it, for nodes holding more than one (lanes
    on one shaft)."""
    webs: dict[int, list[int]] = {}
    for roll in line.rolls:
        webs.setdefault(roll.node, []).append(roll.web)
    return {node: ws for node, ws in webs.items() if len(ws) > 1}


def inertia_text(inertia: object, display: Display = SI) -> str:
    """A roller's inertia in ``display``'s unit: a number, or a roll's stated totals
    (``spec.roll_inertia``)."""
    j, m = display.factor("inertia"), display.factor("length")
    unit = display.unit("length")
    if isinstance(inertia, RollTotals):
        return (f"empty {number_text(j * inertia.empty)}, full {number_text(j * inertia.full)} "
                f"at ⌀ {number_text(m * inertia.full_diameter)} {unit}")
    if isinstance(inertia, RollTotal):
        return (f"{number_text(j * inertia.total)} at ⌀ {number_text(m * inertia.diameter)} "
                f"{unit}")
    return number_text(j * float(inertia))  # type: ignore[arg-type]


def span_display(display: Display, line: BranchedLine, k: int) -> Display:
    """``display`` for the tension of span ``k``: per width of its own web or lane in a
    per-width system (``Display.at_width``)."""
    return display.at_width(line.materials[line.spans[k].web].width)


def force_label(display: Display, name: str) -> str:
    """A column label of forces on the webs: per width (N/m, pli) in a per-width system,
    each row divided by its own web's width."""
    return display.at_width(1.0).label(name, "force")


def line_tables(line: BranchedLine, display: Display = SI) -> list[Table]:
    """The line's tables in ``display``'s units ('si' or 'imperial', or per width: each web's
    EA and each span's tension reference per its own web's width): line, webs, rollers,
    spans, drives and their zones, calibrated sensors, scenarios."""
    spec = line.spec
    small, small_unit = small_length(display)
    thin, thin_unit = thin_length(display)
    length = display.factor("length")
    about = make_table("line", "Line", ["key", "value"], [
        ("name", line.name), ("description", spec.description or "–"),
        ("source", spec.source or "–"), ("file", line.source),
        ("scenario", line.scenario or "(none)"), ("line speed", profile_text(
            spec.speed, "speed", display)),
        ("size", f"{len(spec.webs)} webs, {len(spec.rollers)} rollers, {len(line.spans)} "
                 f"spans, {len(line.drives)} drives")])
    webs = []
    for w, web in enumerate(spec.webs):
        m = line.materials[w]
        origin = (f"layers {' + '.join(web.layers or [])}" if web.layers else
                  f"slit from {web.slit_from}" if web.slit_from else "unwind")
        webs.append((web.name, kind_of(web), origin, " → ".join(web.path),
                     number_text(m.ea * display.at_width(m.width).factor("force")),
                     number_text(m.thickness * thin),
                     number_text(m.width * small)))
    rollers = []
    for i, roller in enumerate(spec.rollers):
        core = (number_text(roller.core_radius * small)
                if isinstance(roller, UnwindSpec | RewindSpec) else "–")
        rollers.append((roller.name, roller_kind(line, i), number_text(roller.radius * small),
                        core, inertia_text(roller.inertia, display),
                        number_text(roller.friction * display.factor("rot_damping"))))
    cells = {k for zone in line.zones.values() for k in zone.loadcells}
    spans = []
    for span in line.spans:
        ref = line.span_tension_spec(span.index)
        spans.append((span.name, spec.webs[span.web].name, spec.rollers[span.a].name,
                       spec.rollers[span.b].name, number_text(span.length * length),
                       profile_text(ref, "force", span_display(display, line, span.index))
                       if ref is not None else "–",
                       "yes" if span.index in cells else "no"))
    drives = []
    for i in line.drives:
        roller = spec.rollers[i]
        assert not isinstance(roller, IdleSpec)
        zone = line.zones.get(i)
        what = ("line speed (master)" if zone is None else
                ("sum of " if len(zone.loadcells) > 1 else "")
                + " + ".join(line.spans[k].name for k in zone.loadcells))
        span_names = ", ".join(line.spans[k].name for k in zone.spans) if zone else "–"
        drives.append((roller.name, what, span_names,
                       number_text(roller.drive.torque_limit * display.factor("torque")),
                       number_text(roller.drive.ratio), *train_cells(roller.drive, display)))
    trains = any(spec.rollers[i].drive.transmission.type != "direct"  # type: ignore[union-attr]
                 or spec.rollers[i].drive.brake is not None  # type: ignore[union-attr]
                 for i in line.drives)  # compliant or braked drives: their columns
    drives = [row[:5] + (row[5:] if trains else ()) for row in drives]
    return [about,
            make_table("webs", "Webs", ["web", "kind", "from", "path", force_label(display, "EA"),
                                        f"thickness [{thin_unit}]", f"width [{small_unit}]"],
                       webs),
            make_table("rollers", "Rollers", [
                "roller", "kind", f"radius [{small_unit}]", f"core radius [{small_unit}]",
                display.label("inertia", "inertia"),
                display.label("viscous friction", "rot_damping")], rollers),
            make_table("spans", "Spans", ["span", "web", "from", "to",
                                          display.label("length", "length"),
                                          "tension reference", "loadcell"], spans),
            make_table("drives", "Drives and their tension zones", [
                "drive", "controls", "zone spans", display.label("torque limit", "torque"),
                "ratio", *(TRAIN_COLUMNS if trains else [])], drives),
            *([sensors_table(line, display)] if spec.sensors else []),
            make_table("scenarios", "Scenarios", ["scenario", "duration [s]", "description"],
                       [(name, number_text(sc.duration), sc.description or "–")
                        for name, sc in spec.scenarios.items()])]


def verdict_table(result: BranchResult, display: Display = SI) -> Table:
    """Per web and lane: its kind, span tension range and final value, its loadcells'
    largest deviation from their reference, length-balance drift (in ``display``'s units) and
    the verdict's findings about it (``BranchResult.verdict``, whose messages are SI)."""
    findings = result.verdict.findings
    length = display.factor("length")
    rows = []
    materials = result.plan.line.materials
    for w, web in enumerate(result.web_summary()):
        force = display.at_width(materials[w].width).factor("force")
        table = web["spans"]
        assert isinstance(table, dict)
        low = min(v["min_N"] for v in table.values())
        high = max(v["max_N"] for v in table.values())
        deviations = [f"{name} {number_text(v['max_deviation_N'] * force)}"
                      for name, v in table.items() if "max_deviation_N" in v]
        about = [f"{f.level}: {f.message}" for f in findings if f.where == web["web"]]
        rows.append((str(web["web"]), str(web["kind"]), f"{number_text(low * force)} to "
                     f"{number_text(high * force)}", ", ".join(deviations) or "–",
                     number_text(length * float(web["length_balance_drift_m"]), 2),  # type: ignore[arg-type]
                     "; ".join(about) or "ok"))
    return make_table("verdict", "Verdict per web and lane", [
        "web", "kind", force_label(display, "span tensions"),
        force_label(display, "largest deviation from reference"),
        display.label("length balance drift", "length"), "findings"], rows)


def drive_findings_table(result: BranchResult) -> Table:
    """The verdict's findings about drives and the run (torque limits, a stopped run)."""
    webs = {w.name for w in result.plan.line.spec.webs}
    rows = [(f.level, f.kind, f.where, f.message) for f in result.verdict.findings
            if f.where not in webs]
    return make_table("drive_findings", "Findings about drives and the run",
                      ["level", "kind", "where", "finding"], rows)


def train_cells(drive: DriveSpec, display: Display) -> tuple[str, ...]:
    """A drive's transmission, backlash, speed-loop side and brake as the chain's drives
    table words them."""
    return (transmission_text(drive.transmission, display),
            backlash_text(getattr(drive.transmission, "backlash", None), display),
            drive.feedback, profile_text(drive.brake, "torque", display) or "none")
