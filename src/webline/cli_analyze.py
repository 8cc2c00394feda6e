"""``webline analyze``: operating point, equilibrium inputs, closed-loop modes, the verdict
and, on request, the decentralized certificate."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Annotated

import typer

from webline.cli_common import (
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
    from webline.analysis.certificate import Certificate
    from webline.line import Line


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
) -> None:
    """Operating point, equilibrium inputs and closed-loop modes of a line, and its verdict.

    Exit status: 0 ok (no closed-loop mode grows), 2 bad input, 3 unstable (one grows).
    """
    from webline.analysis.modes import closed_loop_modes
    from webline.analysis.zone_loops import speed_leaks, zone_loops
    from webline.model.operating_point import analysis_time, operating_point
    from webline.report.display import Display
    from webline.report.tables import modes_table, operating_point_tables, operating_point_values
    from webline.report.verdict_text import verdict_lines
    from webline.report.zone_tables import leak_lines, zone_loops_table
    from webline.sim.stability import stability_findings
    from webline.verdict import Verdict

    loaded = _load(line, scenario, controller, sets)
    t = analysis_time(loaded) if at is None else time_option(at, "--time", zero=True)
    display = Display(units.value, loaded.spec.web.width)
    point = operating_point(loaded, t)
    modes = closed_loop_modes(loaded, t)
    loops, leaks = zone_loops(loaded, t), speed_leaks(loaded)
    cert = _certificate(loaded) if certificate else None
    verdict = Verdict.of(stability_findings(loaded, t))
    if as_json:
        payload: dict[str, object] = {
            "line": loaded.name, "scenario": scenario, "units": units.value,
            "operating_point": operating_point_values(point, display),
            "closed_loop_modes": [m.as_dict() for m in modes],
            "zone_loops": [loop.as_dict() for loop in loops],
            "speed_loop_leaks": [leak.message() for leak in leaks], "verdict": verdict.as_dict()}
        if cert is not None:
            payload["certificate"] = {"holds": cert.holds, "worst_ratio": cert.worst_ratio,
                                      "max_real": cert.max_real,
                                      "max_real_plant": cert.max_real_plant,
                                      "sampled_radius": cert.sampled_radius,
                                      "sections": cert.rows()}
        typer.echo(json.dumps(payload, indent=2, default=float))
    else:
        tables = [*operating_point_tables(loaded, point, display), modes_table(modes)]
        if loops:
            tables.append(zone_loops_table(loops))
        print_tables(tables, _console())
        for warning in leak_lines(leaks):
            typer.echo(warning, err=True)
        typer.echo("\n".join(verdict_lines(verdict)))
        if cert is not None:
            _print_certificate(cert)
    if verdict.exit_code:
        raise typer.Exit(verdict.exit_code)


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


def _print_certificate(cert: Certificate) -> None:
    """Certificate rows as a table and a one-line verdict, with the true stability margin."""
    from webline.report.tables import make_table

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
