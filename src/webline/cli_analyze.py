"""``webline analyze``: operating point, equilibrium inputs, closed-loop modes, the verdict
and, on request, the decentralized certificate."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Annotated

import typer

from webline.cli_common import (
    FAMILY_TYPES,
    BadInput,
    ControllerOpt,
    LineArg,
    ScenarioOpt,
    SetOpt,
    Units,
    UnitsOpt,
    _console,
    _load,
    print_tables,
    time_option,
)

if TYPE_CHECKING:
    from webline.analysis.branch_across_roll import BranchRollModes
    from webline.analysis.certificate import Certificate
    from webline.line import Line
    from webline.model.web_graph import BranchedLine
    from webline.report.text.display import Display
    from webline.sim.linear.roll_modes import RollModes


def analyze(
    line: LineArg, units: UnitsOpt = Units.si, scenario: ScenarioOpt = None,
    at: Annotated[str | None, typer.Option(
        "--time", "-t", help="Analyse the references at this time, e.g. 2 or '2 s' [s]; "
        "default 0, or the end of the speed ramp for a start from rest.")] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")]
    = False,
    certificate: Annotated[bool, typer.Option(
        "--certificate", help="Also the decentralized stability certificate of thesis Thm "
        "6.2.1: distance to instability, interconnection bound and margin per section.")]
    = False,
    controller: ControllerOpt = None,
    sets: SetOpt = None,
    across_roll: Annotated[bool, typer.Option(
        "--across-roll", help="Also the closed-loop modes from the rolls as loaded until the "
        "unwind is empty (with --scenario: along the scenario's course), and a warning where "
        "a loop mode's damping falls below --damping.")] = False,
    points: Annotated[int, typer.Option(
        "--points", min=2, max=200, help="Points along the roll for --across-roll.")] = 20,
    damping: Annotated[float, typer.Option(
        "--damping", min=0.0, help="Damping threshold for --across-roll.")] = 0.1,
    figure: Annotated[str | None, typer.Option(
        "--figure", help="With --across-roll: write the map of the modes to this PNG file.")]
    = None,
) -> None:
    """Operating point, equilibrium inputs and closed-loop modes of a line, and its verdict.

    Exit status: 0 ok (no closed-loop mode grows), 2 bad input, 3 unstable (one grows).
    """
    from webline.model.lines import load_line

    source = load_line(line)
    if source.branched:  # docs/branching.md, "Linear models"
        if figure is not None and not across_roll:
            raise BadInput("--figure: the map of the modes across the roll; give --across-roll")
        _analyze_branched(source, scenario, at, as_json, units,
                          (points, damping, figure) if across_roll else None, certificate,
                          sets=sets, family=None if controller is None
                          else FAMILY_TYPES[controller.value])
        return
    from webline.analysis.modes import closed_loop_modes
    from webline.analysis.zone_loops import speed_leaks, zone_loops
    from webline.model.operating_point import analysis_time, operating_point
    from webline.report.text.display import Display
    from webline.report.text.tables import (
        modes_table,
        operating_point_tables,
        operating_point_values,
    )
    from webline.report.text.verdict_text import verdict_lines
    from webline.report.text.zone_tables import (
        leak_lines,
        roll_modes_table,
        roll_modes_values,
        zone_loops_table,
    )
    from webline.sim.linear.stability import stability_findings
    from webline.verdict import Verdict

    loaded = _load(source, scenario, controller, sets)
    t = analysis_time(loaded) if at is None else time_option(at, "--time", zero=True)
    display = Display(units.value, loaded.spec.web.width)
    point = operating_point(loaded, t)
    modes = closed_loop_modes(loaded, t)
    loops, leaks = zone_loops(loaded, t), speed_leaks(loaded)
    cert = _certificate(loaded) if certificate else None
    course = _across_roll(loaded, scenario, points, damping, figure, display) if across_roll \
        else None
    verdict = Verdict.of(stability_findings(loaded, t)
                         + (course.findings() if course is not None else []))
    if as_json:
        payload: dict[str, object] = {
            "line": loaded.name, "scenario": scenario, "units": units.value,
            "operating_point": operating_point_values(point, display),
            "closed_loop_modes": [m.as_dict() for m in modes],
            "zone_loops": [loop.as_dict() for loop in loops],
            "speed_loop_leaks": [leak.message() for leak in leaks], "verdict": verdict.as_dict()}
        if course is not None:
            payload["modes_across_roll"] = roll_modes_values(course)
        if cert is not None:
            payload["certificate"] = _certificate_values(cert)
        typer.echo(json.dumps(payload, indent=2, default=float))
    else:
        tables = [*operating_point_tables(loaded, point, display), modes_table(modes)]
        if loops:
            tables.append(zone_loops_table(loops))
        if course is not None:
            tables.append(roll_modes_table(course, display))
        print_tables(tables, _console())
        for warning in leak_lines(leaks):
            typer.echo(warning, err=True)
        typer.echo("\n".join(verdict_lines(verdict)))
        if cert is not None:
            _print_certificate(cert)
    if verdict.exit_code:
        raise typer.Exit(verdict.exit_code)


def _analyze_branched(source: str | BranchedLine, scenario: str | None, at: str | None,
                      as_json: bool, units: Units, across: tuple[int, float, str | None] | None,
                      certificate: bool = False, *, sets: list[str] | None = None,
                      family: str | None = None) -> None:
    """``analyze`` of a branched line: operating point, closed-loop modes and the stability
    verdict (``sim.branches.linear``) in ``units``; ``across``: (points, damping threshold,
    figure) of ``--across-roll``; ``certificate``: thesis Thm 6.2.1 over the tree's sections
    (``analysis.branch_certificate``); ``sets``: the ``--set PATH=VALUE`` options, applied
    after the scenario; ``family``: every drive on this controller family (``--controller``,
    its line-file type), applied first, as ``run`` does."""
    from webline.analysis.modes import modes_of
    from webline.cli_branches import branched_line
    from webline.report.text.branch_analysis import point_tables, point_values
    from webline.report.text.display import Display
    from webline.report.text.tables import modes_table
    from webline.report.text.verdict_text import verdict_lines
    from webline.sim.branches.equilibrium import operating_point
    from webline.sim.branches.linear import (
        analysis_time,
        branch_linear_model,
        stability_findings,
    )
    from webline.sim.branches.plan import compile_branches
    from webline.verdict import Verdict

    line = branched_line(source, scenario, sets, family)
    from webline.spec.branched.controllers import python_drives

    if python_drives(line.spec):  # (as a single-path line's analyses refuse them)
        raise BadInput(f"{line.source}: {', '.join(python_drives(line.spec))} run a user's "
                       "python controller, which has no linear model in webline: no "
                       "closed-loop analysis")
    t = analysis_time(line) if at is None else time_option(at, "--time", zero=True)
    plan = compile_branches(line)
    point = operating_point(plan, t)
    model = branch_linear_model(plan, point, "closed")
    modes = modes_of(model.a, model.states)
    display = Display(units.value, 1.0)  # (per width: each web's own, branch_analysis)
    course = None if across is None else _branched_across_roll(line, plan, scenario, *across,
                                                                display)
    cert = _branched_certificate(line) if certificate else None
    verdict = Verdict.of(stability_findings(plan, point, t)
                         + (course.findings() if course is not None else []))
    spans, nodes = _branch_point_rows(plan, point)
    if as_json:
        from webline.report.text.branch_analysis import rolls_modes_values

        payload: dict[str, object] = {
            "line": line.name, "scenario": scenario, "units": units.value,
            "analysis_time_s": t, "operating_point": point_values(spans, nodes, display),
            "closed_loop_modes": [m.as_dict() for m in modes], "verdict": verdict.as_dict()}
        if course is not None:
            payload["modes_across_roll"] = rolls_modes_values(course, display)
        if cert is not None:
            payload["certificate"] = _certificate_values(cert)
        typer.echo(json.dumps(payload, indent=2, default=float))
    else:
        tables = [*point_tables(spans, nodes, t, display), modes_table(modes)]
        if course is not None:
            from webline.report.text.branch_analysis import rolls_modes_table

            tables.append(rolls_modes_table(course, display))
        print_tables(tables, _console())
        typer.echo("\n".join(verdict_lines(verdict)))
        if cert is not None:
            _print_certificate(cert)
    if verdict.exit_code:
        raise typer.Exit(verdict.exit_code)


def _branch_point_rows(plan: object, point: object) -> tuple[list[dict], list[dict]]:
    """Rows of a branched operating point: per span its tension [N], per roller its surface
    speed [m/s] (on a roll: its drive's lane), ω [rad/s] and motor torque [N·m] (None: idle)."""
    from webline.sim.branches.equilibrium import BranchPoint
    from webline.sim.branches.linear import speed_arm
    from webline.sim.branches.loop import layout as B
    from webline.sim.branches.plan import BranchPlan

    assert isinstance(plan, BranchPlan) and isinstance(point, BranchPoint)
    line, x = plan.line, point.x
    spans = [{"span": s.name, "web": line.spec.webs[s.web].name,
              "width_m": line.materials[s.web].width,
              "tension_N": float(max(x[s.index], 0.0))} for s in line.spans]
    nodes = []
    for i, roller in enumerate(line.spec.rollers):
        omega = float(x[plan.offsets[B.O_OMEGA] + i])
        d = int(plan.nodes[i, B.N_DRIVE])
        nodes.append({"roller": roller.name, "speed_m_s": speed_arm(plan, point, i) * omega,
                      "omega_rad_s": omega,
                      "torque_Nm": float(point.torque[d]) if d >= 0 else None})
    return spans, nodes


def _branched_across_roll(line: object, plan: object, scenario: str | None, points: int,
                          damping: float, figure: str | None, display: Display
                          ) -> BranchRollModes:
    """The modes across the rolls of a branched line (``analysis.branch_across_roll``): along
    the scenario's course where one is given (``line`` has it applied), else from the rolls
    as loaded until the first unwind is empty; the map written to ``figure`` if given."""
    from webline.analysis.branch_across_roll import branch_roll_course, branch_roll_modes
    from webline.model.web_graph import BranchedLine
    from webline.sim.branches.plan import BranchPlan

    assert isinstance(line, BranchedLine) and isinstance(plan, BranchPlan)
    duration = float(line.spec.scenarios[scenario].duration) if scenario else None
    if duration is None and not any(r.direction < 0 for r in line.rolls):
        raise BadInput("--across-roll: this line has no unwind to run empty; give --scenario "
                       "to follow its course")
    time, length, radius = branch_roll_course(line, points, duration)
    course = branch_roll_modes(plan, time, radius, length, damping)
    if figure is not None:
        from webline.report.plots.roll_figures import roll_modes_figure
        from webline.report.text.branch_analysis import base_display

        fig = roll_modes_figure(course, base_display(display))
        rewind = next((n for n, r in zip(course.rolls, plan.line.rolls, strict=True)
                       if r.direction > 0), "rewind")
        fig.axes[1].set_xlabel(base_display(display).label(f"{rewind} diameter", "length"))
        _save_png(fig, figure)
    return course


def _save_png(fig: object, figure: str) -> None:
    """Write matplotlib figure ``fig`` to ``figure`` as PNG (atomically)."""
    import io
    from pathlib import Path

    from webline.files import atomic_write_bytes

    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)  # type: ignore[attr-defined]
    atomic_write_bytes(Path(figure), buffer.getvalue())
    typer.echo(f"wrote {figure}", err=True)


