"""Draw the figures of docs/wound-roll.md from runs of the built-in converter, and print every
number the page quotes.

    .venv/bin/python docs/wound_roll_figures.py      # writes docs/img/wound-roll-*.png
    .venv/bin/python docs/wound_roll_figures.py slitter    # one part of it only

1. The commissioning task: a taper for a 600 mm roll of 25 µm film (``design_taper``), the
   untapered roll for comparison, and the roll of a run with the chosen taper.
2. A tension step during winding (the study of the page's "In a run"): the band it leaves.
3. The converter's flying-splice scenario: what of its transients reaches the roll.
4. The slitter (a branched line): each lane's roll, snapshots during winding, and the shaft's
   taper designed for one lane.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import webline
from webline.analysis.roll_taper import design_roll, design_taper, with_taper
from webline.report.plots.wound_roll import wound_roll_figure
from webline.studies.wound_roll_band import ROLL, STEP  # the page's roll table and step

IMG = Path(__file__).resolve().parent / "img"


def _mpa(x: float) -> str:
    return f"{x / 1e6:.3g} MPa"


def commissioning() -> None:
    line = webline.load_line("converter").replace(
        {"web.thickness": "25 um", "rollers.rewind.roll_stress": ROLL}
    )
    design = design_roll(line, 0.6)
    for form in ("linear", "hyperbolic"):
        r = design.roll(form, 0.0)
        print(
            f"no taper: min hoop {_mpa(r.hoop.min())} at r = {1e3 * r.radius[r.hoop.argmin()]:.4g}"
            f" mm, {int((r.hoop < -0.2e6).sum())} layers below -0.2 MPa, max pressure "
            f"{_mpa(r.pressure.max())}, core {_mpa(r.core_pressure)}"
        )
        break
    choices = design_taper(line, diameter=0.6)
    for c in choices:
        print(
            f"{c.form}: taper {c.taper:.3f}, mean wound-on {_mpa(c.mean_stress)}, "
            f"below it: {c.below}"
        )
    tapered = with_taper(line, choices[0], 0.6)
    result = webline.simulate(tapered, 5.0)
    roll = result.wound_roll
    s = roll.stress
    print(
        f"run with {choices[0].form} {choices[0].taper:.3f}: min hoop {_mpa(s.hoop.min())}, "
        f"max pressure {_mpa(s.pressure.max())}, core {_mpa(s.core_pressure)}; findings: "
        f"{[f.kind for f in result.verdict.findings]}"
    )
    wound_roll_figure(roll).savefig(IMG / "wound-roll-taper.png", dpi=90)


def step_band() -> None:
    line = webline.load_line("converter").replace(
        {"rollers.rewind.roll_stress": ROLL, "spans.rewind_span.tension": STEP}
    )
    result = webline.simulate(line, 10.0)
    for f in result.verdict.findings:
        if f.kind == "roll_band":
            print("step:", f.message)
    print(f"step: peak rewind tension {result.tension[:, -1].max():.4g} N")
    wound_roll_figure(result.wound_roll).savefig(IMG / "wound-roll-step.png", dpi=90)


def flying_splice() -> None:
    line = webline.load_line("converter").replace({"rollers.rewind.roll_stress": ROLL})
    result = webline.simulate(line, scenario="flying-splice")
    t, ten = result.time, result.tension[:, -1]
    near = (t > 3.5) & (t < 6.0)
    ref = float(np.median(ten[near]))
    print(
        f"flying splice: rewind tension {ten[near].min():.4g}-{ten[near].max():.4g} N around "
        f"the unwind splice at 4 s ({100 * (ten[near].max() - ten[near].min()) / ref:.2g} % "
        f"of {ref:.4g} N); start: {ten[(t > 0.2) & (t < 1.0)].min():.4g} N at t ~ 0.5 s"
    )
    for f in result.verdict.findings:
        if f.kind.startswith("roll_"):
            print("flying splice:", f.message)


def slitter() -> None:
    table = {"k1": "5 kPa", "k2": 100, "diameter": "0.3 m"}
    line = webline.load_line("slitter").replace({
        "rollers.rewind_shaft.roll_stress": {**table, "at_radii": ["85 mm", "0.12 m"]},
        "rollers.rewind_3.roll_stress": table,
        "webs.lane_3.spans.lane_3_span.tension": "150 N",
    })
    result = webline.simulate(line, 2.0)
    for name, roll in result.wound_rolls.items():
        s = roll.stress
        print(f"slitter {name}: {len(s.radius)} layers, core {_mpa(s.core_pressure)}, min hoop "
              f"{_mpa(s.hoop.min())} at r = {1e3 * s.radius[s.hoop.argmin()]:.4g} mm")
        for snap in roll.snapshots:
            print(f"  at r = {1e3 * snap.radius:.4g} mm: {len(snap.stress.radius)} layers, core "
                  f"{_mpa(snap.stress.core_pressure)}")
    wound_roll_figure(result.wound_rolls["rewind_shaft/lane_1"]).savefig(
        IMG / "wound-roll-slitter.png", dpi=90)
    shaft = webline.load_line("slitter").replace({"rollers.rewind_shaft.roll_stress": {
        "k1": "1.5 kPa", "k2": 120, "core": {"modulus": "3 GPa", "inner_radius": "70 mm"},
        "min_hoop": "-0.4 MPa", "diameter": "0.4 m"}})
    lane = "rewind_shaft/lane_1"
    best = design_taper(shaft, roll=lane)[0]
    for less in (0.0, 0.05):
        tapered = with_taper(shaft, best, roll=lane)
        node = tapered.node_index["rewind_shaft"]  # type: ignore[union-attr]
        tapered = tapered.replace({"rollers.rewind_shaft.taper.taper":
                                   tapered.spec.rollers[node].taper.taper - less})
        roll = webline.simulate(tapered, 2.0).wound_rolls[lane]
        print(f"slitter shaft taper {best.form} {best.taper:.3f} - {less}: min hoop "
              f"{_mpa(roll.stress.hoop.min())}")


if __name__ == "__main__":
    IMG.mkdir(exist_ok=True)
    parts = {"commissioning": commissioning, "step": step_band, "splice": flying_splice,
             "slitter": slitter}
    for part in sys.argv[1:] or parts:
        parts[part]()
