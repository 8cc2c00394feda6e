"""``webline``: the command line, a thin layer over the public API.

Exit status: 0 ok or warning (warnings printed), 1 a run that failed (what was computed until
then is still written, and the failure described), 2 bad input (one line naming the file, key
and problem), 3 unstable (``analyze``; ``run`` also for a runaway), 130 interrupted (Ctrl-C),
143 stopped by SIGTERM (handled as Ctrl-C).
"""

from __future__ import annotations

import contextlib
import sys
import time
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape

from webline.cli_analyze import analyze
from webline.cli_benchmark import benchmark_command
from webline.cli_common import (
    FAMILY_TYPES,
    INTERRUPTED,
    TERMINATED,
    BadInput,
    ControllerOpt,
    DataFormat,
    LineArg,
    Precision,
    ScenarioOpt,
    SetOpt,
    Units,
    UnitsOpt,
    _console,
    _duration,
    _load,
    code_notes,
    fail,
    handles_errors,
    open_output,
    print_tables,
    progress_bar,
    runs_code,
    sigterm_as_interrupt,
)
from webline.cli_export import export_command
from webline.cli_hints import WeblineGroup
from webline.cli_roll import taper_command
from webline.cli_sweep import sweep_command
from webline.cli_tune import experiment_command, tune_command
from webline.cli_twin import fit_command, replay_command
from webline.cli_warm import warm_command
from webline.version import __version__

# The simulation, analysis and report layers are imported inside the commands that use them,
# so that `webline --version` and `webline --help` start in a fraction of a second.

app = typer.Typer(
    cls=WeblineGroup, name="webline", add_completion=False, no_args_is_help=True,
    rich_markup_mode=None,
    pretty_exceptions_enable=False,
    help="Simulate and analyse roll-to-roll (web handling) lines described in line files. "
    "Exit status: 0 ok or warning, 1 failed run, 2 bad input, 3 unstable (analyze; run: also "
    "a runaway), 130 interrupted (Ctrl-C), 143 stopped by SIGTERM (as Ctrl-C).",
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"webline {__version__}")
        raise typer.Exit()


@app.callback()
def root(version: Annotated[bool, typer.Option(
        "--version", callback=_version, is_eager=True, help="Show the version and exit.")]
         = False) -> None:
    """Simulate and analyse roll-to-roll (web handling) lines described in line files."""


# --- helpers ----------------------------------------------------------------------------------


# --- commands ---------------------------------------------------------------------------------


