"""robustness: Monte Carlo of the PI, state-feedback and adaptive controllers on the HSWL
under parameter uncertainty (the thesis's future work): EA ±10 %, bearing friction ±50 %,
inertias ±20 % (uniform) and loadcell noise; the distribution of the RMS tension error and
the probability of instability (verdict unstable or failed) per controller.

Every controller sees the same drawn lines (one seed: common random numbers), so their
differences are the controllers', not the draws'.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import webline
from webline.control.select import FAMILIES, with_controller
from webline.line import load_line
from webline.sim.sweeps.distributions import proportion_interval
from webline.studies.output import finish, pyplot, save
from webline.studies.result import StudyResult

SEED = 2026
#: loadcell noise: standard deviation of the tension measurement, drawn per case
NOISE = "uniform(0 lbf, 0.5 lbf)"
ROLLERS = ("unwind", "master", "process", "idler", "rewind")


def uncertainty(line: webline.Line) -> dict[str, str]:
    """{path: distribution}: EA ±10 %, each roller's friction ±50 % and inertia ±20 %, the
    loadcell noise (the last disturbance of ``line``)."""
    spec = line.spec
    dists = {"web.ea": f"uniform({spec.web.ea!r} N, 10 %)"}
    for roller in spec.rollers:
        if roller.name in ROLLERS:
            dists[f"rollers.{roller.name}.friction"] = f"uniform({roller.friction!r}, 50 %)"
            if isinstance(roller.inertia, float):  # (not a roll's totals table)
                dists[f"rollers.{roller.name}.inertia"] = f"uniform({roller.inertia!r}, 20 %)"
    dists[f"disturbances[{len(spec.disturbances) - 1}].tension"] = NOISE
    return dists


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Monte Carlo per controller family; ``table.csv``, a histogram and ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    n, duration = (8, 1.0) if quick else (200, 10.0)
    base = load_line("hswl").with_scenario("speed-change")
    base = base.replace(disturbances=[*[d.model_dump(exclude_none=True)
                                        for d in base.spec.disturbances],
                                      {"type": "measurement_noise", "tension": 0.0,
                                       "seed": 1}])
    rows: list[dict[str, object]] = []
    errors = {}
    for family in FAMILIES:
        line = with_controller(base, family)
        ds = webline.monte_carlo(line, uncertainty(line), n, seed=SEED, duration=duration)
        loadcell = np.isfinite(ds.tension_rms_error.values).any(axis=0)
        worst = ds.tension_rms_error.values[:, loadcell].max(axis=1)
        bad = np.isin(ds.status.values.astype(str), ("unstable", "failed"))
        k = int(bad.sum())
        low, high = proportion_interval(k, n)
        finite = worst[np.isfinite(worst) & ~bad]
        errors[family] = finite
        rows.append({
            "controller": family, "cases": n, "unstable_or_failed": k,
            "p_unstable_or_failed": k / n, "p_95_low": low, "p_95_high": high,
            "rms_error_median_N": float(np.median(finite)) if finite.size else math.nan,
            "rms_error_p90_N": float(np.quantile(finite, 0.9)) if finite.size else math.nan,
            "rms_error_max_N": float(finite.max()) if finite.size else math.nan,
        })
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 3.5))
    for family, values in errors.items():
        if values.size:
            ax.hist(values, bins=20, alpha=0.5, label=family)
    ax.set_xlabel("largest RMS tension error over the loadcell spans [N]")
    ax.set_ylabel("cases")
    ax.legend()
    figures = [save(fig, out_dir / "rms_error_histogram.png")]
    summary = (f"robustness: {n} lines per controller drawn from EA ±10 %, friction ±50 %, "
               f"inertias ±20 %, loadcell noise {NOISE} (seed {SEED}), {duration:g} s of the "
               "speed-change scenario\n" + "\n".join(
                   f"{r['controller']}: P(unstable or failed) = {r['p_unstable_or_failed']:.1%} "
                   f"({r['unstable_or_failed']} of {r['cases']}; 95 % interval "
                   f"{r['p_95_low']:.1%} to {r['p_95_high']:.1%}), RMS tension error median "
                   f"{r['rms_error_median_N']:.3g} N, 90 % below {r['rms_error_p90_N']:.3g} N"
                   for r in rows))
    return finish("robustness", out_dir, figures, rows, summary)