def _across_roll(line: Line, scenario: str | None, points: int, damping: float,
                 figure: str | None, display: Display) -> RollModes:
    """The modes across the roll (``analysis.across_roll``): along the scenario's course
    where one is given, else from the rolls as loaded to an empty unwind; the map's figure
    written to ``figure`` if given."""
    from webline.analysis.across_roll import modes_across_roll

    duration = line.spec.scenarios[scenario].duration if scenario else None
    course = modes_across_roll(line, points, duration=duration, threshold=damping)
    if figure is not None:
        from webline.report.plots.roll_figures import roll_modes_figure

        _save_png(roll_modes_figure(course, display), figure)
    return course


def _certificate(line: Line) -> Certificate:
    """The decentralized certificate of ``line`` with webline's default design; a line that
    cannot run state feedback on every drive (what the theorem is about) is bad input."""
    from webline.analysis.certificate import certificate
    from webline.errors import LineFileError

    try:
        return certificate(line)
    except LineFileError as exc:
        raise BadInput(f"--certificate: thesis Thm 6.2.1 is about decentralized state feedback "
                       f"on every drive, which this line cannot run: {exc}") from None


def _branched_certificate(line: object) -> Certificate:
    """Thesis Thm 6.2.1 over a branched line's sections; a tree whose sections do not hold
    all it reads (an idle junction between zones) is refused in one line, with the reason."""
    from webline.analysis.branch_certificate import NotCertifiable, branch_certificate

    try:
        return branch_certificate(line)  # type: ignore[arg-type]
    except NotCertifiable as exc:
        raise BadInput(f"--certificate: {exc}") from None


