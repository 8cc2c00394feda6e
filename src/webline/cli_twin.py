"""``webline replay`` and ``webline fit``: measured traces against a line (issue 24).

Registered on the app by ``webline.cli``; it imports nothing from there (no cycle). The twin
layer (scipy, pandas, the simulation) loads inside the commands.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich.markup import escape

from webline.cli_common import LineArg, ScenarioOpt, _console, open_output
from webline.errors import ArgumentError

if TYPE_CHECKING:
    from webline.twin.traces.measurements import Measurements

DataArg = Annotated[str, typer.Argument(
    help="Measurement file: CSV, Parquet or NetCDF with a time column and webline's signal "
    "names (a run's own results.csv/results.nc work as they are); units in the headers.")]
MapOpt = Annotated[list[str] | None, typer.Option(
    "--map", metavar="COLUMN=SIGNAL", help="Read a foreign column as a webline signal, e.g. "
    "--map LC2=tension[process_span] (repeatable; SIGNAL empty: skip the column).")]
ForceOpt = Annotated[bool, typer.Option(
    "--force", help="Write into a non-empty folder webline did not write, or over another "
    "command's output there.")]

REPLAY_FILES = ("report.html", "metrics.csv", "replay.png")
FIT_FILES = ("fitted.toml", "fit.json", "report.html")


def parse_pairs(items: list[str] | None, option: str, sep: str = "=") -> dict[str, str]:
    """``["A=B", ...]`` as a dict; ``ArgumentError`` naming ``option`` for an item without
    ``sep``."""
    out = {}
    for item in items or []:
        key, found, value = item.partition(sep)
        if not found or not key.strip():
            raise ArgumentError(f"{option}: expected NAME{sep}VALUE, got {item!r}")
        out[key.strip()] = value.strip()
    return out


def _data(data: str, line: str, scenario: str | None,
          maps: list[str] | None) -> Measurements:
    from webline.model.lines import load_line
    from webline.twin.traces.measurements import load_measurements

    base = load_line(line)
    if scenario:
        base = base.with_scenario(scenario)
    return load_measurements(data, base, parse_pairs(maps, "--map"))


def replay_command(
    line: LineArg,
    data: DataArg,
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder; default out/LINE-replay.")] = None,
    scenario: ScenarioOpt = None,
    maps: MapOpt = None,
    force: ForceOpt = False,
) -> None:
    """Simulate a line driven by the references logged in measured data and compare it with
    every measured signal: metrics (RMS, max |error|, NRMSE, bias, R²), overlay figure and an
    HTML report. Exit status: 0, 2 bad input (the file, column and problem)."""
    from webline.report.outputs import default_folder
    from webline.twin.fitting.report import write_replay_report
    from webline.twin.traces.replay import replay

    measurements = _data(data, line, scenario, maps)
    result = replay(measurements.line, measurements)
    target = out or Path(default_folder(result.line.name, "replay"))
    folder = open_output(target, force, "replay", REPLAY_FILES)
    for name in REPLAY_FILES:
        folder.claim(name)
    report = write_replay_report(result, target)
    folder.finish()
    console = _console()
    console.print(escape(measurements.report()))
    console.print(escape("driven by: " + "; ".join(result.notes)))
    console.print(escape(result.metrics.to_string(
        index=False, float_format=lambda v: f"{v:.4g}")))
    console.print(escape(f"report: {report}"))


DataListArg = Annotated[list[str], typer.Argument(
    metavar="DATA...", help="One or more measurement files (CSV, Parquet or NetCDF, as for "
    "replay), fitted jointly: shared parameters to every record, each record driven by its "
    "own logged references.")]


def fit_command(
    line: LineArg,
    data: DataListArg,
    free: Annotated[list[str], typer.Option(
        "--free", metavar="PATH=LOW..HIGH", help="A parameter to fit and its bounds, e.g. "
        "--free 'rollers.unwind.inertia=0.5..5 kg*m**2' (repeatable; * for every element: "
        "rollers.*.friction).")],
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder; default out/LINE-fit.")] = None,
    scenarios: Annotated[list[str] | None, typer.Option(
        "--scenario", "-s", help="A named scenario of the line file (see 'webline show'): "
        "given once, every record's; given once per record, the records' in their order "
        "(repeatable).")] = None,
    per_record: Annotated[list[str] | None, typer.Option(
        "--per-record", metavar="PATH", help="A --free PATH fitted once per record, not "
        "shared (an initial roll radius, a sensor offset that differs between the records); "
        "reported as PATH@FILE (repeatable).")] = None,
    maps: MapOpt = None,
    max_simulations: Annotated[int, typer.Option(
        "--max-simulations", min=10, help="Stop after about this many simulations (of the "
        "local stages; the global stage's come on top).")] = 400,
    starts: Annotated[int, typer.Option(
        "--starts", min=1, help="Starts of the global stage: the line's values and the best "
        "of a Latin hypercube over the bounds, each fitted briefly; the best goes on (1: the "
        "line's values only).")] = 8,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Seed of the Latin hypercube.")] = 0,
    accept_poor: Annotated[bool, typer.Option(
        "--accept-poor", help="Exit 0 for a poor fit (its files still say it is poor).")] = False,
    interval_method: Annotated[str, typer.Option(
        "--intervals", help="wald: value ± t x the honest standard error; profile: "
        "profile-likelihood intervals, for confidence regions that are not ellipsoids "
        "(each parameter's profile refits the others: some tens of simulations each).")
    ] = "wald",
    force: ForceOpt = False,
) -> None:
    """Fit line parameters to one or more measured records by weighted least squares:
    values, standard errors, 95 % intervals, correlations, the parameters the data cannot
    identify and a verdict (good, poor, failed, with the reasons; a record whose own
    residuals are above the noise makes it poor). Several records are fitted jointly: e.g.
    an accel-ramps and a tension-step test, -s given once per file. Writes fitted.toml (the
    line with the fitted shared values, annotated), fit.json and an HTML report, whatever
    the verdict. Exit status: 0 good, 4 poor (0 with --accept-poor), 5 failed, 2 bad
    input."""
    from webline.report.outputs import default_folder
    from webline.twin.fitting.fit import fit
    from webline.twin.fitting.fit_files import write_fit_files
    from webline.twin.fitting.records import scenario_list
    from webline.twin.fitting.report import fit_figure_names, write_fit_report

    if interval_method not in ("wald", "profile"):
        raise ArgumentError(f"--intervals: 'wald' or 'profile', got {interval_method!r}")
    bounds = parse_pairs(free, "--free")
    chosen = scenario_list(scenarios or None, len(data), "--scenario")
    measurements = [_data(path, line, scenario, maps)
                    for path, scenario in zip(data, chosen, strict=True)]
    from webline.model.lines import load_line

    result = fit(load_line(line), measurements, bounds, scenario=chosen,
                 per_record=per_record or (), max_simulations=max_simulations,
                 starts=starts, seed=seed, profile=interval_method == "profile")
    target = out or Path(default_folder(result.line.name, "fit"))
    files = (*FIT_FILES, *fit_figure_names(len(result.records)))
    folder = open_output(target, force, "fit", files)
    for name in files:
        folder.claim(name)
    write_fit_files(result, target)
    report = write_fit_report(result, target)
    folder.finish()
    console = _console()
    for m in measurements:
        console.print(escape(m.report()))
    console.print(escape(repr(result)))
    console.print(escape(f"report: {report}"))
    from webline.twin.fitting.verdict import EXIT

    status = result.verdict.status
    if status != "good":
        typer.echo(f"warning: {status.upper()} FIT, its values are not to be trusted: "
                   + "; ".join(result.verdict.reasons), err=True)
    if status == "failed" or (status == "poor" and not accept_poor):
        raise typer.Exit(EXIT[status])
