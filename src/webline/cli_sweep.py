"""``webline sweep``: a parameter sweep or Monte Carlo study from the command line.

Registered on the app by ``webline.cli``; it imports nothing from there (no cycle).
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TaskProgressColumn,
    TextColumn,
    TimeRemainingColumn,
)
from rich.table import Table as RichTable

from webline.cli_common import Units, UnitsOpt, _duration, fail, open_output
from webline.errors import ArgumentError
from webline.spec.paths import split_values, toml_value

if TYPE_CHECKING:
    from webline.report.outputs import OutputFolder
    from webline.report.text.display import Display

#: the chunk store's folder in a sweep's output folder (``webline.sim.sweeps.chunks``)
CHUNKS = "chunks"

# webline.units (pint) and the simulation layers load inside the functions that use them, so
# that `webline --version` and `--help` stay fast.


def whole_count(text: str, option: str) -> int:
    """A count as typed (``1000``, ``1e9``, ``1_000``): a whole number >= 1, else
    ``ArgumentError`` naming ``option``."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value >= 1 and value == math.floor(value)):
        raise ArgumentError(f"{option}: expected a whole number >= 1, got {text.strip()!r}")
    return int(value)


def parse_range(path: str, text: str) -> list[object]:
    """``start:stop:n``: n values, both ends included, in start's unit. The count is bounded
    (``limits.check_case_count``) before anything is allocated, and start and stop are read
    as strictly as a line file's values (``units.quantity_parts``)."""
    from webline.limits import check_case_count
    from webline.units import quantity_parts, unit_reading

    start, stop, count = (part.strip() for part in text.split(":"))
    n = whole_count(count, f"--set {path}: n of start:stop:n")
    check_case_count(n, f"--set {path}")
    try:
        (a, unit), (b, unit_b) = quantity_parts(start), quantity_parts(stop)
        if unit_b != unit:
            if not unit or not unit_b:
                raise ValueError(f"{start!r} and {stop!r}: write both with a unit or neither")
            factor, dims, _ = unit_reading(unit, start)
            factor_b, dims_b, _ = unit_reading(unit_b, stop)
            if dims != dims_b:
                raise ValueError(f"{start!r} and {stop!r} are not of one kind")
            b = b * factor_b / factor
    except ValueError as exc:
        raise ArgumentError(f"--set {path}: cannot read {text!r} as start:stop:n "
                            f"({exc})") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise ArgumentError(f"--set {path}: start and stop of {text!r} must be finite")
    mags = np.linspace(a, b, n)
    if not unit:
        return [float(m) for m in mags]
    return [f"{float(m)!r} {unit}" for m in mags]


def parse_values(path: str, text: str) -> list[object]:
    """``v1,v2,...`` (each a number, a quantity such as ``9 kN``, or a TOML value: a string,
    a boolean, an inline table ``{type = "state_feedback"}``; commas inside braces, brackets
    and quotes do not split) or ``start:stop:n`` (``parse_range``) as the values of ``path``;
    raises ``ArgumentError`` naming the option."""
    if text.count(":") == 2 and "," not in text:
        return parse_range(path, text)
    values: list[object] = []
    for piece in split_values(text):
        try:
            value = toml_value(piece)
        except ValueError as exc:
            raise ArgumentError(f"--set {path}: {exc}") from None
        values.append(float(value) if isinstance(value, int) and not isinstance(value, bool)
                      else value)
    return values


def parse_sets(sets: list[str], samples: int | None) -> dict[str, Any]:
    """{path: values} (a sweep) or {path: distribution} (with ``--samples``)."""
    out: dict[str, Any] = {}
    for item in sets:
        path, sep, text = item.partition("=")
        path, text = path.strip(), text.strip()
        if not sep or not path or not text:
            raise ArgumentError(f"--set: expected PATH=VALUES, got {item!r}")
        if samples is not None:
            from webline.sim.sweeps.distributions import parse_distribution

            try:
                parse_distribution(text)
            except ValueError as exc:
                raise ArgumentError(f"--set {path}: {exc}") from None
            out[path] = text
        else:
            out[path] = parse_values(path, text)
    return out


