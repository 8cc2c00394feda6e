"""``webline benchmark``: the built-in controller families and the user's controllers on
the standard set (docs/benchmark.md), ranked.

Registered on the app by ``webline.cli``; it imports nothing from there (no cycle).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from webline.cli_common import BadInput, _console, open_output, progress_bar

# the simulation and studies layers load inside the command, so that --help stays fast


def benchmark_command(
    controller: Annotated[list[str] | None, typer.Option(
        "--controller", "-c", metavar="FILE.py:NAME", help="A controller of yours to rank "
        "(repeatable): FILE.py:NAME or MODULE:NAME, a class or factory called with no "
        "arguments, or a controller object (docs/controllers.md).")] = None,
    quick: Annotated[bool, typer.Option(
        "--quick", help="The quick subset (3 cases, 2 Monte Carlo samples), as the tests "
        "use; its numbers are not the standard set's.")] = False,
    builtin: Annotated[bool, typer.Option(
        "--builtin/--no-builtin", help="Rank the built-in families too.")] = True,
    out: Annotated[Path, typer.Option(
        "--out", "-o", help="Output folder.")] = Path("out") / "benchmark",
    force: Annotated[bool, typer.Option(
        "--force", help="Write into a non-empty folder webline did not write.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
) -> None:
    """Rank controllers on the standard benchmark set (versioned): tension IAE, peak and
    settling, speed IAE, torque RMS, energy and Monte Carlo robustness, the same settings
    for every contender. Writes benchmark.csv, runs.csv and benchmark.md. Exit 0 when the
    set ran (a contender that failed a case is scored "failed" there), 2 for bad input."""
    from rich.markup import escape
    from rich.table import Table

    from webline.studies.benchmark.contenders import BUILTIN, user_contenders
    from webline.studies.benchmark.result import FILES
    from webline.studies.benchmark.run import benchmark
    from webline.studies.benchmark.standard_set import cases

    controllers = list(controller or [])
    if not builtin and not controllers:
        raise BadInput("--no-builtin needs at least one --controller")
    user_contenders(controllers)  # a bad name is one line, exit 2, before anything runs
    folder = open_output(out, force, "benchmark", FILES)
    total = len(cases(quick)) * (len(BUILTIN) * builtin + len(controllers))
    with progress_bar(not quiet, "benchmark") as bar:
        result = benchmark(controllers, quick=quick, builtin=builtin,
                           progress=None if bar is None else
                           lambda done, _, label: bar(done / total))
    result.write(folder.path, folder.claim)
    folder.finish()
    table = Table(title=f"webline benchmark v{result.version} (set {result.set_hash}"
                  f"{', quick subset' if quick else ''}): lower mean rank is better",
                  title_justify="left")
    for column in ("place", "contender", "mean rank", "pairs", "cases run", "failed", "n/a"):
        table.add_column(column)
    for row in result.ranking.itertuples(index=False):
        table.add_row(*(escape(f"{v:.3g}" if isinstance(v, float) else str(v))
                        for v in row))
    _console().print(table)
    for run in result.runs:
        if run.status in ("failed", "n/a"):
            typer.echo(f"{run.case}, {run.contender}: {run.status}: {run.note}")
    typer.echo(f"Report: {(folder.path / 'benchmark.md').resolve()}")
