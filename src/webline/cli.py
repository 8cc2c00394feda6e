"""``webline``: the command line, a thin layer over the public API.

Exit status: 0 ok or warning (warnings printed), 1 a run that failed (what was computed until
then is still written, and the failure described), 2 bad input (one line naming the file, key
and problem), 3 unstable (``analyze``; ``run`` also for a runaway), 130 interrupted.
"""

from __future__ import annotations

import functools
import json
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, TypeVar

import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeElapsedColumn
from rich.table import Table as RichTable

from webline.errors import WeblineError
from webline.version import __version__

if TYPE_CHECKING:
    from webline.analysis.certificate import Certificate
    from webline.line import Line

# The simulation, analysis and report layers are imported inside the commands that use them,
# so that `webline --version` and `webline --help` start in a fraction of a second.

app = typer.Typer(
    name="webline", add_completion=False, no_args_is_help=True, rich_markup_mode=None,
    pretty_exceptions_enable=False,
    help="Simulate and analyse roll-to-roll (web handling) lines described in line files. "
    "Exit status: 0 ok or warning, 1 failed run, 2 bad input, 3 unstable (analyze; run: also "
    "a runaway), 130 interrupted.",
)


class Units(StrEnum):
    si = "si"
    imperial = "imperial"


class ControllerFamily(StrEnum):
    pi = "pi"
    state_feedback = "state-feedback"
    adaptive = "adaptive"
    mrac = "mrac"


#: the line-file ``type`` of each --controller choice
FAMILY_TYPES = {"pi": "cascaded_pi", "state-feedback": "state_feedback", "adaptive": "adaptive",
                "mrac": "mrac"}
ControllerOpt = Annotated[ControllerFamily | None, typer.Option(
    "--controller", "-c", help="Run every drive with this controller family (its default "
    "design) instead of the line file's.")]


class DataFormat(StrEnum):
    netcdf = "netcdf"
    csv = "csv"


class Precision(StrEnum):
    float64 = "float64"
    float32 = "float32"


class BadInput(WeblineError):
    """A command-line value is wrong (exit status 2)."""

    exit_code = 2


LineArg = Annotated[str, typer.Argument(
    metavar="LINE",
    help="A line file (.toml) or the name of a built-in line (see 'webline lines').")]
UnitsOpt = Annotated[Units, typer.Option("--units", "-u", help="Units to show quantities in.")]
ScenarioOpt = Annotated[str | None, typer.Option(
    "--scenario", "-s", help="A named scenario of the line file (see 'webline show').")]
SetOpt = Annotated[list[str] | None, typer.Option(
    "--set", metavar="PATH=VALUE", help="Change one value of the line, by its nested path, "
    "with units (repeatable): --set web.ea='9 kN' --set "
    "rollers.process.controller.tension_bandwidth='2 Hz'. Applied after --scenario.")]

F = TypeVar("F", bound=Callable[..., None])


def handles_errors(command: F) -> F:
    """Turn webline's errors into one line on stderr and their exit status, no traceback."""

    @functools.wraps(command)
    def wrapper(*args: object, **kwargs: object) -> None:
        try:
            command(*args, **kwargs)
        except WeblineError as exc:
            fail(str(exc), exc.exit_code)

    return wrapper  # type: ignore[return-value]


def fail(message: str, code: int) -> None:
    """Print ``error: message`` on stderr, one line per line of ``message`` (a line file's
    problems), and exit with ``code``."""
    for text in message.splitlines() or [""]:
        typer.echo("error: " + " ".join(text.split()), err=True)
    raise typer.Exit(code)


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


def _console() -> Console:
    """Standard output for tables: the terminal's width, or 160 columns when piped."""
    console = Console(highlight=False)
    if not console.is_terminal:
        console.width = 160
    return console


def print_tables(tables: list, console: Console) -> None:
    """Print report tables (``webline.report.tables.Table``) with rich, skipping empty ones."""
    for table in tables:
        if not table.rows:
            continue
        out = RichTable(title=escape(table.title), title_justify="left", title_style="bold")
        for column in table.columns:
            out.add_column(escape(column), overflow="fold")
        for row in table.rows:
            out.add_row(*(escape(cell) for cell in row))
        console.print(out)