def _jsonable_attrs(ds: Any) -> Any:
    ds = ds.copy()
    ds.attrs = {k: (json.dumps(v) if isinstance(v, list | dict) else v)
                for k, v in ds.attrs.items()}
    return ds


def write_outputs(ds: Any, folder: OutputFolder,
                  display: Display | None = None) -> tuple[Path, Path]:
    """Write ``sweep.nc`` (SI) and ``report.html`` (in ``display``'s units, default SI) into
    ``folder`` atomically, list them and the chunk store's files in its manifest and finish
    it (``report.outputs``)."""
    from webline.files import atomic_write_bytes, atomic_write_text
    from webline.report.sweep_report import sweep_html

    # built in memory and written in one plain write, as a run's results
    # (``sim.results.result_files.write_netcdf``): HDF5 crashes closing a file on a full disk
    image = _jsonable_attrs(ds).to_netcdf(engine="h5netcdf")
    results = atomic_write_bytes(folder.claim("sweep.nc"), image)
    report = atomic_write_text(folder.claim("report.html"), sweep_html(ds, display))
    from webline.sim.sweeps.chunks import store_files

    for kept in store_files(folder.path / CHUNKS):  # kept for --resume; its chunk store's
        folder.adopt(f"{CHUNKS}/{kept.name}")  # (written since, beside its claimed record)
    folder.finish()
    return results, report


def _display(line: str, system: str, spec: dict[str, Any]) -> Display:
    """The report's units: ``system``, forces per width of the line's web for the per-width
    systems (refused when the study changes the web's width: no one width to divide by)."""
    from webline.model.lines import load_line
    from webline.report.text.display import Display

    if not system.endswith("per-width"):
        return Display(system)  # type: ignore[arg-type]
    loaded = load_line(line)
    if loaded.branched:  # film, foil, laminate, lanes: each its own width
        raise ArgumentError(f"--units {system}: a branched line's webs and lanes have their "
                            "own widths, so its tensions have no one width to be shown per; "
                            "choose si or imperial")
    if "web.width" in spec:
        raise ArgumentError(f"--units {system}: the study changes web.width, so its tensions "
                            "have no one width to be shown per; choose si or imperial")
    return Display(system, loaded.spec.web.width)  # type: ignore[arg-type]


