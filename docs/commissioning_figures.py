"""Draw the figures of docs/commissioning.md: a fit of the built-in `converter` to a synthetic
recording (the page's example), measured against simulated before and after, and the
residuals.

    .venv/bin/python docs/commissioning_figures.py      # writes docs/img/commissioning-*.png

Uses the fit report's own figure functions (`webline.twin.figures`).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from webline.twin.figures import overlay_figure, residual_figure
from webline.twin.fit import fit
from webline.twin.synthetic import synthetic_csv

IMG = Path(__file__).resolve().parent / "img"
TRUTH = {"rollers.infeed.inertia": 0.7, "rollers.chill.inertia": 2.4,
         "rollers.drum.friction": 0.09, "web.modulus": "3.3 GPa",
         "rollers.dancer.dancer.damping": "700 N*s/m"}
FREE = {"rollers.infeed.inertia": "0.1 .. 2 kg*m**2", "rollers.chill.inertia": "0.5 .. 8 kg*m**2",
        "rollers.drum.friction": "0.005 .. 0.5 N*m*s", "web.modulus": "2 .. 6 GPa",
        "rollers.dancer.dancer.damping": "100 .. 3000 N*s/m"}
SHOWN = ["tension[process_span]", "tension[rewind_span]", "torque[infeed]", "torque[chill]"]


def main() -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = synthetic_csv(Path(folder) / "startup.csv", "converter", changes=TRUTH,
                             duration=10.0, scenario="startup", offset=3.7, seed=1)
        result = fit("converter", path, FREE, scenario="startup")
    measured = {n: result.data.signals[n][::result.data.stride] for n in SHOWN}
    overlay = overlay_figure(result.time, measured, result.after.values, SHOWN,
                             "converter start-up: measured, line file (dashed), fitted",
                             result.before.values)
    residuals = residual_figure(result.time, {n: result.residuals()[n] for n in SHOWN},
                                result.noise, "residuals after the fit (simulated - measured)")
    IMG.mkdir(exist_ok=True)
    overlay.savefig(IMG / "commissioning-fit.png", dpi=80)
    residuals.savefig(IMG / "commissioning-residuals.png", dpi=80)


if __name__ == "__main__":
    main()
