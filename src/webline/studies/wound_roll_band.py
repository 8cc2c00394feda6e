"""Study ``wound-roll-band``: what a transient in the line leaves in the roll (issue 38,
docs/wound-roll.md "In a run"). The built-in ``converter`` with the page's assumed roll table
(Pfeiffer K1 1.5 kPa, K2 120, a 3 GPa fibre core, hoop limit -0.2 MPa) is run twice:

1. a step of the rewind zone's set tension, 150 -> 200 N at 4 s and back at 6 s, during winding;
2. a speed change during winding, 300 -> 150 m/min in 2 s from 3 s (the rewind's inertia
   compensation and speed loop lag the deceleration: its zone swings by about a third).

For each run the wound roll is solved (``physics.roll_stress``, the layers' wound-on tension from
the simulated rewind tension and roll radius) and its ``roll_band`` findings are compared with
the run itself: the band's radius must lie within the radius the simulated rewind roll had
while the transient lasted (its set tension, or its loadcell tension, more than the roll
table's ``band`` off the steady value). Figures: pressure and hoop stress against radius with
the roll's cross-section, per run. Table: per band, its radius, the times it was wound, the
radius the run wound during the transient, and whether the first lies within the second.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

import webline
from webline.line import load_line
from webline.model.web_graph import BranchedLine
from webline.report.plots.wound_roll import wound_roll_figure
from webline.studies.output import finish, save
from webline.studies.result import StudyResult

#: docs/wound-roll.md's roll table (every value assumed and explained there)
ROLL = {
    "k1": "1.5 kPa",
    "k2": 120,
    "core": {"modulus": "3 GPa", "inner_radius": "76 mm"},
    "min_hoop": "-0.2 MPa",
    "max_pressure": "1 MPa",
    "core_rating": "2 MPa",
}
STEP = {
    "type": "steps",
    "initial": "150 N",
    "steps": [{"time": "4 s", "value": "200 N"}, {"time": "6 s", "value": "150 N"}],
}

#: the laminator's laminate (film 23 um + foil 9 um, wound as one web of 32 um, its in-plane
#: modulus the layers' EA over that section: 22.9 GPa) with the same stack law: no published
#: K1, K2 for a film-foil laminate was found, so the film's are assumed; a 3 in core of 6 mm
#: wall (inner radius 70 mm under the rewind's 76.2 mm)
LAMINATE_ROLL = {**ROLL, "core": {"modulus": "3 GPa", "inner_radius": "70 mm"}}
LAMINATE_STEP = {
    "type": "steps",
    "initial": "180 N",
    "steps": [{"time": "4 s", "value": "240 N"}, {"time": "6 s", "value": "180 N"}],
}
LAMINATOR_RUN = "laminator: laminate step 180-240-180 N"

SLOW_DOWN = {"type": "ramp", "initial": "300 m/min", "final": "150 m/min", "start": "3 s",
             "duration": "2 s"}


def _records(result: Any) -> tuple[np.ndarray, np.ndarray, Any]:
    """The rewound roll's records: (tension entering it [N], its radius [m], its
    ``WoundRoll``), of a single-path run (its rewind) or a branched one (its first roll with
    a ``roll_stress`` table, from the span entering it)."""
    roll, line = result.wound_roll, result.line
    if not isinstance(line, BranchedLine):  # a single-path line: the last span, the rewind
        return result.tension[:, -1], result.radius[:, -1], roll
    j = result.roll_names.index(roll.where)
    return (result.tension[:, line.web_spans(line.rolls[j].web)[-1]],
            result.roll_radius[:, j], roll)


def _transient_radii(time: np.ndarray, tension: np.ndarray, radius: np.ndarray,
                     share: float) -> tuple[float, float, float, float]:
    """(first, last time [s], smallest, largest radius [m]) of the roll while the tension
    entering it is more than ``share`` off its median (the run's transient)."""
    steady = float(np.median(tension))
    off = np.abs(tension / steady - 1.0) > share
    off[time < 0.5] = False  # (the first half second is the run's own start)
    if not off.any():
        return (np.nan, np.nan, np.nan, np.nan)
    return (float(time[off].min()), float(time[off].max()), float(radius[off].min()),
            float(radius[off].max()))


def _rows(name: str, result: Any, share: float) -> list[dict[str, object]]:
    tension, radius, roll = _records(result)
    t0, t1, r_lo, r_hi = _transient_radii(result.time, tension, radius, share)
    thickness = roll.stress.thickness

    def inside(r0: float, r1: float) -> bool:  # to one layer below, two above (the top one)
        return bool(r_lo - thickness <= r0 and r1 <= r_hi + 2 * thickness)

    rows: list[dict[str, object]] = []
    for f in roll.findings():
        if f.kind != "roll_band":
            continue
        b0, b1 = f.details["radius_m"]
        peak = f.details["peak_radius_m"]
        rows.append({
            "run": name,
            "band": "hard" if f.details["hoop_departure"] > 0 else "soft",
            "band_from_mm": 1e3 * b0, "band_to_mm": 1e3 * b1, "peak_mm": 1e3 * peak,
            "wound_from_s": f.details["time_s"][0], "wound_to_s": f.details["time_s"][1],
            "hoop_departure_pct": 100 * f.details["hoop_departure"],
            "transient_from_s": t0, "transient_to_s": t1,
            "transient_radius_from_mm": 1e3 * r_lo, "transient_radius_to_mm": 1e3 * r_hi,
            "band_inside_transient": inside(b0, b1),
            "peak_inside_transient": inside(peak, peak),
        })
    if not rows:
        rows.append({"run": name, "band": "none", "transient_from_s": t0, "transient_to_s": t1,
                     "transient_radius_from_mm": 1e3 * r_lo,
                     "transient_radius_to_mm": 1e3 * r_hi, "band_inside_transient": False,
                     "peak_inside_transient": False})
    return rows


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Run the two cases; write the roll figures, ``table.csv`` and ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    base = load_line("converter").replace({"rollers.rewind.roll_stress": ROLL})
    table: Any = getattr(base.spec.rollers[base.n_nodes - 1], "roll_stress", None)
    share = float(table.band)  # the table's band (5 % by default)
    step: Any = webline.simulate(base.replace({"spans.rewind_span.tension": STEP}),
                            8.0 if quick else 10.0)
    slower: Any = webline.simulate(base.replace({"speed": SLOW_DOWN}), 8.0)
    laminate: Any = webline.simulate(webline.load_line("laminator").replace(
        {"rollers.rewind.roll_stress": LAMINATE_ROLL,
         "webs.laminate.spans.laminate_zone.tension": LAMINATE_STEP}), 8.0)
    rows = _rows("tension step 150-200-150 N", step, share)
    rows += _rows("speed change 300-150 m/min", slower, share)
    rows += _rows(LAMINATOR_RUN, laminate, share)
    figures = [save(wound_roll_figure(step.wound_roll), out_dir / "roll_tension_step.png"),
               save(wound_roll_figure(slower.wound_roll), out_dir / "roll_speed_change.png"),
               save(wound_roll_figure(laminate.wound_roll), out_dir / "roll_laminator_step.png")]
    lines = ["wound-roll-band: transients of the converter and the laminator as bands "
             "in their rewind rolls"]
    for row in rows:
        if row["band"] == "none":
            lines.append(f"{row['run']}: no band beyond the table's {100 * share:.3g} % "
                         f"(transient at t = {row['transient_from_s']:.4g}-"
                         f"{row['transient_to_s']:.4g} s)")
            continue
        where = ("inside" if row["band_inside_transient"] else
                 "peak inside" if row["peak_inside_transient"] else "OUTSIDE")
        lines.append(
            f"{row['run']}: a {row['band']} band at r = {row['band_from_mm']:.5g}-"
            f"{row['band_to_mm']:.5g} mm (hoop {row['hoop_departure_pct']:+.3g} % of the "
            f"wound-on stress, most at {row['peak_mm']:.5g} mm), wound at t = "
            f"{row['wound_from_s']:.4g}-{row['wound_to_s']:.4g} s: "
            f"{where} the radius the roll had during the transient "
            f"({row['transient_radius_from_mm']:.5g}-{row['transient_radius_to_mm']:.5g} mm, "
            f"t = {row['transient_from_s']:.4g}-{row['transient_to_s']:.4g} s)")
    return finish("wound-roll-band", out_dir, figures, rows, "\n".join(lines))