def _load(source: str, scenario: str | None, controller: ControllerFamily | None = None,
          sets: list[str] | None = None) -> Line:
    """The line as a command runs it: loaded, with ``--controller``, ``--scenario`` and every
    ``--set PATH=VALUE`` applied, in that order."""
    from webline.line import load_line
    from webline.spec.paths import parse_assignment

    line = load_line(source)
    if controller is not None:
        from webline.control.select import with_controller

        line = with_controller(line, FAMILY_TYPES[controller.value])  # type: ignore[arg-type]
    if scenario:
        line = line.with_scenario(scenario)
    changes = {}
    for text in sets or []:
        try:
            path, value = parse_assignment(text)
        except ValueError as exc:
            raise BadInput(f"--set: {exc}") from None
        changes[path] = value
    return line.replace(changes) if changes else line


def _duration(text: str | None) -> float | None:
    if text is None:
        return None
    try:
        value = float(text)  # a plain number is seconds
    except ValueError:
        value = None
    try:
        from webline.units import to_si

        value = to_si(text, "time") if value is None else value
    except ValueError as exc:
        raise BadInput(f"--duration: {exc}") from None
    if not value > 0:
        raise BadInput(f"--duration: must be > 0 s, got {text!r}")
    return value


def prepare_out(out: Path) -> Path:
    """Create the output folder ``out`` and check that files can be written in it."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".webline-write-test"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise BadInput(f"{out}: cannot write to the output folder ({reason})") from None
    return out


@contextmanager
def progress_bar(enabled: bool, label: str) -> Iterator[Callable[[float], None] | None]:
    """A progress bar on stderr (cleared when done) fed with the fraction done, or None. Until
    the first fraction arrives it says that the line's compiled loop is being loaded, or
    compiled the first time a line of this structure runs (numba; seconds, then cached)."""
    if not enabled:
        yield None
        return
    waiting = "loading the line's compiled loop (compiled once per line structure)"
    columns = (TextColumn("{task.description}"), BarColumn(), TaskProgressColumn(),
               TimeElapsedColumn())
    with Progress(*columns, console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(escape(waiting), total=1.0)
        yield lambda fraction: bar.update(task, completed=fraction, description=escape(label))


# --- commands ---------------------------------------------------------------------------------


@app.command()
@handles_errors
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
        "--force", help="Write into a non-empty output folder that webline did not write.")]
    = False,
    svg: Annotated[bool, typer.Option(
        "--svg", help="Also write every figure as SVG (vector) beside its PNG.")] = False,
) -> None:
    """Simulate a line and write its results, figures and an HTML report.

    Prints the verdict (ok, warning, unstable, failed) and its findings. Exit status: 0 ok or
    warning, 1 failed (what was computed is written), 2 bad input, 3 unstable or a runaway
    (diverged), 130 interrupted by Ctrl-C (what was computed is written, status interrupted).
    """
    from webline.report.run_output import open_run_folder, write_run
    from webline.report.verdict_text import verdict_lines
    from webline.sim.simulate import simulate

    scenario_line = _load(line, scenario, controller, sets)
    for warning in scenario_line.warnings:  # unusual values (webline.spec.ranges)
        typer.echo(f"warning: {scenario_line.source}: {warning}", err=True)
    seconds = _duration(duration)
    if seconds is None and scenario:
        seconds = scenario_line.spec.scenarios[scenario].duration
    folder = open_run_folder(out, scenario_line.name, scenario, force)
    prepare_out(folder.path)
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
        fail("interrupted before anything was computed; nothing written", 130)
    if not quiet:
        simulated = float(result.time[-1]) if len(result.time) else 0.0
        err.print(f"Simulated {simulated:.4g} s of {escape(scenario_line.name)} in "
                  f"{time.perf_counter() - started:.2f} s; writing results and report")
    try:
        files, results_file = write_run(result, folder, data_format.value, precision.value,
                                        units.value, scenario, svg)
    except KeyboardInterrupt:
        fail(f"interrupted while writing {folder.path}: the files written are whole, the others "
             "missing or from the previous run", 130)
    if not quiet:
        from webline.report.display import Display
        from webline.report.tables import summary_tables

        console = _console()
        print_tables(summary_tables(result, Display(units.value)), console)
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


@app.command()
@handles_errors
def validate(line: LineArg) -> None:
    """Check a line file (and each of its scenarios): list every problem (up to 20) with its
    TOML line and exit 2, or print 'ok' and any warnings (unusual values) and exit 0."""
    from webline.line import load_line

    loaded = load_line(line)  # a LineFileError lists every problem, one a line (fail())
    for name in loaded.spec.scenarios:
        loaded.with_scenario(name)
    for warning in loaded.warnings:
        typer.echo(f"warning: {loaded.source}: {warning}", err=True)
    scenarios = ", ".join(loaded.spec.scenarios) or "none"
    typer.echo(f"ok: {loaded.source}: line {loaded.name!r} with {loaded.n_nodes} rollers, "
               f"{loaded.n_spans} spans, {len(loaded.drives)} drives, {len(loaded.zones)} "
               f"tension zones; scenarios: {scenarios}"
               + (f"; {len(loaded.warnings)} warnings" if loaded.warnings else ""))


@app.command()
@handles_errors
def lines() -> None:
    """List the built-in lines and their scenarios."""
    from webline.line import load_line
    from webline.report.tables import make_table
    from webline.spec.load import builtin_lines

    rows = [[name, description, ", ".join(load_line(name).spec.scenarios)]
            for name, description in builtin_lines().items()]
    print_tables([make_table("lines", "Built-in lines", ["name", "description", "scenarios"],
                             rows)], _console())


@app.command()
@handles_errors
def show(line: LineArg, units: UnitsOpt = Units.si, scenario: ScenarioOpt = None,
         sets: SetOpt = None) -> None:
    """Show a line: sections, rollers, spans, drives, controllers and scenarios."""
    from webline.report.describe import line_tables
    from webline.report.display import Display

    print_tables(line_tables(_load(line, scenario, None, sets), Display(units.value)),
                 _console())


@app.command()
@handles_errors
def analyze(
    line: LineArg, units: UnitsOpt = Units.si, scenario: ScenarioOpt = None,
    at: Annotated[float | None, typer.Option(
        "--time", "-t", help="Analyse the references at this time [s]; default 0, or the end "
        "of the speed ramp for a start from rest.")] = None,
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
    from webline.model.operating_point import analysis_time, operating_point
    from webline.report.display import Display
    from webline.report.tables import modes_table, operating_point_tables, operating_point_values
    from webline.report.verdict_text import verdict_lines
    from webline.sim.stability import stability_findings
    from webline.verdict import Verdict

    loaded = _load(line, scenario, controller, sets)
    t = analysis_time(loaded) if at is None else at
    if not t >= 0:
        raise BadInput(f"--time: must be >= 0 s, got {at}")
    display = Display(units.value)
    point = operating_point(loaded, t)
    modes = closed_loop_modes(loaded, t)
    cert = _certificate(loaded) if certificate else None
    verdict = Verdict.of(stability_findings(loaded, t))
    if as_json:
        payload: dict[str, object] = {
            "line": loaded.name, "scenario": scenario, "units": units.value,
            "operating_point": operating_point_values(point, display),
            "closed_loop_modes": [m.as_dict() for m in modes], "verdict": verdict.as_dict()}
        if cert is not None:
            payload["certificate"] = {"holds": cert.holds, "worst_ratio": cert.worst_ratio,
                                      "max_real": cert.max_real,
                                      "max_real_plant": cert.max_real_plant,
                                      "sampled_radius": cert.sampled_radius,
                                      "sections": cert.rows()}
        typer.echo(json.dumps(payload, indent=2, default=float))
    else:
        tables = [*operating_point_tables(loaded, point, display), modes_table(modes)]
        print_tables(tables, _console())
        typer.echo("\n".join(verdict_lines(verdict)))
        if cert is not None:
            _print_certificate(cert)
    if verdict.exit_code:
        raise typer.Exit(verdict.exit_code)


def _certificate(line: Line) -> Certificate:
    """The decentralized certificate of ``line`` with webline's default design."""
    from webline.analysis.certificate import certificate

    return certificate(line)


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
) -> None:
    """Run a named study (thesis reproductions): figures, table.csv and summary.txt."""
    from webline.studies import STUDIES

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
    folder = prepare_out(out or Path("out") / f"study-{name}")
    result = STUDIES[name](folder, quick=quick)
    typer.echo(result.summary)
    if result.verdict is not None:
        typer.echo(f"verdict of its runs: {result.verdict.headline}")
    typer.echo(str(folder.resolve()))


from webline.cli_sweep import sweep_command  # noqa: E402  (its own module: cli.py is long)

app.command("sweep")(handles_errors(sweep_command))


def main() -> None:
    """Console-script entry point."""
    app(prog_name="webline")