@app.command()
@handles_errors
@runs_code
def run(
    line: LineArg = "hswl",
    duration: Annotated[str | None, typer.Option(
        "--duration", "-d", help="Simulated time, e.g. 30 or '2 min' [s]; default: the "
        "scenario's duration, else 10 s.")] = None,
    scenario: ScenarioOpt = None,
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder; default out/LINE[-SCENARIO].")] = None,
    units: UnitsOpt = Units.si,
    data_format: Annotated[DataFormat, typer.Option(
        "--format", "-f", help="File format of the results (always SI).")] = DataFormat.netcdf,
    quiet: Annotated[bool, typer.Option("--quiet", "-q",
                                        help="Print only the report's path.")] = False,
    controller: ControllerOpt = None,
    sets: SetOpt = None,
    precision: Annotated[Precision, typer.Option(
        "--precision", help="Floating-point precision of the signals in results.nc.")]
    = Precision.float64,
    force: Annotated[bool, typer.Option(
        "--force", help="Write into a non-empty folder webline did not write, or over "
        "another command's output there (the files its manifest lists); never over a file "
        "webline did not write.")]
    = False,
    svg: Annotated[bool, typer.Option(
        "--svg", help="Also write every figure as SVG (vector) beside its PNG.")] = False,
) -> None:
    """Simulate a line and write its results, figures and an HTML report.

    Prints the verdict (ok, warning, unstable, failed) and its findings. Exit status: 0 ok or
    warning, 1 failed (what was computed is written), 2 bad input, 3 unstable or a runaway
    (diverged), 130 interrupted by Ctrl-C, 143 by SIGTERM (what was computed is written, status
    interrupted).
    """
    from webline.model.lines import load_line

    loaded = load_line(line)
    if loaded.branched:  # its own files (docs/branching.md)
        from webline.cli_branches import run_branched

        run_branched(loaded, _duration(duration), scenario, out, force, quiet,
                     svg=svg, units=units.value, sets=sets, data_format=data_format.value,
                     precision=precision.value,
                     family=None if controller is None else FAMILY_TYPES[controller.value])
        return
    reporter = None
    try:
        from webline.report.early import Reporter
        from webline.report.outputs import default_folder
        from webline.report.run_output import write_run
        from webline.report.text.verdict_text import verdict_lines
        from webline.sim.simulate import simulate

        scenario_line = _load(loaded, scenario, controller, sets)
        from webline.sim.user_objects import check_consent

        check_consent(scenario_line)  # (before anything is written: a refusal is one line)
        for warning in scenario_line.warnings:  # unusual values (webline.spec.ranges)
            typer.echo(f"warning: {scenario_line.source}: {warning}", err=True)
        seconds = _duration(duration)
        if seconds is None and scenario:
            seconds = scenario_line.spec.scenarios[scenario].duration
        from webline.report.results_file import results_name

        folder = open_output(out or default_folder(scenario_line.name, scenario), force, "run",
                             (results_name(data_format.value), "report.html", "summary.json"))
        # the report's process, forked once the line and the simulation's modules are loaded
        # (it shares them): it imports matplotlib while we simulate (report.early)
        reporter = Reporter.start()
        err = Console(stderr=True, highlight=False)
        started = time.perf_counter()
        if not quiet:
            err.print(f"Simulating {escape(scenario_line.name)} (Ctrl-C stops and writes what was "
                      "computed)")
        try:
            with progress_bar(not quiet, f"simulating {scenario_line.name}") as progress:
                result = simulate(scenario_line, seconds, progress=progress,
                                  raise_on_failure=False)
        except KeyboardInterrupt:
            fail("interrupted before anything was computed; nothing written", INTERRUPTED)
        if not quiet:
            simulated = float(result.time[-1]) if len(result.time) else 0.0
            err.print(f"Simulated {simulated:.4g} s of {escape(scenario_line.name)} in "
                      f"{time.perf_counter() - started:.2f} s; writing results and report")
        try:
            files, results_file = write_run(result, folder, data_format.value, precision.value,
                                            units.value, scenario, svg, reporter)
        except KeyboardInterrupt:
            fail(f"interrupted while writing {folder.path}: the files written are whole, the "
                 "others missing or from the previous run", INTERRUPTED)
        if not quiet:
            from webline.report.text.display import Display
            from webline.report.text.tables import summary_tables

            console = _console()
            print_tables(summary_tables(result, Display(units.value, result.line.spec.web.width)),
                         console)
            console.print(f"Results (SI): {escape(str(results_file))}\n"
                          f"Figures:      {escape(str(folder.path / 'figures'))} "
                          f"({len(files.figures)} files, {'PNG and SVG' if svg else 'PNG'})\n"
                          f"Summary:      {escape(str(files.summary))}\n"
                          "Report (open it in a browser):")
        typer.echo(str(files.report.resolve()))
        for text in verdict_lines(result.verdict, quiet):
            typer.echo(text, err=True)
        if result.failure is not None:
            typer.echo(f"what was computed until then is in {folder.path}", err=True)
        if result.verdict.exit_code:
            raise typer.Exit(result.verdict.exit_code)
    finally:  # the report's process ends with the command, whichever way it ends
        if reporter is not None:
            reporter.close()


