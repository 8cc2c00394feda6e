"""Study ``ecp-backlash``: the ECP rectilinear backlash experiment of thesis Sec. 3.5 and
Appendix B (Figs 3.17-3.19): deviation of the load (mass 2) velocity due to backlash against the
bounds, for gaps of 1.55, 3.56 and 5.38 mm.

Plant, gaps, reference and PI: data file ``ecp_rectilinear_sec3_5.toml`` (every assumed value is
listed there); run length in ``ecp_backlash_sec3_5.toml``. For each gap the PI loop on the
velocity of mass 1 is simulated from rest with and without backlash
(``backlash_bounds.simulate_loop``) and the deviation e(t) = vL,with - vL,without is compared
with, at every instant t:

* the valid bound  φmax ∫_0^t |c e^{Aσ} D| dσ  (the L1 norm of the impulse response up to t,
  which holds for any sign pattern of the backlash deviation φ);
* the printed bound (3.57), φmax |c ∫_0^t e^{Aσ} D dσ|, which is *not* a bound in general
  (E-3.3): shown dashed, with its peak over time.

The experimental traces of the thesis are not in the text, so only the model side is shown.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.linalg import expm

from webline.analysis.drivetrain import backlash_bounds as bb
from webline.analysis.drivetrain import equivalent
from webline.analysis.drivetrain.params import (
    BeltDrive,
    SpeedPI,
    ecp_rectilinear_plant,
    load_parameter_set,
)
from webline.studies.output import finish, pyplot, save
from webline.studies.result import StudyResult

GAPS = ("fig3_17", "fig3_18", "fig3_19")


def speed_pi() -> SpeedPI:
    """The PI of the data file, placed by (2.4)-(2.5) on the rigid pair of masses."""
    data = load_parameter_set("ecp_rectilinear_sec3_5")
    plant = ecp_rectilinear_plant(GAPS[0])
    rigid = BeltDrive(plant.j_motor, plant.j_load, plant.b_motor, plant.b_load, 1.0, 1.0,
                      plant.stiffness)
    return equivalent.pi_motor_side(rigid, data["speed_loop"]["bandwidth"],
                                    data["speed_loop"]["damping"])


def bounds_over_time(loop: bb.BacklashLoop, t: np.ndarray,
                     refine: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """(valid L1 bound, printed (3.57)) on the load speed at every time of the uniform grid
    ``t`` [s] from 0, with the kernel h(σ) = c e^{Aσ} D on a grid ``refine`` times finer."""
    dt = (t[1] - t[0]) / refine
    n = (t.size - 1) * refine + 1
    step = expm(loop.a * dt)
    x = loop.d.astype(float)
    h = np.empty(n)
    for i in range(n):
        h[i] = loop.load_speed @ x
        x = step @ x
    sigma = np.arange(n) * dt
    valid = loop.phi_max * cumulative_trapezoid(np.abs(h), sigma, initial=0.0)
    printed = loop.phi_max * np.abs(cumulative_trapezoid(h, sigma, initial=0.0))
    return valid[::refine], printed[::refine]


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Simulate each gap; write one figure per gap (Figs 3.17-3.19), ``table.csv`` and
    ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    data = load_parameter_set("ecp_rectilinear_sec3_5")
    p = load_parameter_set("ecp_backlash_sec3_5")["run"]
    duration = p["quick_duration"] if quick else p["duration"]
    t = np.arange(round(duration / p["time_step"]) + 1) * p["time_step"]
    gains = speed_pi()
    w = 2 * math.pi * data["reference"]["frequency"]
    amplitude = w * data["reference"]["position_amplitude"]

    def reference(time: float) -> float:
        return amplitude * math.sin(w * time)

    plt = pyplot()
    figures, rows = [], []
    for gap in GAPS:
        plant = ecp_rectilinear_plant(gap)
        with_bl = bb.simulate_loop(plant, gains, reference, t)
        without = bb.simulate_loop(plant, gains, reference, t, backlash=False)
        deviation = with_bl[:, 3] - without[:, 3]
        loop = bb.backlash_loop(plant, gains, "reduced")
        valid, printed = bounds_over_time(loop, t)
        l1_inf = bb.l1_bound(loop, output=loop.load_speed)
        printed_peak = bb.printed_bound_peak(loop, output=loop.load_speed)
        eigen = bb.eigen_bound(loop, output=loop.load_speed)
        ratio = np.abs(deviation[1:]) / valid[1:]
        clearance_mm = 2e3 * plant.gap_pos
        fig, ax = plt.subplots(figsize=(7, 3.5))
        ax.plot(t, deviation * 1e3, label="simulated deviation of the load velocity")
        ax.plot(t, valid * 1e3, "k-", lw=1, label="valid bound (L1, up to t)")
        ax.plot(t, -valid * 1e3, "k-", lw=1)
        ax.plot(t, printed * 1e3, "r--", lw=1, label="printed (3.57), not a bound")
        ax.set(xlabel="time [s]", ylabel="deviation [mm/s]",
               title=f"{gap.replace('fig', 'Fig. ').replace('_', '.')}: backlash "
                     f"{clearance_mm:.2f} mm")
        ax.legend(fontsize=7, loc="lower right")
        figures.append(save(fig, out_dir / f"{gap}_deviation.png"))
        rows.append({
            "figure": gap, "clearance_mm": clearance_mm, "half_gap_mm": plant.gap_pos * 1e3,
            "phi_max_N": loop.phi_max,
            "max_deviation_mm_s": float(np.abs(deviation).max() * 1e3),
            "valid_bound_at_end_mm_s": float(valid[-1] * 1e3),
            "valid_bound_t_inf_mm_s": l1_inf * 1e3,
            "printed_bound_3_57_peak_mm_s": printed_peak * 1e3,
            "eigen_bound_3_62_mm_s": eigen * 1e3,
            "max_deviation_over_valid_bound": float(ratio.max()),
            "within_valid_bound_every_instant": bool(np.all(np.abs(deviation) <= valid)),
            "exceeds_printed_bound": bool(np.abs(deviation).max() > printed_peak),
        })
    summary = "ecp-backlash (thesis Sec. 3.5, App. B, Figs 3.17-3.19)\n" + "\n".join(
        f"{r['clearance_mm']:.2f} mm: max |deviation| {r['max_deviation_mm_s']:.2f} mm/s; valid "
        f"bound {r['valid_bound_at_end_mm_s']:.2f} mm/s at the end "
        f"({r['valid_bound_t_inf_mm_s']:.2f} as t->inf), within it at every instant: "
        f"{r['within_valid_bound_every_instant']} "
        f"(largest ratio {r['max_deviation_over_valid_bound']:.3f}); printed (3.57) peak "
        f"{r['printed_bound_3_57_peak_mm_s']:.2f} mm/s, exceeded: {r['exceeds_printed_bound']}; "
        f"eigenvalue bound {r['eigen_bound_3_62_mm_s']:.1f} mm/s" for r in rows)
    return finish("ecp-backlash", out_dir, figures, rows, summary)