def sweep_command(
    line: Annotated[str, typer.Argument(metavar="LINE", help="A line file or built-in line.")],
    set_: Annotated[list[str], typer.Option(
        "--set", help="PATH=v1,v2,... or PATH=start:stop:n (a sweep), or with --samples "
        "PATH=normal(9 kN, 5 %) / uniform(a, b) / lognormal(m, s).")],
    samples: Annotated[str | None, typer.Option(
        "--samples", help="Monte Carlo: number of cases drawn (1000, 1e4).")] = None,
    seed: Annotated[int, typer.Option("--seed", help="Monte Carlo seed.")] = 0,
    duration: Annotated[str | None, typer.Option(
        "--duration", "-d", help="Simulated time per case [s] or with a unit.")] = None,
    scenario: Annotated[str | None, typer.Option("--scenario", "-s")] = None,
    workers: Annotated[int | None, typer.Option(
        "--workers", min=1, help="Threads (default: every core); with --scheduler local, the "
        "processes of a Dask LocalCluster.")] = None,
    scheduler: Annotated[str | None, typer.Option(
        "--scheduler", help="A Dask scheduler address, or 'local' for a LocalCluster.")]
    = None,
    resume: Annotated[bool, typer.Option(
        "--resume", help="Go on with the study stored in --out (only missing chunks run); "
        "refused if its line, cases, settings or webline changed.")] = False,
    restart: Annotated[bool, typer.Option(
        "--restart", help="Start the study stored in --out again: remove its chunks and run "
        "every case (e.g. after editing the line).")] = False,
    zip_: Annotated[bool, typer.Option(
        "--zip", help="Pair the i-th values of every --set instead of a grid.")] = False,
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder; default out/LINE-sweep.")] = None,
    quiet: Annotated[bool, typer.Option("--quiet", "-q")] = False,
    units: UnitsOpt = Units.si,
    force: Annotated[bool, typer.Option(
        "--force", help="Write into a non-empty folder webline did not write, or over "
        "another command's output there (the files its manifest lists); never over a file "
        "webline did not write.")]
    = False,
    work_limit: Annotated[bool, typer.Option(
        "--work-limit/--no-work-limit", help="Refuse a study of more than 1e12 RK4 steps "
        "(about a day of one core) before it runs; --no-work-limit lifts it.")] = True,
) -> None:
    """Run a parameter sweep (grid or --zip) or, with --samples, a Monte Carlo study; write
    sweep.nc (SI: metrics and verdict per case, a grid with a dimension per parameter) and an
    HTML report (in --units: the table of cases, verdicts, metrics, figures)."""
    n_samples = None
    if samples is not None:  # bounded before anything is read or allocated
        from webline.limits import check_case_count

        n_samples = whole_count(samples, "--samples")
        check_case_count(n_samples, "--samples")
    spec = parse_sets(set_, n_samples)
    import webline

    if resume and restart:
        raise ArgumentError("--resume and --restart: choose one (go on with the study, or "
                            "start it again)")
    seconds = _duration(duration)  # as run's: a plain number is seconds
    display = _display(line, units.value, spec)
    from webline.sim.sweeps.chunks import STUDY_FILE, store_files

    folder = open_output(out or Path("out") / f"{Path(line).stem}-sweep", force, "sweep",
                         ("sweep.nc", "report.html", f"{CHUNKS}/{STUDY_FILE}"))
    folder.claim(f"{CHUNKS}/{STUDY_FILE}")  # the folder is webline's from here on
    if restart:  # the study's own files only: its record and chunks
        for stale in store_files(folder.path / CHUNKS):
            stale.unlink()
    err = Console(stderr=True, highlight=False)
    columns = (TextColumn("cases"), BarColumn(), MofNCompleteColumn(), TaskProgressColumn(),
               TextColumn("{task.fields[rate]}"), TimeRemainingColumn())
    started = time.perf_counter()
    with Progress(*columns, console=err, transient=True, disable=quiet) as bar:
        task = bar.add_task("cases", total=None, rate="")

        def progress(done: int, total: int) -> None:
            rate = done / max(time.perf_counter() - started, 1e-9)
            bar.update(task, completed=done, total=total, rate=f"{rate:.0f} cases/s")

        common: dict[str, Any] = {
            "duration": seconds, "scenario": scenario, "workers": workers,
            "progress": progress, "scheduler": scheduler, "resume": resume,
            "store": folder.path / CHUNKS,  # chunk by chunk, so a killed run can resume
            "work_limit": work_limit}
        try:
            if n_samples is not None:
                ds = webline.monte_carlo(line, spec, n_samples, seed=seed, **common)
            else:
                ds = webline.sweep(line, spec, mode="zip" if zip_ else "grid", **common)
        except KeyboardInterrupt as exc:  # StudyInterrupted says what --resume continues from
            fail(str(exc) or "interrupted before the study started; nothing saved", 130)
    from webline.report.sweep_report import metric_table, status_table

    try:
        results, report = write_outputs(ds, folder, display)
    except OSError as exc:  # every chunk is saved: a resume only merges them
        from webline.errors import StudyError
        from webline.files import write_failure

        raise StudyError(write_failure(exc, "free some space: --resume will merge the saved "
                                       "chunks without running a case again")) from None
    if not quiet:
        console = Console(highlight=False, width=None if err.is_terminal else 120)
        for table in (status_table(ds), metric_table(ds, display)):
            shown = RichTable(title=escape(table.title), title_justify="left")
            for column in table.columns:
                shown.add_column(escape(column))
            for row in table.rows:
                shown.add_row(*(escape(cell) for cell in row))
            console.print(shown)
        elapsed = time.perf_counter() - started
        console.print(f"{ds.status.size} cases in {elapsed:.1f} s; results: "
                      f"{escape(str(results))}\nReport (open it in a browser):")
    typer.echo(str(report.resolve()))
