"""``webline run`` of a branched line (docs/branching.md): results.nc, summary.json, the
figures and report.html; the verdict per web and lane printed and in the exit status.
``webline show`` of a branched line: its tables, and its schematic on request."""

from __future__ import annotations

from pathlib import Path

import typer

from webline.cli_common import BadInput, open_output, parse_sets, progress_bar
from webline.files import atomic_write
from webline.model.web_graph import BranchedLine, load_branched
from webline.report.results_file import results_name
from webline.report.writer import branch_display
from webline.sim.branches.run import simulate_branches
from webline.sim.branches.winder import splice_summary

FIGURE = "figures/tensions.png"
REPORT = "report.html"


def run_branched(source: str | BranchedLine, seconds: float | None, scenario: str | None,
                 out: Path | None, force: bool, quiet: bool, svg: bool = False, units: str = "si",
                 sets: list[str] | None = None,
                 data_format: str = "netcdf", precision: str = "float64",
                 family: str | None = None) -> None:
    """Simulate branched line ``source`` (``sets``: ``--set PATH=VALUE``, applied after
    ``scenario``) and write its files into ``out`` (default out/LINE[-SCENARIO]): the results
    as ``data_format`` ('netcdf': results.nc, floats as ``precision``; 'csv': results.csv;
    ``sim.results.dataset_files``), each figure also as SVG with ``svg``, the report in
    ``units`` ('si' or 'imperial'). ``quiet``: print only the report's path. ``family``:
    every drive runs this controller family (``--controller``, its line-file type) instead
    of the file's; the file's python controllers run as in ``simulate`` (docs/controllers.md,
    "On a branched line")."""
    display = branch_display(units)
    line = branched_line(source, scenario, sets, family)
    from webline.sim.user_objects import branched_controllers, check_consent

    check_consent(line)  # (before anything is written: a refusal is one line)
    name = results_name(data_format)  # type: ignore[arg-type]
    folder = open_output(out or Path("out") / (line.name + (f"-{scenario}" if scenario else "")),
                         force, "run", (name, "summary.json", FIGURE, REPORT))
    if seconds is None and scenario:
        seconds = line.spec.scenarios[scenario].duration
    with progress_bar(not quiet, f"simulating {line.name}") as progress:
        result = simulate_branches(line, seconds, raise_on_failure=False,
                                   controller=branched_controllers(line, None), progress=progress)
    from webline.report.branch_report import write_branch_report

    results = folder.claim(name)  # NetCDF: with the resolved line file (line_spec)
    if data_format == "csv":
        result.to_csv(results)
    else:
        result.to_netcdf(results, precision)  # type: ignore[arg-type]
    report = write_branch_report(result, folder.path, folder=folder, results_file=results,
                                 svg=svg, display=display).report
    folder.finish()
    if not quiet:
        for w, web in enumerate(result.web_summary()):
            table = web["spans"]
            assert isinstance(table, dict)
            shown = display.at_width(line.materials[w].width)  # (per width: its own)
            f, unit = shown.factor("force"), shown.unit("force")
            spans = ", ".join(f"{name} {f * v['min_N']:.4g}-{f * v['max_N']:.4g} {unit}"
                              for name, v in table.items())
            typer.echo(f"{web['kind']} {web['web']}: {spans}")
        for item in splice_summary(result):  # docs/branching.md, flying splice
            typer.echo(f"flying splice of {item['roll']} at t = {item['time_s']:.4g} s: "
                       f"largest change {item['largest_change_N']:.4g} N in "
                       f"{item['largest_change_span']}; old roll stops in >= "
                       f"{item['old_stop_s']:.3g} s, new roll runs up in >= "
                       f"{item['new_run_up_s']:.3g} s at the torque limit")
        typer.echo(f"Results (SI): {results}\nSummary: {folder.path / 'summary.json'}\n"
                   f"Figures: {folder.path / 'figures'}\nReport: {report}")
    else:
        typer.echo(str(report))
    typer.echo(result.verdict.headline, err=True)
    if result.verdict.exit_code:
        raise typer.Exit(result.verdict.exit_code)


def branched_line(source: str | BranchedLine, scenario: str | None, sets: list[str] | None,
                  family: str | None = None) -> BranchedLine:
    """Branched line ``source`` as a command runs it: with ``--controller`` (every drive on
    ``family``, its line-file type), ``scenario``, then every ``--set PATH=VALUE`` of
    ``sets`` (``BranchedLine.replace``: a bad path or value is one line naming it, exit 2),
    in the chain's order."""
    changes = parse_sets(sets)
    line = load_branched(source)
    if family is not None:
        from webline.control.select import with_branched_controller

        line = with_branched_controller(line, family)  # type: ignore[arg-type]
    if scenario:
        line = line.with_scenario(scenario)
    return line.replace(changes)


def show_branched(source: str | BranchedLine, scenario: str | None, schematic: Path | None,
                  units: str = "si", sets: list[str] | None = None) -> list:
    """The tables of branched line ``source`` (``report.text.branch_tables``) in ``units``,
    with ``scenario`` and ``sets`` (``--set``) applied; with ``schematic``, its schematic
    written there (PNG, or SVG/PDF by the file's suffix)."""
    display = branch_display(units)
    line = branched_line(source, scenario, sets)
    from webline.report.text.branch_tables import line_tables

    if schematic is not None:
        write_schematic(line, schematic)
    return line_tables(line, display)


def write_schematic(line: object, path: Path, display: object = None) -> None:
    """Save the schematic of ``line`` (a ``BranchedLine`` or a ``Line``, its lengths and
    forces in ``display``'s units) to ``path``: PNG, SVG or PDF by its suffix."""
    from webline.model.web_graph import BranchedLine

    fmt = path.suffix.lower().lstrip(".")
    if fmt not in ("png", "svg", "pdf"):
        raise BadInput(f"--schematic {path}: give a .png, .svg or .pdf file")
    if isinstance(line, BranchedLine):
        from webline.report.plots.branch_schematic import branch_schematic

        figure = branch_schematic(line)
    else:
        from webline.report.plots.schematic import schematic

        figure = schematic(line, display)  # type: ignore[arg-type]
    atomic_write(path, lambda target: figure.savefig(target, format=fmt, dpi=110))