@app.command()
@handles_errors
def validate(line: LineArg) -> None:
    """Check a line file (and each of its scenarios): list every problem (up to 20) with its
    TOML line and exit 2, or print 'ok' and any warnings (unusual values, winder settings that
    cannot act, speed loops soft against the web) and exit 0."""
    from webline.model.lines import load_line

    loaded = load_line(line)  # a LineFileError lists every problem, one a line (fail())
    if loaded.branched:  # docs/branching.md
        branched = loaded
        for name in branched.spec.scenarios:
            branched.with_scenario(name)
        from webline.analysis.dancer_modes import unstable_carriages

        with contextlib.suppress(ValueError, ArithmeticError):  # (as below: D2 of winder.md)
            for mode in unstable_carriages(branched):
                typer.echo(f"warning: {branched.source}: {mode.message()}", err=True)
        code_notes(branched)
        typer.echo(f"ok: {branched.source}: branched line {branched.name!r} with "
                   f"{len(branched.spec.webs)} webs, {len(branched.spec.rollers)} rollers, "
                   f"{len(branched.spans)} spans, {len(branched.drives)} drives, "
                   f"{len(branched.zones)} tension zones; scenarios: "
                   f"{', '.join(branched.spec.scenarios) or 'none'}")
        return
    for name in loaded.spec.scenarios:
        loaded.with_scenario(name)
    from webline.analysis.zone_loops import speed_leaks

    try:  # the tuning's warnings need the plan (an operating point): none without one
        leaks = [leak.message() for leak in speed_leaks(loaded)]
    except (ValueError, ArithmeticError):
        leaks = []
    from webline.analysis.dancer_modes import unstable_carriages

    # a carriage's closed-loop mode growing (docs/winder.md D2): it needs the linear model
    with contextlib.suppress(ValueError, ArithmeticError):  # (LinAlgError is a ValueError)
        leaks += [mode.message() for mode in unstable_carriages(loaded)]
    warnings = [*loaded.warnings, *leaks]
    for warning in warnings:
        typer.echo(f"warning: {loaded.source}: {warning}", err=True)
    for note in loaded.notes:  # what webline derived (a roll's inertia from its totals)
        typer.echo(f"note: {loaded.source}: {note}")
    code_notes(loaded)
    scenarios = ", ".join(loaded.spec.scenarios) or "none"
    typer.echo(f"ok: {loaded.source}: line {loaded.name!r} with {loaded.n_nodes} rollers, "
               f"{loaded.n_spans} spans, {len(loaded.drives)} drives, {len(loaded.zones)} "
               f"tension zones; scenarios: {scenarios}"
               + (f"; {len(warnings)} warnings" if warnings else ""))


@app.command()
@handles_errors
def lines() -> None:
    """List the built-in lines and their scenarios."""
    from webline.report.text.tables import make_table
    from webline.spec.load import builtin_lines, read_any

    rows = [[name, description, ", ".join(read_any(name)[0].get("scenarios", {}))]
            for name, description in builtin_lines().items()]
    print_tables([make_table("lines", "Built-in lines", ["name", "description", "scenarios"],
                             rows)], _console())


@app.command()
@handles_errors
def show(line: LineArg, units: UnitsOpt = Units.si, scenario: ScenarioOpt = None,
         sets: SetOpt = None,
         schematic: Annotated[Path | None, typer.Option(
             "--schematic", help="Also draw the line's schematic into this file (.png, .svg "
             "or .pdf).")] = None) -> None:
    """Show a line: sections, rollers, spans, drives, controllers and scenarios (a branched
    line: its webs, rollers, spans, drives and zones)."""
    from webline.cli_branches import show_branched, write_schematic
    from webline.model.lines import load_line
    from webline.report.text.describe import line_tables
    from webline.report.text.display import Display

    source = load_line(line)
    if source.branched:  # docs/branching.md, "Report"
        print_tables(show_branched(source, scenario, schematic, units.value, sets), _console())
        code_notes(source)
        if schematic is not None:
            typer.echo(f"Schematic: {schematic}")
        return
    loaded = _load(source, scenario, None, sets)
    display = Display(units.value, loaded.spec.web.width)
    print_tables(line_tables(loaded, display), _console())
    code_notes(loaded)
    if schematic is not None:
        write_schematic(loaded, schematic, display)
        typer.echo(f"Schematic: {schematic}")


app.command("analyze")(handles_errors(analyze))


