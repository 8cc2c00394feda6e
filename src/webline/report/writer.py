"""Writing a run to a folder: the HTML report, its figures (PNG, and SVG on request), a JSON
summary and the results (NetCDF or CSV, always SI)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING

from webline.analysis.modes import Mode, closed_loop_modes
from webline.analysis.zone_loops import ZoneLoop, speed_leaks, zone_loops
from webline.control.zone_tuning import SpeedLoopLeak
from webline.errors import ArgumentError, WeblineError
from webline.files import atomic_write_bytes, atomic_write_text
from webline.limits import MAX_EIGEN_STATES
from webline.line import Line
from webline.model.operating_point import OperatingPoint, analysis_time, operating_point
from webline.report.outputs import OutputFolder, ReportFiles
from webline.report.plots.big_lines import condensed, summarised
from webline.report.plots.figures import figure_jobs
from webline.report.render import render_figures
from webline.report.text.describe import line_tables
from webline.report.text.display import SYSTEMS, Display, System
from webline.report.text.html import Image, Section, Text, render
from webline.report.text.tables import (
    Table,
    json_safe,
    make_table,
    modes_table,
    operating_point_tables,
    operating_point_values,
    summary_tables,
    summary_values,
)
from webline.report.text.verdict_text import STATUS_CLASS, events_parts
from webline.report.text.zone_tables import (
    leak_lines,
    roll_modes_table,
    roll_modes_values,
    zone_loops_table,
)
from webline.sim.results.result import Result
from webline.spec.load import dump_spec

if TYPE_CHECKING:  # imported where a branched run's report is written
    from webline.sim.branches.result import BranchResult

#: Resolution of the PNG figures [dots per inch].
DPI = 110


@dataclass(frozen=True)
class Analysis:
    """Operating point and closed-loop modes of a line at time ``time`` [s], or why there are
    none (``problem``)."""

    time: float
    point: OperatingPoint | None
    modes: tuple[Mode, ...]
    problem: str = ""
    zone_loops: tuple[ZoneLoop, ...] = ()
    leaks: tuple[SpeedLoopLeak, ...] = ()
    modes_note: str = ""  #: why there are no modes although there is an operating point


#: the report computes no modes or zone loops of a closed-loop model with more states than
#: this (``limits.MAX_EIGEN_STATES``: a dense eigen-decomposition grows as n³)
MAX_MODE_STATES = MAX_EIGEN_STATES


def analyse(line: Line) -> Analysis:
    """Operating point and closed-loop modes at ``analysis_time(line)``; a line without an
    equilibrium gives an ``Analysis`` that says why instead of raising. A line whose
    closed-loop model has more than ``MAX_MODE_STATES`` states gets no modes, and a note that
    says so (``modes_note``)."""
    from webline.sim.core.plan import compile_plan
    from webline.sim.linear.linearize import plan_linear_model

    t = analysis_time(line)
    try:
        point = operating_point(line, t)
        states = len(plan_linear_model(compile_plan(line), loop="closed", t=t).states)
        note = ""
        if states > MAX_MODE_STATES:
            note = (f"Modes and zone loops not computed: the closed-loop model has {states} "
                    f"states, more than the report's limit of {MAX_MODE_STATES} (a dense "
                    "eigen-decomposition, whose time grows as the cube of the states).")
        modes = () if note else tuple(closed_loop_modes(line, t))
        return Analysis(t, point, modes, zone_loops=tuple(zone_loops(line, t)),
                        leaks=tuple(speed_leaks(line)), modes_note=note)
    except (WeblineError, ValueError, ArithmeticError) as exc:
        return Analysis(t, None, (), str(exc))


def _target(out_dir: Path, folder: OutputFolder | None, relative: str) -> Path:
    """Where ``relative`` goes: claimed in ``folder``'s manifest, or plainly under out_dir."""
    if folder is not None:
        return folder.claim(relative)
    target = out_dir / relative
    target.parent.mkdir(parents=True, exist_ok=True)
    return target