def _certificate_values(cert: Certificate) -> dict[str, object]:
    """The certificate as plain data (JSON)."""
    return {"holds": cert.holds, "worst_ratio": cert.worst_ratio, "max_real": cert.max_real,
            "max_real_plant": cert.max_real_plant, "sampled_radius": cert.sampled_radius,
            "sections": cert.rows()}


def _print_certificate(cert: Certificate) -> None:
    """Certificate rows as a table and a one-line verdict, with the true stability margin."""
    from webline.report.text.tables import make_table

    rows = cert.rows()
    columns = list(rows[0])
    table = make_table("certificate", "Decentralized certificate (thesis 6.44, 6.54)",
                       columns, [[_fmt(row[c]) for c in columns] for row in rows])
    print_tables([table], _console())
    verdict = "holds" if cert.holds else "does not hold"
    typer.echo(f"certificate {verdict}: worst ratio δs/(√N ξ) = {cert.worst_ratio:.3g}; "
               f"interconnected sections max Re λ = {cert.max_real:.3g} 1/s; full plant "
               f"{_fmt(cert.max_real_plant)} 1/s; sampled spectral radius "
               f"{_fmt(cert.sampled_radius)}")


def _fmt(value: object) -> str:
    return f"{value:.4g}" if isinstance(value, float) else str(value)
