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

SLOW_DOWN = {"type": "ramp", "initial": "300 m/min", "final": "150 m/min", "start": "3 s",
             "duration": "2 s"}


def _transient_radii(result: Any, rewind: int, share: float) -> tuple[float, float, float, float]:
    """(first, last time [s], smallest, largest radius [m]) of the rewind roll while its
    zone's tension is more than ``share`` off its median (the run's transient)."""
    tension = result.tension[:, -1]
    steady = float(np.median(tension))
    off = np.abs(tension / steady - 1.0) > share
    off[result.time < 0.5] = False  # (the first half second is the run's own start)
    if not off.any():
        return (np.nan, np.nan, np.nan, np.nan)
    t = result.time[off]
    r = result.radius[off, rewind]
    return float(t.min()), float(t.max()), float(r.min()), float(r.max())


def _rows(name: str, result: Any, rewind: int, share: float) -> list[dict[str, object]]:
    t0, t1, r_lo, r_hi = _transient_radii(result, rewind, share)
    thickness = result.wound_roll.stress.thickness
    rows: list[dict[str, object]] = []
    for f in result.verdict.findings:
        if f.kind != "roll_band":
            continue
        b0, b1 = f.details["radius_m"]
        rows.append({
            "run": name,
            "band": "hard" if f.details["hoop_departure"] > 0 else "soft",
            "band_from_mm": 1e3 * b0, "band_to_mm": 1e3 * b1,
            "wound_from_s": f.details["time_s"][0], "wound_to_s": f.details["time_s"][1],
            "hoop_departure_pct": 100 * f.details["hoop_departure"],
            "transient_from_s": t0, "transient_to_s": t1,
            "transient_radius_from_mm": 1e3 * r_lo, "transient_radius_to_mm": 1e3 * r_hi,
            # within the radius wound while the transient lasted, to one layer each side
            "band_inside_transient": bool(r_lo - thickness <= b0 and b1 <= r_hi + 2 * thickness),
        })
    if not rows:
        rows.append({"run": name, "band": "none", "transient_from_s": t0, "transient_to_s": t1,
                     "transient_radius_from_mm": 1e3 * r_lo,
                     "transient_radius_to_mm": 1e3 * r_hi, "band_inside_transient": False})
    return rows


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Run the two cases; write the roll figures, ``table.csv`` and ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    base = load_line("converter").replace({"rollers.rewind.roll_stress": ROLL})
    rewind = base.n_nodes - 1
    table: Any = getattr(base.spec.rollers[rewind], "roll_stress", None)
    share = float(table.band)  # the table's band (5 % by default)
    step: Any = webline.simulate(base.replace({"spans.rewind_span.tension": STEP}),
                            8.0 if quick else 10.0)
    slower: Any = webline.simulate(base.replace({"speed": SLOW_DOWN}), 8.0)
    rows = _rows("tension step 150-200-150 N", step, rewind, share)
    rows += _rows("speed change 300-150 m/min", slower, rewind, share)
    figures = [save(wound_roll_figure(step.wound_roll), out_dir / "roll_tension_step.png"),
               save(wound_roll_figure(slower.wound_roll), out_dir / "roll_speed_change.png")]
    lines = ["wound-roll-band: transients of the converter as bands in its rewind roll"]
    for row in rows:
        if row["band"] == "none":
            lines.append(f"{row['run']}: no band beyond the table's {100 * share:.3g} % "
                         f"(transient at t = {row['transient_from_s']:.4g}-"
                         f"{row['transient_to_s']:.4g} s)")
            continue
        where = "inside" if row["band_inside_transient"] else "OUTSIDE"
        lines.append(
            f"{row['run']}: a {row['band']} band at r = {row['band_from_mm']:.5g}-"
            f"{row['band_to_mm']:.5g} mm (hoop {row['hoop_departure_pct']:+.3g} % of the "
            f"wound-on stress), wound at t = {row['wound_from_s']:.4g}-{row['wound_to_s']:.4g} s: "
            f"{where} the radius the roll had during the transient "
            f"({row['transient_radius_from_mm']:.5g}-{row['transient_radius_to_mm']:.5g} mm, "
            f"t = {row['transient_from_s']:.4g}-{row['transient_to_s']:.4g} s)")
    return finish("wound-roll-band", out_dir, figures, rows, "\n".join(lines))