def branch_display(units: str) -> Display:
    """The ``Display`` of a branched line's tables and report. A per-width system
    ('si-per-width': N/m, 'imperial-per-width': pli) comes with a unit width: each web's and
    lane's forces are divided by its own width where they are shown (``Display.at_width``),
    everything else is in the system's base."""
    if units not in SYSTEMS:
        raise ArgumentError(f"units={units!r}: expected one of {', '.join(SYSTEMS)}")
    return Display(units, 1.0 if units.endswith("-per-width") else None)


def write_report(result: Result | BranchResult, out_dir: Path, *, units: System = "si",
                 scenario: str | None = None, results_file: Path | None = None,
                 analysis: Analysis | None = None,
                 folder: OutputFolder | None = None, svg: bool = False) -> ReportFiles:
    """Write ``report.html`` (self-contained), ``summary.json`` and ``figures/*.png`` (and
    ``figures/*.svg`` with ``svg``) for ``result`` into ``out_dir``, every quantity in
    ``units`` ('si', 'imperial', or either per width of web). Each file is
    written atomically; with ``folder`` (the ``OutputFolder`` of ``out_dir``) each joins its
    manifest. A branched line's ``BranchResult`` gets its own report (``branch_report``: 'si'
    or 'imperial', each web and lane having its own width; its scenario the one its line
    ran)."""
    from webline import __version__

    if not isinstance(result, Result):  # a BranchResult (docs/branching.md, Report)
        from webline.report.branch_report import write_branch_report

        return write_branch_report(result, out_dir, folder=folder, results_file=results_file,
                                   svg=svg, display=branch_display(units))
    display = Display(units, result.line.spec.web.width)
    line = result.line
    analysis = analysis or analyse(line)
    images: dict[str, Image] = {}
    written: list[Path] = []
    for fig in render_figures(figure_jobs(result, display, analysis.modes), DPI, svg=svg):
        images[fig.key] = Image(fig.key, fig.caption, fig.png)
        written.append(atomic_write_bytes(_target(out_dir, folder, f"figures/{fig.key}.png"),
                                          fig.png))
        if fig.svg is not None:
            written.append(atomic_write_bytes(
                _target(out_dir, folder, f"figures/{fig.key}.svg"), fig.svg))

    summary = summary_values(result, display)
    content = json_safe({
        "summary": summary, "webline_version": __version__, "scenario": scenario,
        "operating_point": (operating_point_values(analysis.point, display)
                            if analysis.point else None),
        "closed_loop_modes": [m.as_dict() for m in analysis.modes],
        "zone_loops": [loop.as_dict() for loop in analysis.zone_loops],
        "speed_loop_leaks": [leak.message() for leak in analysis.leaks],
        "modes_across_roll": (roll_modes_values(result.roll_modes)
                              if result.roll_modes is not None else None),
        "wound_roll": (result.wound_roll.summary() if result.wound_roll is not None
                       else None),
        "verdict": result.verdict.as_dict(),
    })
    summary_path = atomic_write_text(_target(out_dir, folder, "summary.json"),
                                     json.dumps(content, indent=2, allow_nan=False))

    html = render(
        title=f"webline report: {line.name}" + (f", scenario {scenario}" if scenario else ""),
        subtitle=(line.spec.scenarios[scenario].description if scenario
                  else line.spec.description),
        status=_status_text(result, display), status_class=STATUS_CLASS[result.status],
        headline=result.verdict.headline,
        sections=_sections(result, display, images, analysis, scenario, results_file),
        footer=f"webline {__version__} · generated {datetime.now(UTC):%Y-%m-%d %H:%M} UTC · "
               f"units: {units}",
    )
    report = atomic_write_text(_target(out_dir, folder, "report.html"), html)
    return ReportFiles(report, summary_path, tuple(written))


