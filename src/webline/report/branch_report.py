"""The HTML report of a branched line's run (docs/branching.md, "Report"): the verdict per web
and lane, the line's description, source and tables, every figure with its computed caption,
the run's settings and the resolved line file; and the notebook view of a branched line and
of its result."""

from __future__ import annotations

import io
import json
from datetime import UTC, datetime
from pathlib import Path

from webline.errors import WeblineError
from webline.files import atomic_write_bytes, atomic_write_text
from webline.model.web_graph import BranchedLine
from webline.report.outputs import OutputFolder, ReportFiles
from webline.report.plots.branch_figures import branch_figure_jobs, deviation_text
from webline.report.render import render_figures
from webline.report.text.branch_tables import (
    SI,
    drive_findings_table,
    line_tables,
    verdict_table,
)
from webline.report.text.display import Display, number_text
from webline.report.text.html import Image, Section, Text, render, table_html
from webline.report.text.tables import (
    Table,
    json_safe,
    least_damped,
    make_table,
    modes_table,
    summary_tables,
    summary_values,
)
from webline.report.text.verdict_text import STATUS_CLASS, events_parts
from webline.sim.branches.result import BranchResult
from webline.sim.branches.winder import splice_summary
from webline.spec.load import dump_spec
from webline.version import __version__

#: Resolution of the PNG figures [dots per inch] (the chain report's)
DPI = 110


def write_branch_report(result: BranchResult, out_dir: Path, *,
                        folder: OutputFolder | None = None, results_file: Path | None = None,
                        svg: bool = False, display: Display = SI) -> ReportFiles:
    """Write ``figures/KEY.png`` (and ``figures/KEY.svg`` with ``svg``) for every figure,
    ``summary.json`` (settings, verdict, a single-path run's ``summary``: spans, drives and
    events; per web its span tensions and length balance, each wound roll's numbers:
    ``WoundRoll.summary``) and a
    self-contained ``report.html`` for ``result`` into ``out_dir``, each atomically; with
    ``folder`` (the ``OutputFolder`` of ``out_dir``) each joins its manifest. The figures and
    the report's tables and captions are in ``display``'s units ('si' or 'imperial');
    ``summary.json`` stays SI (its keys name their units), as ``results.nc`` does."""
    def target(relative: str) -> Path:
        if folder is not None:
            return folder.claim(relative)
        path = out_dir / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        return path

    images: dict[str, Image] = {}
    written = []
    for fig in render_figures(branch_figure_jobs(result, display), DPI, svg=svg):
        images[fig.key] = Image(fig.key, fig.caption, fig.png)
        written.append(atomic_write_bytes(target(f"figures/{fig.key}.png"), fig.png))
        if fig.svg is not None:
            written.append(atomic_write_bytes(target(f"figures/{fig.key}.svg"), fig.svg))
    line = result.plan.line
    summary = {"line": line.name, "scenario": line.scenario, "webline_version": __version__,
               "settings": result.settings, "verdict": result.verdict.as_dict(),
               # the single-path summary (spans, drives, events; its speed errors null)
               "summary": json_safe(summary_values(result, SI)),
               "webs": result.web_summary(), "splices": splice_summary(result),
               "wound_rolls": [roll.summary() for roll in result.wound_rolls.values()],
               "failure": result.failure}
    summary_path = atomic_write_text(target("summary.json"),
                                     json.dumps(summary, indent=1) + "\n")
    report = atomic_write_text(target("report.html"),
                               report_html(result, images, results_file, display))
    return ReportFiles(report, summary_path, tuple(written))


def status_text(result: BranchResult, display: Display = SI) -> str:
    """What was simulated and its largest deviation from a tension reference."""
    duration = float(result.time[-1]) if len(result.time) else 0.0
    if result.failure is not None:
        return (f"The run stopped early: {result.failure}; everything computed until "
                f"t = {duration:.4g} s is shown.")
    text = f"Run completed: {duration:.4g} s simulated."
    deviation = deviation_text(result, display)
    if deviation:
        text += f" Largest deviation from a tension reference: {deviation}."
    return text


