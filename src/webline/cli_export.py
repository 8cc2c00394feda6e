"""``webline export LINE --fmu OUT.fmu``: the line with its built-in controllers as an FMI 2.0
or 3.0 co-simulation FMU (``webline.fmu``, docs/fmu.md).

Registered on the app by ``webline.cli``; it imports nothing from there (no cycle).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from webline.errors import ArgumentError


def export_command(
    line: Annotated[str, typer.Argument(help="A built-in line name or a line file.")],
    fmu: Annotated[Path | None, typer.Option("--fmu", help="Write the FMU to this file.")] = None,
    fmi: Annotated[int, typer.Option("--fmi", help="FMI version: 2 or 3.")] = 3,
    step: Annotated[str | None, typer.Option(
        "--step", help="Communication step (e.g. '10 ms'), a whole number of controller "
        "periods; default: one period.")] = None,
    scenario: Annotated[str | None, typer.Option(
        "--scenario", help="A named scenario of the line file for the FMU's references "
        "and events.")] = None,
    plant_only: Annotated[bool, typer.Option(
        "--plant-only", help="The drives' torque commands as inputs, the controllers left "
        "out (for a PLC's or a user's controller to close the loop).")] = False,
) -> None:
    """Export LINE with its built-in controllers (or, with --plant-only, without them) as a
    co-simulation FMU for Linux x86-64 that runs without Python (docs/fmu.md); a single-path
    line as its line of one web. Needs a C compiler (cc or gcc) to link it."""
    from webline.fmu.export import export_fmu
    from webline.spec.source import file_is_branched

    if fmu is None:
        raise ArgumentError("export: say where to write the FMU with --fmu OUT.fmu")
    path = export_fmu(line, fmu, fmi=fmi, step=step, scenario=scenario, plant_only=plant_only)
    if not file_is_branched(line):  # (read: the export above took it)
        typer.echo(f"{line}: a single-path line, exported as its line of one web "
                   "(docs/fmu.md)", err=True)
    typer.echo(str(path))
