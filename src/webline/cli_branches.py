"""``webline run`` of a branched line (docs/branching.md): results.nc, summary.json and a
tensions-per-web figure; the verdict per web and lane printed and in the exit status."""

from __future__ import annotations

import json
from pathlib import Path

import typer

from webline.cli_common import BadInput, open_output
from webline.files import atomic_write, atomic_write_text
from webline.model.web_graph import load_branched
from webline.sim.branches.run import simulate_branches
from webline.version import __version__

FIGURE = "figures/tensions.png"


def run_branched(source: str, seconds: float | None, scenario: str | None, out: Path | None,
                 force: bool, quiet: bool, unsupported: dict[str, bool]) -> None:
    """Simulate branched line ``source`` and write its files into ``out`` (default
    out/LINE[-SCENARIO]); ``unsupported``: options given that stage 1 does not support."""
    for option, given in unsupported.items():
        if given:
            raise BadInput(f"{option}: not yet supported for a branched line (stage 1: the "
                           "file's cascaded PI drives; results.nc in SI, summary.json and the "
                           "tensions figure)")
    line = load_branched(source)
    if scenario:
        line = line.with_scenario(scenario)
    folder = open_output(out or Path("out") / (line.name + (f"-{scenario}" if scenario else "")),
                         force, "run", ("results.nc", "summary.json", FIGURE))
    if seconds is None and scenario:
        seconds = line.spec.scenarios[scenario].duration
    result = simulate_branches(line, seconds, raise_on_failure=False)
    from webline.report.plots.branch_figures import tensions_figure
    from webline.spec.load import dump_spec

    results = folder.claim("results.nc")  # every output embeds its inputs: the line's spec
    ds = result.dataset.assign_attrs(line_spec=dump_spec(line.spec))
    atomic_write(results, lambda path: ds.to_netcdf(path, engine="h5netcdf"))
    summary = {"line": line.name, "scenario": scenario, "webline_version": __version__,
               "settings": result.settings, "verdict": result.verdict.as_dict(),
               "webs": result.web_summary(), "failure": result.failure}
    atomic_write_text(folder.claim("summary.json"), json.dumps(summary, indent=1) + "\n")
    figure = tensions_figure(result)
    atomic_write(folder.claim(FIGURE), lambda path: figure.savefig(path, format="png", dpi=110))
    folder.finish()
    if not quiet:
        for web in result.web_summary():
            table = web["spans"]
            assert isinstance(table, dict)
            spans = ", ".join(f"{name} {v['min_N']:.4g}-{v['max_N']:.4g} N"
                              for name, v in table.items())
            typer.echo(f"{web['kind']} {web['web']}: {spans}")
        typer.echo(f"Results (SI): {results}\nSummary: {folder.path / 'summary.json'}\n"
                   f"Figure: {folder.path / FIGURE}")
    typer.echo(result.verdict.headline, err=True)
    if result.verdict.exit_code:
        raise typer.Exit(result.verdict.exit_code)