def modes_parts(result: BranchResult) -> list[Table | Text]:
    """The closed-loop modes of the run's line at its analysis time (docs/branching.md,
    "Linear models"): what they are, their table, the least damped one and the stability
    verdict (continuous model and the loop as sampled); or why there are none."""
    from webline.analysis.modes import closed_loop_modes
    from webline.sim.branches.equilibrium import operating_point
    from webline.sim.branches.linear import analysis_time, stability_findings

    line = result.plan.line
    from webline.sim.branches.loop import layout as B

    users = [line.spec.rollers[int(i)].name for i, family in zip(
        result.plan.di[:, B.DI_NODE], result.plan.di[:, B.DI_FAMILY], strict=True)
        if family == B.FAMILY_USER]
    if users:
        return [Text(f"No closed-loop modes: {', '.join(users)} ran a user's Python "
                     "controller, which has no linear model in webline (docs/controllers.md).")]
    t = analysis_time(line)
    try:
        modes = closed_loop_modes(line, t)
        unstable = stability_findings(result.plan, operating_point(result.plan, t), t)
    except (WeblineError, ValueError, ArithmeticError) as exc:
        return [Text(f"No closed-loop modes: {exc}")]
    parts: list[Table | Text] = [
        Text(f"The line with its controllers (as continuous-time laws) linearized at its "
             f"operating point at t = {t:g} s of its references, roll radii at their initial "
             "values (docs/branching.md, Linear models)."), modes_table(modes)]
    weakest = least_damped(modes)
    if weakest is not None:
        parts.append(Text(f"Least damped oscillating mode: ζ = {number_text(weakest.damping, 3)}"
                          f" at ωn = {number_text(weakest.natural_frequency)} rad/s, mostly in "
                          f"{weakest.dominant}."))
    parts += [Text(f"Unstable: {f.message}.") for f in unstable] or [Text(
        "No closed-loop mode grows, in the continuous model or in the loop as sampled "
        f"({1.0 / result.plan.dt:.4g} Hz, torque held).")]
    return parts


def report_html(result: BranchResult, images: dict[str, Image],
                results_file: Path | None = None, display: Display = SI) -> str:
    """The report page of ``result`` with the rendered figures ``images`` (by key), its
    numbers in ``display``'s units."""
    line = result.plan.line
    spec = line.spec
    scenario = line.scenario
    settings = result.settings
    run_rows = [("webline version", __version__), ("line file", line.source),
                ("scenario", scenario or "(none)"),
                ("duration", f"{settings.get('duration', float('nan')):g} s"),
                ("controller period", f"{settings.get('dt', float('nan')) * 1e3:g} ms"),
                ("RK4 sub-steps per period", f"{settings.get('substeps', 0):g}"),
                ("recorded every", f"{settings.get('record_every', 0):g} periods"),
                ("records", str(len(result.time))),
                ("results file (SI)", results_file.name if results_file else "(none)")]
    tables = line_tables(line, display)
    findings = drive_findings_table(result)
    sections = [
        Section("Verdict", [verdict_table(result, display), *([findings] if findings.rows else [
            Text("No finding about a drive or the run: no drive's command reached its torque "
                 "limit and the run went to its end.")])]),
        Section("Line", [*tables[:1], *([images["schematic"]] if "schematic" in images else []),
                         *tables[1:]]),
        # the single-path report's summary: span tensions, drives and events
        Section("Summary", [*summary_tables(result, display), *events_parts(result.events)]),
        Section("Time plots", [image for key, image in images.items()
                               if key != "schematic" and not key.startswith("wound_roll")]),
        *([Section("Wound rolls", rolls)] if (rolls := [
            image for key, image in images.items() if key.startswith("wound_roll")]) else []),
        Section("Closed-loop modes", modes_parts(result)),
        Section("Run", [make_table("run", "Settings", ["key", "value"], run_rows)]),
        Section("Resolved line file", [Text(dump_spec(spec), pre=True, fold="The line as it "
                                            "ran (scenario applied), every quantity in SI "
                                            "units: show the TOML")]),
    ]
    return render(
        title=f"webline report: {line.name}" + (f", scenario {scenario}" if scenario else ""),
        subtitle=(spec.scenarios[scenario].description if scenario else spec.description),
        status=status_text(result, display), status_class=STATUS_CLASS[result.verdict.status],
        headline=result.verdict.headline, sections=sections,
        footer=f"webline {__version__} · generated {datetime.now(UTC):%Y-%m-%d %H:%M} UTC · "
               f"units: {display.system} (the verdict's findings and the resolved line file: "
               "SI)")


def schematic_svg(line: BranchedLine) -> str:
    """The branched schematic as an inline SVG element (no XML header, no date, fixed ids)."""
    import matplotlib

    from webline.report.plots.branch_schematic import branch_schematic

    buffer = io.StringIO()
    with matplotlib.rc_context({"svg.hashsalt": "webline", "svg.fonttype": "none"}):
        branch_schematic(line).savefig(buffer, format="svg", metadata={"Date": None})
    text = buffer.getvalue()
    return text[text.index("<svg"):]


def branched_line_html(line: BranchedLine) -> str:
    """A branched line for a notebook: its schematic (SVG) and its tables (SI)."""
    return ("<div class='webline-line'>"
            f"<div style='max-width:100%;overflow-x:auto'>{schematic_svg(line)}</div>"
            + "".join(table_html(t) for t in line_tables(line)) + "</div>")


def branch_result_html(result: BranchResult) -> str:
    """A branched run for a notebook: the verdict's headline, the run's status and the
    verdict per web and lane."""
    from html import escape

    return (f"<div class='webline-result'><p><b>{escape(result.verdict.headline)}</b></p>"
            f"<p>{escape(status_text(result))}</p>{table_html(verdict_table(result))}</div>")
