"""``webline tune`` and ``webline experiment``: controllers tuned on a line's scenarios, and
the identification tests a drive engineer runs on the machine.

Registered on the app by ``webline.cli``; it imports nothing from there (no cycle).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer

from webline.cli_common import BadInput, LineArg, open_output
from webline.errors import WeblineError

# the twin and simulation layers load inside the commands, so that --help stays fast


def _uncertain(texts: list[str]) -> dict[str, str]:
    out = {}
    for text in texts:
        path, sep, dist = text.partition("=")
        if not sep or not path.strip() or not dist.strip():
            raise BadInput(f"--uncertain {text!r}: expected PATH=DIST, e.g. "
                           "web.modulus='normal(4 GPa, 10 %)'")
        out[path.strip()] = dist.strip()
    return out


def tune_command(
    line: LineArg,
    out: Annotated[Path, typer.Option("--out", "-o", help="Output folder.")],
    scenario: Annotated[list[str] | None, typer.Option(
        "--scenario", "-s", help="A scenario to tune on (repeatable; default: the line's "
        "scenarios without a web break that last at most 60 s).")] = None,
    free: Annotated[list[str] | None, typer.Option(
        "--free", metavar="PATH=LOW..HIGH", help="A value to tune within bounds, with units "
        "(repeatable; default: every cascaded-PI drive's speed and tension bandwidths, a "
        "third to three times their values).")] = None,
    fit: Annotated[Path | None, typer.Option(
        "--fit", help="A fit's fit.json (or its folder): the robustness Monte Carlo draws its "
        "parameters from normal(value, stderr). A fit whose verdict is not good is refused "
        "(exit 2) unless --poor-fit widen.")] = None,
    poor_fit: Annotated[str, typer.Option(
        "--poor-fit", metavar="refuse|widen", help="What to do with a --fit whose verdict is "
        "poor or failed: refuse it (exit 2), or widen its parameters to their bounds "
        "(uniform draws).")] = "refuse",
    uncertain: Annotated[list[str] | None, typer.Option(
        "--uncertain", metavar="PATH=DIST", help="An uncertain parameter of the robustness "
        "Monte Carlo (repeatable), e.g. web.modulus='normal(4 GPa, 10 %)'; overrides --fit "
        "for the same path. Default without --fit: modulus and inertias 10 %, dancer damping "
        "30 %.")] = None,
    evaluations: Annotated[int, typer.Option(
        "--evaluations", min=1, help="Most candidates simulated (each runs every "
        "scenario).")] = 200,
    samples: Annotated[int, typer.Option(
        "--samples", min=0, help="Draws of the robustness Monte Carlo.")] = 20,
    seed: Annotated[int, typer.Option("--seed", min=0, help="Seed of the optimiser and the "
                                      "draws.")] = 0,
    force: Annotated[bool, typer.Option(
        "--force", help="Write into a non-empty folder webline did not write.")] = False,
) -> None:
    """Tune LINE's controllers: lowest tension error over the scenarios, every margin,
    torque limit and robustness constraint held. Exit 0 when every constraint holds, 1 when
    one does not (the files say which)."""
    from webline.twin.tuning.tune import line_ops, tune
    from webline.twin.tuning.tune_output import FILES, write_tune
    from webline.twin.tuning.tune_robust import fit_uncertain
    from webline.twin.tuning.tune_space import parse_free

    base = line_ops(line).load(line)  # a single-path or a branched line (docs/branching.md)
    space = None if not free else [parse_free(base, text) for text in free]
    dists: dict[str, Any] | None = None
    notes: list[str] = []
    if fit is not None:
        if poor_fit not in ("refuse", "widen"):
            raise BadInput(f"--poor-fit: expected refuse or widen, got {poor_fit!r}")
        dists, notes = fit_uncertain(fit / "fit.json" if fit.is_dir() else fit, poor_fit)
    if uncertain:
        dists = {**(dists or {}), **_uncertain(uncertain)}
    folder = open_output(out, force, "tune", FILES)

    def report(n: int, best: float) -> None:
        typer.echo(f"  {n} candidates, best objective {best:.4g}", err=True)

    result = tune(base, scenario or None, free=space, uncertain=dists, samples=samples,
                  seed=seed, evaluations=evaluations, progress=report)
    write_tune(result, folder.path, folder.claim)
    folder.finish()
    for note in (*notes, *result.notes):
        typer.echo(f"note: {note}")
    typer.echo(result.summary())
    typer.echo(str(folder.path.resolve()))
    if not result.holds:
        raise typer.Exit(1)


def experiment_command(
    line: LineArg,
    name: Annotated[str | None, typer.Argument(
        metavar="NAME", help="accel-ramps, tension-step or dancer-step.")] = None,
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder (default out/experiment-NAME).")] = None,
    list_: Annotated[bool, typer.Option(
        "--list", help="List the experiments, what each identifies and how long it runs "
        "on LINE.")] = False,
    force: Annotated[bool, typer.Option(
        "--force", help="Write into a non-empty folder webline did not write.")] = False,
    identify: Annotated[list[str] | None, typer.Option(
        "--identify", help="Parameters the test should identify, checked before it runs "
        "(sensitivities of the logged signals): PATH or PATH=LOW..HIGH UNIT, comma-"
        "separated or repeated, e.g. rollers.process.inertia,web.ea.")] = None,
) -> None:
    """Simulate an identification test on LINE and write the traces to record."""
    from webline.model.lines import load_line
    from webline.twin.tuning.experiment import EXPERIMENTS, plan_experiment, write_experiment
    from webline.twin.tuning.experiment_branched import PLANNERS, write_branched_experiment

    base: Any = load_line(line)
    branched = base.branched  # the same tests on its drives and zones
    write = write_branched_experiment if branched else write_experiment

    def planned(key: str) -> Any:
        return PLANNERS[key](base) if branched else plan_experiment(base, key)

    if list_:
        for key, experiment in EXPERIMENTS.items():
            try:
                duration = f"{planned(key).duration:g} s on {base.name}"
            except WeblineError as exc:  # the test does not apply to this line
                duration = f"not on {base.name}: {exc}"
            typer.echo(f"{key}: {experiment.title}; identifies "
                       f"{'; '.join(experiment.identifies)}; {duration} "
                       f"({experiment.duration_rule})")
        return
    if name is None:
        raise BadInput("give an experiment NAME or --list")
    if name not in EXPERIMENTS:
        raise BadInput(f"no experiment named {name!r}; known: {', '.join(EXPERIMENTS)}")
    check = None
    if identify:
        from webline.twin.tuning.experiment_sensitivity import check_plan

        wanted = [item for text in identify for item in text.split(",") if item.strip()]
        check = check_plan(planned(name), wanted)  # before anything is written
        typer.echo(f"sensitivity check of {name} on {base.name} (condition number "
                   f"{check.condition:.3g}):")
        for text in check.lines():
            typer.echo(f"  {text}")
        missed = [p for p, ok in zip(check.paths, check.identifiable, strict=True) if not ok]
        if missed:
            typer.echo(f"warning: {name} cannot identify {', '.join(missed)}: choose another "
                       "test for them (webline experiment LINE --list)")
    folder = open_output(out or Path("out") / f"experiment-{name}", force, "experiment",
                         ("results.csv", "experiment.json"))
    plan, result = write(base, name, folder.path, folder.claim)
    if check is not None:
        path = folder.path / "experiment.json"
        data = json.loads(path.read_text(encoding="utf-8")) | {"sensitivity": check.as_dict()}
        path.write_text(json.dumps(data, indent=2), encoding="utf-8")
    folder.finish()
    typer.echo(f"{name} on {base.name}: {plan.duration:g} s; identifies "
               f"{'; '.join(plan.experiment.identifies)}")
    for text in plan.derivation:
        typer.echo(f"  {text}")
    typer.echo(f"verdict: {result.verdict.headline}")
    typer.echo(str(folder.path.resolve()))