@app.command()
@handles_errors
def study(
    name: Annotated[str | None, typer.Argument(
        metavar="NAME", help="The study to run (see 'webline study --list').")] = None,
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder; default out/study-NAME.")] = None,
    quick: Annotated[bool, typer.Option(
        "--quick", help="A shortened run (seconds), as the tests use.")] = False,
    list_: Annotated[bool, typer.Option("--list", help="List the studies and exit.")] = False,
    force: Annotated[bool, typer.Option(
        "--force", help="Write into a non-empty folder webline did not write, or over "
        "another command's output there (the files its manifest lists); never over a file "
        "webline did not write.")]
    = False,
) -> None:
    """Run a named study (thesis reproductions): figures, table.csv, summary.txt and an HTML
    report (report.html: findings, table, figures), listed in the folder's manifest like a
    run's files (a rerun removes what it no longer writes)."""
    from webline.studies import STUDIES
    from webline.studies.output import recording

    if list_:
        for key, func in STUDIES.items():
            doc = sys.modules[func.__module__].__doc__ or ""
            first = " ".join(doc.split("\n\n")[0].split())
            typer.echo(f"{key}: {first}")
        return
    if name is None:
        raise BadInput("give a study NAME or --list")
    if name not in STUDIES:
        raise BadInput(f"no study named {name!r}; known: {', '.join(sorted(STUDIES))}")
    folder = open_output(out or Path("out") / f"study-{name}", force, f"study {name}",
                         ("table.csv", "summary.txt"))
    with recording(folder):
        result = STUDIES[name](folder.path, quick=quick)
        from webline import __version__
        from webline.report.study_report import study_html
        from webline.studies.output import write_text

        doc = " ".join((sys.modules[STUDIES[name].__module__].__doc__ or "").split("\n\n")[0]
                       .split())
        write_text(folder.path / "report.html", study_html(
            name, doc, result.summary, result.table, result.figures, result.verdict,
            __version__))
    typer.echo(result.summary)
    if result.verdict is not None:
        typer.echo(f"verdict of its runs: {result.verdict.headline}")
    typer.echo(f"Report (open it in a browser): {(folder.path / 'report.html').resolve()}")
    typer.echo(str(folder.path.resolve()))


app.command("sweep")(handles_errors(
    sweep_command, resume="the same command with --resume goes on from the chunks stored"))
app.command("replay")(handles_errors(runs_code(replay_command)))
app.command("fit")(handles_errors(runs_code(fit_command)))
app.command("tune")(handles_errors(runs_code(tune_command)))
app.command("experiment")(handles_errors(runs_code(experiment_command)))
app.command("taper")(handles_errors(runs_code(taper_command)))
app.command("benchmark")(handles_errors(runs_code(benchmark_command)))
app.command("warm")(handles_errors(warm_command))
app.command("export")(handles_errors(export_command))


def main() -> None:
    """Console-script entry point. SIGTERM (a batch scheduler's stop) is handled as Ctrl-C
    (``cli_common.sigterm_as_interrupt``), exit status 143 instead of 130. Once a command has
    finished (every file written and
    closed), the process ends without Python's module teardown, which takes 0.6-1 s after
    numba, scipy and matplotlib are loaded; exit handlers and output buffers still run."""
    with sigterm_as_interrupt() as terminated:
        try:
            app(prog_name="webline")
            code: object = 0
        except SystemExit as done:
            code = done.code
    if terminated() and code == INTERRUPTED:  # stopped by SIGTERM rather than Ctrl-C
        code = TERMINATED
    end_process(code)


def end_process(code: object) -> None:
    """Exit with ``code`` as ``SystemExit`` would (None: 0; an int as is; anything else is
    printed to stderr and gives 1), after the exit handlers, skipping module teardown."""
    import atexit
    import os

    if code is None:
        code = 0
    elif not isinstance(code, int):
        print(code, file=sys.stderr)
        code = 1
    atexit._run_exitfuncs()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (BrokenPipeError, ValueError):  # a closed pipe (webline ... | head): nothing to add
        pass
    os._exit(code)
