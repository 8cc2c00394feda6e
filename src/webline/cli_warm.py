"""``webline warm``: compile ahead the simulation loops a user will need (``webline.sim.warm``),
so that the first ``webline run`` does not wait for the compiler.

Registered on the app by ``webline.cli``; it imports nothing from there (no cycle).
"""

from __future__ import annotations

from typing import Annotated

import typer

# the simulation layer loads inside the command, so that --help stays fast


def warm_command(
    lines: Annotated[
        list[str] | None,
        typer.Argument(
            metavar="[LINE]...",
            help="Built-in line names or line files; default: hswl and "
            "laminator (a single-path and a branched line).",
        ),
    ] = None,
    sweeps: Annotated[
        bool,
        typer.Option("--sweeps/--no-sweeps", help="Also the batch loop of sweeps and Monte Carlo."),
    ] = True,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing.")] = False,
) -> None:
    """Compile and cache the simulation loops of LINE's runs (and sweeps) ahead, once after
    installing: later runs load them in a fraction of a second. Compiling from empty caches
    takes a minute or two of CPU; a warm cache makes this command take about a second."""
    from webline import compile_ahead as warm

    chosen = list(lines) if lines else list(warm.DEFAULT_LINES)
    names = warm.targets(chosen, sweeps=sweeps)

    def say(text: str) -> None:
        if not quiet:
            typer.echo(text, err=True)

    warm.check_lines(chosen)  # a bad name: one line, exit 2 (handles_errors), before anything
    if warm.cache_is_empty():
        estimate = warm.first_compile_estimate(names)
        say(
            f"First run of this webline version: compiling its simulation loops "
            f"({', '.join(names)}) into {warm.cache_folder()}; about {estimate:.0f} CPU-seconds "
            f"(~{estimate / 60:.0f} min on one free core), once: later runs load them."
        )
    # a bad line file raises LineFileError: handles_errors makes it one line and exit 2
    done = warm.warm(chosen, sweeps=sweeps, progress=lambda name: say(f"  {name} ..."))
    total = sum(item.seconds for item in done)
    say(f"Compiled loops ready ({len(done)} targets, {total:.1f} s).")