def _status_text(result: Result, display: Display) -> str:
    """What was simulated and the largest tension error, under the verdict's headline."""
    duration = float(result.time[-1]) if len(result.time) else 0.0
    if result.failure is not None:
        return (f"The run stopped early at t = {result.failure.time:.4g} s; everything "
                f"computed until t = {duration:.4g} s is shown.")
    worst = max(result.summary()["spans"].items(),
                key=lambda item: item[1].get("max_abs_error", -1.0))
    text = f"Run completed: {duration:.4g} s simulated."
    if "max_abs_error" in worst[1]:
        text += (" Largest tension error: "
                 f"{display.text(worst[1]['max_abs_error'], 'force')} in {worst[0]}.")
    return text


def _sections(result: Result, display: Display, images: dict[str, Image], analysis: Analysis,
              scenario: str | None, results_file: Path | None) -> list[Section]:
    from webline import __version__

    line = result.line
    described = {t.key: t for t in line_tables(line, display)}
    if analysis.point is not None:
        op_parts: list = [*operating_point_tables(line, analysis.point, display),
                          Text(analysis.modes_note) if analysis.modes_note
                          else modes_table(analysis.modes)]
        if analysis.zone_loops:
            op_parts.append(zone_loops_table(analysis.zone_loops))
        op_parts += [Text(line) for line in leak_lines(analysis.leaks)]
        if result.roll_modes is not None:  # a run across a roll: its modes along the way
            op_parts.append(roll_modes_table(result.roll_modes, display))
            if "across_roll" in images:
                op_parts.append(images["across_roll"])
        if "poles" in images:
            op_parts.append(images["poles"])
        op_parts.insert(0, Text(f"Equilibrium of the line at its references at t = "
                                f"{analysis.time:g} s, roll radii at their initial values; the "
                                "modes are those of the line with its controllers (as "
                                "continuous-time laws) linearized there."))
    else:
        op_parts = [Text(f"No operating point: {analysis.problem}")]
    settings = result.settings
    run_rows = [("webline version", __version__), ("line file", line.source),
                ("scenario", scenario or "(none)"),
                ("duration", f"{settings.get('duration', float('nan')):g} s"),
                ("controller period", f"{settings.get('dt', float('nan')) * 1e3:g} ms"),
                ("RK4 sub-steps per period", f"{settings.get('substeps', 0):g}"),
                ("records", str(len(result.time))),
                ("results file (SI)", str(results_file.name) if results_file else "(none)")]
    line_parts = [described["line"], described["rollers"], described["spans"],
                  described["drives"], described["zones"],
                  *([described["winder"]] if "winder" in described else []),
                  *([described["sensors"]] if "sensors" in described else [])]
    summary_parts = [*summary_tables(result, display), *_verdict_parts(result)]
    if summarised(line):  # hundreds of rows: the first and last of each table
        line_parts = [condensed(p) for p in line_parts]
        summary_parts = [condensed(p) if isinstance(p, Table) else p for p in summary_parts]
        op_parts = [condensed(p) if isinstance(p, Table) else p for p in op_parts]
    return [
        Section("Line", [images["schematic"], *line_parts]),
        Section("Summary", summary_parts),
        # every figure of the run in report order, but the line's and the modes' own
        Section("Time plots", [image for key, image in images.items()
                               if key not in ("schematic", "poles", "across_roll")]),
        Section("Operating point and modes", op_parts),
        Section("Run", [make_table("run", "Settings", ["key", "value"], run_rows)]),
        Section("Resolved line file", [Text(dump_spec(line.spec), pre=True,
                                            fold="The line as it ran (scenario applied), every "
                                                 "quantity in SI units: show the TOML")]),
    ]


def _verdict_parts(result: Result) -> list[Table | Text]:
    """The verdict's findings, and the events table (one row per kind and element)."""
    parts: list[Table | Text] = [Text(f"Verdict: {f.level}, {f.kind} in {f.where}: {f.message}.")
                                 for f in result.verdict.findings if f.level != "warning"]
    return parts + events_parts(result.events)
