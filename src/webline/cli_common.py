"""What every ``webline`` command shares: option types, the error wrapper, the terminal's
tables and progress bar, and loading a line as a command runs it (``--controller``,
``--scenario``, ``--set``)."""

from __future__ import annotations

import faulthandler
import functools
import inspect
import signal
import sys
import typing
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

from webline.errors import WeblineError, terminate_as_interrupt

#: exit status of a command stopped by Ctrl-C (128 + SIGINT) and by SIGTERM (128 + SIGTERM)
INTERRUPTED, TERMINATED = 130, 143

if TYPE_CHECKING:
    from webline.line import Line
    from webline.report.outputs import OutputFolder

class Units(StrEnum):
    si = "si"
    imperial = "imperial"
    si_per_width = "si-per-width"  # tensions (every force) in N/m of web width
    imperial_per_width = "imperial-per-width"  # tensions in pli (lbf per inch of width)


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
UnitsOpt = Annotated[Units, typer.Option(
    "--units", "-u", help="Units to show quantities in; the per-width systems show tensions "
    "(every force) per width of web: N/m, or pli (lbf/in).")]
ScenarioOpt = Annotated[str | None, typer.Option(
    "--scenario", "-s", help="A named scenario of the line file (see 'webline show').")]
SetOpt = Annotated[list[str] | None, typer.Option(
    "--set", metavar="PATH=VALUE", help="Change one value of the line, by its nested path, "
    "with units (repeatable): --set web.ea='9 kN' --set "
    "rollers.process.controller.tension_bandwidth='2 Hz'. Applied after --scenario.")]

F = TypeVar("F", bound=Callable[..., None])


def handles_errors(command: F, *, resume: str = "") -> F:
    """Turn webline's errors into one line on stderr and their exit status, no traceback; so
    too an optional package that is missing (``webline.extras``: the extra to install), and
    Ctrl-C or SIGTERM where the command has no handling of its own (exit 130 or 143, with
    ``resume``: how to go on, if the command can)."""

    @functools.wraps(command)
    def wrapper(*args: object, **kwargs: object) -> None:
        try:
            command(*args, **kwargs)
        except WeblineError as exc:
            fail(str(exc), exc.exit_code)
        except OSError as exc:  # a full disk, a folder gone: the command failed, say why
            from webline.files import write_failure

            fail(write_failure(exc), 1)
        except KeyboardInterrupt as exc:  # a command without its own handling (sweep, study)
            why = ("stopped by SIGTERM" if getattr(exc, "signum", None) == signal.SIGTERM
                   else "interrupted (Ctrl-C)")
            fail(f"{why}: every file already written is whole" + (f"; {resume}" if resume
                                                                 else ""), INTERRUPTED)
        except ModuleNotFoundError as exc:
            from webline.extras import missing_extra

            missing = missing_extra(exc)
            if missing is None:
                raise
            fail(str(missing), missing.exit_code)

    return wrapper  # type: ignore[return-value]


AllowCodeOpt = Annotated[bool, typer.Option(
    "--allow-code", help="Run the Python code the line file names (type = \"python\" "
    "controllers) from the line file's own folder; without it such a line is refused "
    "before anything is imported (docs/security.md).")]


def _no_debugger(*args: object, **kwargs: object) -> None:
    """``breakpoint()`` in a command-line run: an error (the controller that called it fails
    the run, named) instead of a debugger's prompt."""
    raise RuntimeError("breakpoint() called during a command-line run, which opens no "
                       "debugger; debug the controller from Python (webline.simulate)")


def runs_code(command: F) -> F:
    """``command`` with an ``--allow-code`` option: within it, runs may import the Python
    code their line file names from its own folder (``spec.code_consent.allowing_code``),
    and ``breakpoint()`` raises instead of waiting for a debugger."""
    from webline.spec.code_consent import allowing_code

    @functools.wraps(command)
    def wrapper(*args: object, allow_code: bool = False, **kwargs: object) -> None:
        hook = sys.breakpointhook
        sys.breakpointhook = _no_debugger  # (a prompt would wait forever on a terminal)
        if not faulthandler.is_enabled():  # a compiled law that crashes the process: its
            faulthandler.enable()  # stack (law_kernel) is printed, docs/controllers.md
        try:
            with allowing_code(allow_code):
                command(*args, **kwargs)
        finally:
            sys.breakpointhook = hook

    hints = typing.get_type_hints(command, include_extras=True)  # (typer reads them)
    signature = inspect.signature(command)
    option = inspect.Parameter("allow_code", inspect.Parameter.KEYWORD_ONLY, default=False,
                               annotation=AllowCodeOpt)
    wrapper.__signature__ = signature.replace(  # type: ignore[attr-defined]
        parameters=[*(p.replace(annotation=hints.get(p.name, p.annotation))
                      for p in signature.parameters.values()), option])
    wrapper.__annotations__ = {**hints, "allow_code": AllowCodeOpt}
    return wrapper  # type: ignore[return-value]


@contextmanager
def sigterm_as_interrupt() -> Iterator[Callable[[], bool]]:
    """Within the block SIGTERM stops the command as Ctrl-C does
    (``webline.errors.terminate_as_interrupt``: a run writes what it computed, status
    interrupted); the yielded function says whether a SIGTERM came. Main thread only."""
    received: list[int] = []

    def handler(signum: int, frame: object) -> None:
        received.append(signum)
        terminate_as_interrupt(signum, frame)

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield lambda: bool(received)
    finally:
        signal.signal(signal.SIGTERM, previous)


