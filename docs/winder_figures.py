"""Draw the figures of the commissioning guide in docs/winder.md from runs of the built-in lines.

    .venv/bin/python docs/winder_figures.py      # writes docs/img/guide-*.png

Each figure is a real webline run (or linear analysis) of a built-in line, drawn with the
report's own figure functions where the report has one, so the guide shows what `webline run`
and `webline analyze` give. The caption of each figure in the guide says which run it is.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

import webline
from webline.analysis import modes_across_roll
from webline.report.display import Display
from webline.report.frame import framed_figure
from webline.report.roll_figures import roll_modes_figure
from webline.report.splice_figures import splice_caption, splice_figure
from webline.report.winder_figures import diameter_figure, taper_figure
from webline.sim.result import Result

IMG = Path(__file__).resolve().parent / "img"
SPRING = 2000.0  # [N/m]: the soft sprung dancer of the zone-loop figure (as in Z1-Z4)
LOAD_STEP = {"type": "steps", "initial": "300 N", "steps": [{"time": "1 s", "value": "360 N"}]}


def _position(result: Result, dancer: str) -> np.ndarray:
    return result.states[:, result.plan.state_names.index(f"{dancer}.position")]


def dancer_startup(result: Result) -> Figure:
    """converter's start from rest: the unwind zone's tensions against load / 2 (top) and the
    carriage against its set position (bottom)."""
    fig = framed_figure(9.0, 5.4, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    for k in (0, 1):
        top.plot(result.time, result.tension[:, k], lw=1.0, label=result.span_names[k])
    carriage = result.line.spec.rollers[1].dancer
    assert carriage is not None
    top.axhline(result.tension_ref[0, 0], color="k", ls="--", lw=0.8,
                label="load / 2 (the dancer's tension)")
    top.set_ylabel("tension [N]")
    bottom.plot(result.time, 1e3 * _position(result, "dancer"), lw=1.0, color="C2",
                label="dancer position")
    bottom.axhline(1e3 * carriage.position, color="k", ls="--", lw=0.8, label="set position")
    bottom.set_ylabel("position [mm]")
    bottom.set_xlabel("time [s]")
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    return fig


def zone_load_step(runs: dict[str, Result]) -> Figure:
    """The unwind zone's tension after a 60 N step of the dancer's load, one run per use."""
    fig = framed_figure(9.0, 3.8)
    ax = fig.subplots()
    for k, (label, result) in enumerate(runs.items()):
        ax.plot(result.time, result.tension[:, 0], lw=1.0, color=f"C{k}", label=label)
    ax.axhline(150.0, color="k", ls="--", lw=0.8, label="tension reference 150 N")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("unwind_span tension [N]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return fig


def web_break(result: Result, until: float) -> Figure:
    """converter's web break: span tensions (top) and the driven rollers' surface speeds
    (bottom), through the stop ramp and the hold after it, up to ``until`` [s]."""
    fig = framed_figure(9.0, 5.4, rows=2)
    top, bottom = fig.subplots(2, 1, sharex=True)
    shown = result.time <= until + 1e-9
    t = result.time[shown]
    for k, name in enumerate(result.span_names):
        top.plot(t, result.tension[shown, k], lw=0.9, label=name)
    top.set_ylabel("tension [N]")
    for d, i in enumerate(result.line.drives):
        bottom.plot(t, result.surface_speed[shown, i], lw=0.9, color=f"C{d}",
                    label=result.node_names[i])
    bottom.set_ylabel("surface speed [m/s]")
    bottom.set_xlabel("time [s]")
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best", ncol=2)
    return fig


def roll_inertia(result: Result) -> Figure:
    """Each roll's total inertia at its shaft against its diameter over a whole roll, with
    its first and last values marked (the empty and full totals a drive is given)."""
    fig = framed_figure(7.0, 4.2)
    ax = fig.subplots()
    for k, i in enumerate((0, result.line.n_nodes - 1)):
        diameter, inertia = 2.0 * result.radius[:, i], result.inertia[:, k]
        ax.plot(diameter, inertia, lw=1.4, color=f"C{k}", label=result.node_names[i])
        ax.plot(diameter[[0, -1]], inertia[[0, -1]], "o", color=f"C{k}", ms=5)
    ax.set_xlabel("roll diameter [m]")
    ax.set_ylabel("inertia at the roll shaft [kg·m²]")
    ax.set_yscale("log")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return fig


def main() -> None:
    line = webline.load_line("converter")
    display = Display()
    figures: dict[str, Figure] = {}
    start = webline.simulate(line, scenario="startup")
    figures["guide-dancer-startup"] = dancer_startup(start)
    lift = 1e3 * np.abs(_position(start, "dancer") - 0.15).max()
    say("startup: dancer within", f"{lift:.3g} mm of its set position;", *(
        f"{start.span_names[k]} {start.tension[:, k].min():.4g}-{start.tension[:, k].max():.4g}"
        f" N, {start.tension[-1, k]:.4g} N at the end;" for k in (0, 1)))
    roll = webline.simulate(line, scenario="roll-change")
    rewind_zone = line.zones[line.controlled_zone(line.n_nodes - 1)].loadcell
    figures["guide-taper"] = taper_figure(roll, display, rewind_zone)
    at_speed = (roll.time > 30.0) & (roll.time < 3960.0)
    ref, measured = roll.tension_ref[at_speed, rewind_zone], roll.tension[at_speed, rewind_zone]
    say("roll-change: set tension", f"{ref[0]:.4g} -> {ref[-1]:.4g} N, measured within",
        f"{100 * np.abs(measured / ref - 1).max():.2g} % at speed")
    figures["guide-roll-inertia"] = roll_inertia(roll)
    for k, i in enumerate((0, line.n_nodes - 1)):
        say(f"roll-change: {roll.node_names[i]} J", f"{roll.inertia[0, k]:.4g} kg*m**2 at",
            f"{2 * roll.radius[0, i]:.3g} m -> {roll.inertia[-1, k]:.4g} at "
            f"{2 * roll.radius[-1, i]:.3g} m")
    noisy = {"disturbances": [{"type": "measurement_noise", "speed": 0.01, "seed": 1}],
             "rollers.rewind.diameter": {"method": "speed_ratio", "filter": "50 ms"}}
    calc = webline.simulate(line.replace(noisy), 8.0)
    figures["guide-diameter"] = diameter_figure(calc, display, [len(line.drives) - 1])
    error = 2.0 * (calc.control_radius[:, -1] - calc.radius[:, -1])
    say("noisy diameter: error mean", f"{1e3 * error.mean():.3g} mm, std",
        f"{1e3 * error.std():.3g} mm, largest {1e3 * np.abs(error).max():.3g} mm")
    steps = {
        "dancer as tension sensor, 2 kN/m": {"use": "tension", "stiffness": SPRING},
        "dancer as filter beside the loadcell, 2 kN/m": {"use": "none", "stiffness": SPRING},
        "dancer position control, air-loaded": {"use": "position", "stiffness": 0.0},
    }
    runs = {label: webline.simulate(line.replace({
        "rollers.dancer.dancer.use": change["use"],
        "rollers.dancer.dancer.stiffness": change["stiffness"],
        "rollers.dancer.dancer.load": LOAD_STEP}), 4.0) for label, change in steps.items()}
    figures["guide-zone-step"] = zone_load_step(runs)
    for label, run in runs.items():
        after = run.tension[run.time > 1.0, 0]
        say(f"load step, {label}: unwind_span", f"{after.min():.4g}-{after.max():.4g} N,",
            f"{run.tension[-1, 0]:.4g} N at 4 s")
    course = modes_across_roll(line)
    figures["guide-modes-across-roll"] = roll_modes_figure(course, display)
    least = course.least_damping()
    wn = [abs(v[j]) for v, j in zip(course.eigenvalues, course.least_damped(), strict=True)
          if j is not None]
    say("across the roll: least damped loop mode at", f"{min(wn):.4g}-{max(wn):.4g} rad/s,",
        f"zeta {np.nanmin(least):.3g}-{np.nanmax(least):.3g}; findings:",
        str([f.message for f in course.findings()]))
    broken = webline.simulate(line, scenario="web-break", raise_on_failure=False)
    figures["guide-web-break"] = web_break(broken, until=float(broken.time[-1]))
    for finding in broken.verdict.findings:
        say("web-break:", finding.message)
    held = broken.time >= 10.0  # the scenario's stop: break at 5 s, 5 s ramp
    say("web-break: largest driven surface speed after the stop",
        f"{np.abs(broken.surface_speed[held][:, line.drives]).max():.3g} m/s")
    spliced = webline.simulate(line, scenario="flying-splice")
    figures["guide-flying-splice"] = splice_figure(spliced, display)
    say("flying-splice:", splice_caption(spliced, display))
    IMG.mkdir(exist_ok=True)
    for name, fig in figures.items():
        path = IMG / f"{name}.png"
        fig.savefig(path, dpi=90)
        print(path)


def say(*words: str) -> None:
    """Print a number the guide quotes, computed from the run it describes."""
    print("  ", *words)


if __name__ == "__main__":
    main()
