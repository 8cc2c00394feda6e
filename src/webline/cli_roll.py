"""``webline taper``: the rewind's taper designed for a good roll (docs/wound-roll.md), checked
by simulating the line with it, and written into a line file ready to run.

Registered on the app by ``webline.cli``; it imports nothing from there (no cycle).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from webline.cli_common import BadInput, LineArg, SetOpt, _load, time_option

if TYPE_CHECKING:
    from webline.line import Line
    from webline.model.web_graph import BranchedLine

#: findings of the simulated roll that reject a taper (a band is reported, not a rejection)
LIMIT_KINDS = ("roll_hoop", "roll_pressure", "roll_core")


def taper_command(
    line: LineArg,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out", "-o", help="The line file to write with the taper (default NAME-taper.toml)."
        ),
    ] = None,
    form: Annotated[
        list[str] | None,
        typer.Option(
            "--form",
            help="A taper form to design (repeatable): linear, hyperbolic (default "
            "both; the one winding the most tension is kept).",
        ),
    ] = None,
    diameter: Annotated[
        str | None,
        typer.Option(
            "--diameter",
            help="The finished roll's diameter, with units (default the "
            "roll_stress table's, else the taper's max_diameter).",
        ),
    ] = None,
    duration: Annotated[
        str, typer.Option("--duration", help="Length of the check run, with units.")
    ] = "10 s",
    check: Annotated[
        bool,
        typer.Option(
            "--check/--no-check", help="Simulate the line with the taper and compute its roll."
        ),
    ] = True,
    roll: Annotated[
        str | None,
        typer.Option(
            "--roll",
            help="The roll to design for on a branched line: ROLLER/WEB (one lane), or a "
            "rewind (every lane on its shaft; default: the only rewind with a roll_stress "
            "table).",
        ),
    ] = None,
    sets: SetOpt = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite the output file.")] = False,
) -> None:
    """Design LINE's rewind taper so that the roll meets the limits of its roll_stress table
    with the most tension, check it by simulating, and write it into a line file. On a
    branched line, the taper of --roll's rewind: on a shaft, one taper under which every
    lane's roll meets the limits (the lane needing most binds), unless --roll names one lane.
    Exit 0 when every simulated roll meets its limits, 1 when one does not or no taper does."""
    from webline.analysis.roll_taper import design_rolls, design_taper, with_taper
    from webline.model.lines import load_line
    from webline.spec.load import dump_spec
    from webline.units import to_si

    loaded = load_line(line)
    if loaded.branched:
        from webline.cli_branches import branched_line

        base: Line | BranchedLine = branched_line(loaded, None, sets)
    else:
        base = _load(loaded, None, None, sets)
    try:
        d = None if diameter is None else to_si(diameter, "length")
    except Exception as exc:  # pint's errors name the unit
        raise BadInput(f"--diameter {diameter!r}: {exc}") from None
    run_s = time_option(duration, "--duration")
    target = out or Path(f"{base.name}-taper.toml")
    if target.exists() and not force:
        raise BadInput(f"{target}: exists (--force to overwrite)")
    designs = design_rolls(base, d, roll)
    for design in designs:
        lim = design.limits
        typer.echo(
            f"{design.roll_name}: roll {1e3 * design.core_radius:.4g}-"
            f"{1e3 * design.outer_radius:.4g} mm of {1e6 * design.thickness:.4g} um web at "
            f"{design.tension:.4g} N x taper; limits: hoop >= {lim.min_hoop / 1e6:.3g} MPa"
            + (f", pressure <= {lim.max_pressure / 1e6:.3g} MPa" if lim.max_pressure else "")
            + (f", core <= {lim.core_rating / 1e6:.3g} MPa" if lim.core_rating else "")
        )
    choices = design_taper(base, tuple(form or ("linear", "hyperbolic")), d, roll)
    for c in choices:
        if c.taper is None:
            typer.echo(f"{c.form}: no taper up to 0.9 meets the limits ({'; '.join(c.below)})")
            continue
        below = f"; a smaller one breaks: {'; '.join(c.below)}" if c.below else ""
        typer.echo(
            f"{c.form}: taper {c.taper:.3f} (mean wound-on stress "
            f"{c.mean_stress / 1e6:.3g} MPa){below}"
        )
        if len(c.lanes) > 1:  # a shaft: which lane binds, what the others keep
            for lane in c.lanes:
                kind, margin = lane.tightest
                typer.echo(
                    f"  {lane.roll_name}: alone {lane.alone:.3f}; {kind} margin "
                    f"{margin / 1e6:.3g} MPa" + (" (binds)" if lane.roll_name == c.binding
                                                 else ""))
    best = choices[0]
    if best.taper is None:
        typer.echo(
            "no taper of these forms meets the limits: lower the tension, stiffen "
            "the core or relax the limits"
        )
        raise typer.Exit(1)
    tapered = with_taper(base, best, d, roll)
    ok = True
    if check:
        import webline

        result = webline.simulate(tapered, run_s)
        for design in designs:  # every lane the taper winds
            which = f", {design.roll_name}" if len(designs) > 1 else ""
            wound = result.wound_rolls.get(design.roll_name)
            found = wound.findings() if wound is not None else []
            meets = wound is not None and not any(f.kind in LIMIT_KINDS for f in found)
            ok = ok and meets
            if wound is not None:
                s = wound.stress
                typer.echo(
                    f"check: {run_s:g} s of {base.name} with {best.form} taper "
                    f"{best.taper:.3f}{which}: min hoop "
                    f"{s.hoop.min() / 1e6:.3g} MPa, max pressure {s.pressure.max() / 1e6:.3g}"
                    f" MPa, core {s.core_pressure / 1e6:.3g} MPa: "
                    + ("meets the limits" if meets else "breaks them")
                )
            for f in found:
                typer.echo(f"  {f.message}")
    target.write_text(dump_spec(tapered.spec), encoding="utf-8")
    typer.echo(str(target.resolve()))
    if not ok:
        raise typer.Exit(1)