def fail(message: str, code: int) -> None:
    """Print ``error: message`` on stderr, one line per line of ``message`` (a line file's
    problems), and exit with ``code``."""
    for text in message.splitlines() or [""]:
        typer.echo("error: " + " ".join(text.split()), err=True)
    raise typer.Exit(code)


def _console() -> Console:
    """Standard output for tables: the terminal's width, or 160 columns when piped."""
    console = Console(highlight=False)
    if not console.is_terminal:
        console.width = 160
    return console


def print_tables(tables: list, console: Console) -> None:
    """Print report tables (``webline.report.text.tables.Table``) with rich, skipping empty ones."""
    for table in tables:
        if not table.rows:
            continue
        out = RichTable(title=escape(table.title), title_justify="left", title_style="bold")
        for column in table.columns:
            out.add_column(escape(column), overflow="fold")
        for row in table.rows:
            out.add_row(*(escape(cell) for cell in row))
        console.print(out)


def _load(source: str | Line, scenario: str | None, controller: ControllerFamily | None = None,
          sets: list[str] | None = None) -> Line:
    """The single-path line as a command runs it: loaded (or as given), with
    ``--controller``, ``--scenario`` and every ``--set PATH=VALUE`` applied, in that order."""
    from webline.line import load_line

    line = load_line(source)
    if controller is not None:
        from webline.control.select import with_controller

        line = with_controller(line, FAMILY_TYPES[controller.value])  # type: ignore[arg-type]
    if scenario:
        line = line.with_scenario(scenario)
    changes = parse_sets(sets)
    return line.replace(changes) if changes else line


def code_notes(line: object) -> None:
    """Tell (stderr, a ``note:`` each) which Python code a line (or branched line, or a path
    or name of one) names: ``validate`` and ``show`` never import it, ``run`` only with
    ``--allow-code`` or the allow-list (docs/security.md)."""
    from webline.sim.user_objects import named_code

    if isinstance(line, str):  # (a branched line's source: its names only)
        from webline.model.web_graph import load_branched

        line = load_branched(line)
    for key, text in named_code(line):  # type: ignore[arg-type]
        typer.echo(f"note: {line.source}: {key} names Python code {text!r}; it was not "  # type: ignore[attr-defined]
                   "imported, and runs only with --allow-code or the allow-list "
                   "(docs/security.md)", err=True)


def parse_sets(sets: list[str] | None) -> dict[str, object]:
    """``--set PATH=VALUE`` options as {path: value} (``spec.paths.parse_assignment``), in
    the order given (a later one of the same path wins); ``BadInput`` for one without '='."""
    from webline.spec.paths import parse_assignment

    changes = {}
    for text in sets or []:
        try:
            path, value = parse_assignment(text)
        except ValueError as exc:
            raise BadInput(f"--set: {exc}") from None
        changes[path] = value
    return changes


def time_option(text: str, option: str, *, zero: bool = False) -> float:
    """The value [s] of a time ``option`` as typed: a plain number is seconds, else a number
    with a unit (``"2 min"``); it must be > 0 (>= 0 with ``zero``)."""
    try:
        value = float(text)  # a plain number is seconds
    except ValueError:
        value = None
    try:
        from webline.units import to_si

        value = to_si(text, "time") if value is None else value
    except ValueError as exc:
        raise BadInput(f"{option}: {exc}") from None
    if not (value >= 0 if zero else value > 0):
        raise BadInput(f"{option}: must be {'>=' if zero else '>'} 0 s, got {text!r}")
    return value


def _duration(text: str | None) -> float | None:
    return None if text is None else time_option(text, "--duration")


def open_output(out: Path, force: bool, kind: str,
                writes: tuple[str, ...] = ()) -> OutputFolder:
    """The output folder ``out`` of the command ``kind`` (``run``, ``sweep``, ``study NAME``),
    opened (``report.outputs.OutputFolder.open``: links and non-folders refused; non-empty
    folders webline did not write and folders of another kind refused unless ``force``; any of
    ``writes`` that a file webline did not write is in the way of refused, even with
    ``force``) and checked to take files."""
    from webline.report.outputs import OutputFolder

    folder = OutputFolder.open(out, kind=kind, force=force, writes=writes)
    try:
        probe = out / ".webline-write-test"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise BadInput(f"{out}: cannot write to the output folder ({reason})") from None
    return folder


@contextmanager
def progress_bar(enabled: bool, label: str) -> Iterator[Callable[[float], None] | None]:
    """A progress bar on stderr (cleared when done) fed with the fraction done, or None. Until
    the first fraction arrives it says that the line's compiled loop is being loaded, or
    compiled the first time a line of this structure runs (numba; seconds, then cached)."""
    if not enabled:
        yield None
        return
    waiting = "loading the line's compiled loop (compiled once per line structure)"
    from webline.compile_ahead import FIRST_COMPILE_CPU_S, cache_is_empty

    if cache_is_empty():  # the first run of this webline version: say what the wait is
        waiting = (f"compiling the simulation loop, once for this webline version (about "
                   f"{FIRST_COMPILE_CPU_S['run hswl']:.0f} s of CPU; `webline warm` does it ahead)")
    columns = (TextColumn("{task.description}"), BarColumn(), TaskProgressColumn(),
               TimeElapsedColumn())
    with Progress(*columns, console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(escape(waiting), total=1.0)
        yield lambda fraction: bar.update(task, completed=fraction, description=escape(label))
