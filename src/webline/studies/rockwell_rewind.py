"""Study ``rockwell-rewind``: the rewind experiments of thesis Sec. 4.3 on the built-in
``rockwell`` line (Figs 4.14-4.30), with the values of ``rockwell_rewind_sec4_3.toml`` (every
assumed value is listed there and in the line file).

Part 1 (Figs 4.14-4.20): mean and standard deviation of the rewind-span tension and of the
rewind's web speed with and without 0.5 mm backlash, with and without the eccentric roller.
Part 2 (Figs 4.21-4.25, 4.27-4.30): amplitude at the disturbance frequency of the tension and of
the rewind speed for a 6 FPM, 0.5-2 Hz sinusoid in the pull roll's speed reference, without
backlash, with 1.5 mm backlash, and with 1.5 mm backlash and a 10 or 14 lbf ft brake;
amplification = amplitude / amplitude without backlash. For every run: the fraction of time the
backlash is open (contact 0) and the number of flank changes (+1 <-> -1), and the range of the
motor torque (the transmitted torque changes sign only if the gap can open).
Part 3 (``studies/rockwell_gap.py``): when the gap opens. It opens when the spring torque
τ = R T + b_L ω_L + J_L dω_L/dt + τ_b through the rewind's belt and gear reaches zero: a
ripple of amplitude a at f opens it iff a > a*(f) = τ̄/|G_τ(j2πf)| with τ̄ = R T_r + b_L V/R +
τ_b (the web slackens iff a > T_r/|G_T(j2πf)|), a slow-down iff its deceleration exceeds
d* = τ̄/σ (quasi-statically R τ̄/J_L). Runs on both sides of d*, with the 6 FPM ripple and with
brakes; gap-open share, mean shift, amplification and the (4.9)-(4.10) prediction; the L1
bound of (4.8) on the tension any motion in the gap can add. Derivation and numbers:
docs/drivetrain.md, "When the gap opens". The summary ends with the thesis's numbers beside
webline's and a verdict for each (``rockwell_claims``).
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import numpy as np

import webline
from webline.analysis.drivetrain.params import load_parameter_set
from webline.line import load_line
from webline.sim.results.result import Result
from webline.studies import rockwell_gap
from webline.studies.output import finish, pyplot, save
from webline.studies.result import StudyResult
from webline.studies.rockwell_claims import claims

FPM = 0.00508  # m/s per ft/min
LBF = 4.4482216152605  # N per lbf
ECCENTRIC, PULL_ROLL = "eccentric", "pull_roll"  #: roller names in the rockwell line


def params() -> dict[str, Any]:
    return load_parameter_set("rockwell_rewind_sec4_3")


def half_gap(clearance: float, p: dict[str, Any]) -> float:
    """Δ [rad at the rewind shaft] for a total ``clearance`` [m] at the sprocket."""
    return 0.5 * clearance / p["backlash_clearance"]["sprocket_radius"]


def case_line(speed_fpm: float, *, gap: float = 0.0, brake: float = 0.0,
              disturbances: list[dict[str, object]] | None = None) -> webline.Line:
    """The ``rockwell`` line at ``speed_fpm`` with backlash Δ = ``gap`` [rad], a ``brake``
    [N·m] on the rewind shaft and the given disturbance tables."""
    data = copy.deepcopy(load_line("rockwell").spec.model_dump(exclude_none=True))
    data["speed"] = speed_fpm * FPM
    drive = data["rollers"][-1]["drive"]
    if gap > 0:
        drive["transmission"]["backlash"] = {"gap": gap}
    if brake > 0:
        drive["brake"] = brake
    data["disturbances"] = disturbances or []
    return load_line(data)


def _amplitude(t: np.ndarray, y: np.ndarray, f: float) -> float:
    w = 2 * np.pi * f
    return float(2 * np.hypot(np.mean(y * np.cos(w * t)), np.mean(y * np.sin(w * t))))


def _contact_stats(result: Result, window: np.ndarray) -> dict[str, object]:
    c = result.contact[window, -1]  # NaN without backlash
    flank = c[np.isfinite(c) & (c != 0)]
    torque = result.torque[window, -1]
    return {
        "gap_open_fraction": float(np.mean(c == 0)),
        "flank_changes": int(np.count_nonzero(np.diff(flank) != 0)),
        "contact_values": " ".join(str(int(v)) for v in np.unique(c[np.isfinite(c)])) or "none",
        "motor_torque_min_N_m": float(torque.min()),
        "motor_torque_max_N_m": float(torque.max()),
    }


def mean_tension_rows(p: dict[str, Any], speeds: list[float], duration: float,
                      window_s: float) -> list[dict[str, object]]:
    """Part 1: four cases per speed."""
    rows = []
    ecc = [{"type": "eccentric_roller", "roller": ECCENTRIC, **p["eccentric"]}]
    gap = half_gap(p["backlash_clearance"]["mean_tension"], p)
    for fpm in speeds:
        for backlash in (False, True):
            for disturbed in (False, True):
                line = case_line(fpm, gap=gap if backlash else 0.0,
                                 disturbances=ecc if disturbed else None)
                r = webline.simulate(line, duration)
                w = r.time >= duration - window_s
                tension, speed = r.tension[w, -1], r.speed[w, -1]
                rows.append({"part": "mean_tension", "speed_fpm": fpm,
                             "backlash_mm": 1e3 * p["backlash_clearance"]["mean_tension"]
                             if backlash else 0.0, "disturbance": "eccentric" if disturbed
                             else "none", "tension_mean_lbf": float(tension.mean() / LBF),
                             "tension_std_lbf": float(tension.std() / LBF),
                             "speed_mean_fpm": float(speed.mean() / FPM),
                             "speed_std_fpm": float(speed.std() / FPM),
                             **_contact_stats(r, w)})
    return rows


def amplification_rows(p: dict[str, Any], speeds: list[float], freqs: list[float],
                       duration: float, window_s: float) -> list[dict[str, object]]:
    """Part 2: no backlash, 1.5 mm, 1.5 mm + each brake, per speed and frequency."""
    gap = half_gap(p["backlash_clearance"]["amplification"], p)
    cases = (("no backlash", 0.0, 0.0), ("backlash", gap, 0.0),
             ("backlash + 10 lbf ft brake", gap, p["brake"]["low"]),
             ("backlash + 14 lbf ft brake", gap, p["brake"]["high"]))
    rows = []
    for fpm in speeds:
        for f in freqs:
            ripple = [{"type": "speed_ripple", "roller": PULL_ROLL, **p["ripple"], "frequency": f}]
            base_t = base_v = 0.0
            for label, g, brake in cases:
                r = webline.simulate(case_line(fpm, gap=g, brake=brake, disturbances=ripple),
                                     duration)
                w = r.time >= duration - window_s
                t = r.time[w]
                amp_t = _amplitude(t, r.tension[w, -1] - r.tension[w, -1].mean(), f)
                amp_v = _amplitude(t, r.speed[w, -1] - r.speed[w, -1].mean(), f)
                if label == "no backlash":
                    base_t, base_v = amp_t, amp_v
                rows.append({"part": "amplification", "speed_fpm": fpm, "frequency_Hz": f,
                             "case": label, "brake_N_m": brake,
                             "tension_amplitude_lbf": amp_t / LBF,
                             "speed_amplitude_fpm": amp_v / FPM,
                             "tension_amplification": amp_t / base_t,
                             "speed_amplification": amp_v / base_v,
                             **_contact_stats(r, w)})
    return rows


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Run both parts; write the figures, ``table.csv`` and ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    p = params()
    g, r = p["grid"], p["run"]
    speeds = g["quick_speeds_fpm"] if quick else g["speeds_fpm"]
    freqs = g["quick_frequencies_hz"] if quick else g["frequencies_hz"]
    duration = r["quick_duration"] if quick else r["duration"]
    window = r["quick_window"] if quick else r["window"]
    part1 = mean_tension_rows(p, speeds, duration, window)
    part2 = amplification_rows(p, speeds, freqs, duration, window)
    plt = pyplot()
    figures = []
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.5))
    for backlash in (0.0, 1e3 * p["backlash_clearance"]["mean_tension"]):
        for dist in ("none", "eccentric"):
            sel = [x for x in part1 if x["backlash_mm"] == backlash and x["disturbance"] == dist]
            label = f"backlash {backlash:g} mm, {dist}"
            axes[0].plot([x["speed_fpm"] for x in sel], [x["tension_mean_lbf"] for x in sel],
                         "o-", label=label)
            axes[1].plot([x["speed_fpm"] for x in sel], [x["tension_std_lbf"] for x in sel],
                         "o-", label=label)
    axes[0].set(xlabel="speed [FPM]", ylabel="mean tension [lbf]",
                title="Figs 4.14-4.18: mean tension")
    axes[1].set(xlabel="speed [FPM]", ylabel="tension std [lbf]", title="Fig. 4.19: std")
    axes[0].legend(fontsize=6)
    figures.append(save(fig, out_dir / "fig4_14_20_mean_std.png"))
    fig, axes = plt.subplots(len(speeds), 2, figsize=(9, 3 * len(speeds)), squeeze=False)
    for k, fpm in enumerate(speeds):
        for case in ("no backlash", "backlash", "backlash + 10 lbf ft brake",
                     "backlash + 14 lbf ft brake"):
            sel = [x for x in part2 if x["speed_fpm"] == fpm and x["case"] == case]
            fr = [x["frequency_Hz"] for x in sel]
            axes[k, 0].plot(fr, [x["tension_amplitude_lbf"] for x in sel], "o-", label=case)
            axes[k, 1].plot(fr, [x["speed_amplitude_fpm"] for x in sel], "o-", label=case)
        axes[k, 0].set(xlabel="disturbance frequency [Hz]", ylabel="tension amplitude [lbf]",
                       title=f"{fpm:g} FPM (Figs 4.24, 4.28, 4.30)")
        axes[k, 1].set(xlabel="disturbance frequency [Hz]", ylabel="speed amplitude [FPM]",
                       title=f"{fpm:g} FPM (Figs 4.25, 4.29, 4.30)")
    axes[0, 0].legend(fontsize=6)
    figures.append(save(fig, out_dir / "fig4_24_30_amplification.png"))
    part3, margin = rockwell_gap.gap_rows(case_line(300.0),
                                          half_gap(p["backlash_clearance"]["amplification"], p),
                                          quick)
    part3 += rockwell_gap.bound_rows(
        {fpm: case_line(fpm) for fpm in speeds},
        {1e3 * p["backlash_clearance"][k]: half_gap(p["backlash_clearance"][k], p)
         for k in ("mean_tension", "amplification")})
    figures.append(save(rockwell_gap.plot(plt, part3, margin), out_dir / "gap_opening.png"))
    rows: list[dict[str, Any]] = part1 + part2 + part3
    lines = ["rockwell-rewind (thesis Sec. 4.3, Figs 4.14-4.30)"]
    for x in part1:
        lines.append(f"{x['speed_fpm']:g} FPM, backlash {x['backlash_mm']:g} mm, "
                     f"{x['disturbance']}: tension {x['tension_mean_lbf']:.3f} +- "
                     f"{x['tension_std_lbf']:.3f} lbf, gap open {x['gap_open_fraction']:.1%}")
    for x in part2:
        lines.append(f"{x['speed_fpm']:g} FPM, {x['frequency_Hz']:g} Hz, {x['case']}: tension "
                     f"amplitude {x['tension_amplitude_lbf']:.3f} lbf "
                     f"(x{x['tension_amplification']:.3f}),"
                     f" speed {x['speed_amplitude_fpm']:.3f} FPM (x{x['speed_amplification']:.3f}),"
                     f" gap open {x['gap_open_fraction']:.1%}, flank changes "
                     f"{x['flank_changes']}, motor torque {x['motor_torque_min_N_m']:.2f}.."
                     f"{x['motor_torque_max_N_m']:.2f} N m")
    lines.append(f"when the gap opens (300 FPM, 10 lbf): mean gear torque {margin.mean_torque:.2f}"
                 f" N m; slow-down threshold d* = {margin.decel_threshold:.3f} m/s^2 "
                 f"(quasi-static R tau/J_L = {margin.quasi_static_decel:.3f})")
    for x in part3:
        if x["part"] == "gap_bound":
            lines.append(f"  {x['speed_fpm']:g} FPM, {x['backlash_mm']:g} mm: any motion in the gap"
                         f" moves the tension by at most {x['tension_bound_lbf']:.3f} lbf (L1 "
                         "bound of (4.8))")
        elif x["part"] == "gap_threshold":
            lines.append(f"  6 FPM ripple at {x['frequency_Hz']:g} Hz: gear torque swing "
                         f"{x['spring_torque_amplitude_N_m']:.3f} N m; gap opens above "
                         f"{x['gap_threshold_fpm']:.1f} FPM, web slack above "
                         f"{x['slack_threshold_fpm']:.1f} FPM ({x['first']} first)")
        else:
            lines.append(
                f"  {x['part']}: {x['multiple_of_threshold']:g} d*, ripple {x['ripple_Hz']:g} Hz,"
                f" brake {x['brake_N_m']:.1f} N m: predicted "
                f"{'open' if x['predicted_open'] else 'closed'}, gap open "
                f"{x['gap_open_fraction']:.1%}, mean shift {x['mean_shift_pct']:+.3f} % ((4.9) "
                f"{x['mean_shift_pct_4_9']:+.3f} %), amplification x{x['amplification']:.3f} "
                f"((4.10) x{x['amplification_4_10']:.3f})")
    lines.append("thesis vs webline (tolerance +-50 %):")
    lines += [f"  {c}" for c in claims(rows)]
    return finish("rockwell-rewind", out_dir, figures, rows, "\n".join(lines))
