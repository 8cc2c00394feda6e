"""Part 3 of ``rockwell-rewind``: runs where the backlash gap opens, and the thesis's claims.

Condition (``webline.analysis.drivetrain.gap_condition``, docs/drivetrain.md "When the gap
opens"): the gap opens when the spring torque τ = R T + b_L ω_L + J_L dω_L/dt + τ_b through the
rewind's belt and gear reaches zero. Mean τ̄ = R T_r + b_L V/R + τ_b (4.19 N·m at 300 FPM,
10 lbf). A pull-roll ripple of amplitude a at f opens it iff a > a*(f) = τ̄/|G_τ(j2πf)|, and
slackens the web iff a > T_r/|G_T(j2πf)|; a slow-down ramp opens it iff its deceleration
d > d* = τ̄/σ (σ: peak torque drop per m/s², from the linear ramp response; R τ̄/J_L quasi-
statically). Runs, each without and with the 1.5 mm backlash: slow-downs 300 -> 100 FPM at
multiples of d*; the thesis's 6 FPM ripple at 0.5-2 Hz during a slow-down at 0.93 d* (shut
while τ̄ (1 - 0.93) > a |G_τ|); brakes
0-14 lbf ft at 2 d*. For each: gap-open share, mean tension shift, amplification (tension std
with backlash / without), and the (4.9)-(4.10) prediction from the recorded deviation torque.
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

import webline
from webline.analysis.drivetrain.backlash_bounds import statistics_shift
from webline.analysis.drivetrain.gap_condition import (
    GapMargin,
    deviation_torque,
    rewind_gap_margin,
    ripple_gains,
    tension_bound,
    tension_deviation,
)
from webline.analysis.drivetrain.params import load_parameter_set
from webline.line import load_line
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as L

FPM = 0.00508  # m/s per ft/min
LBF = 4.4482216152605  # N per lbf
LBF_FT = 1.3558179483314004  # N·m per lbf·ft


def params() -> dict[str, Any]:
    return load_parameter_set("rockwell_gap_sec4_3")


def slowdown_line(base: webline.Line, decel: float, p: dict[str, Any], *, gap: float = 0.0,
                  brake: float = 0.0, ripple_hz: float | None = None) -> webline.Line:
    """``base`` slowing down at ``decel`` [m/s²] as ``p['slowdown']`` says, with backlash Δ =
    ``gap`` [rad], a ``brake`` [N·m] on the rewind shaft and the pull-roll ripple at
    ``ripple_hz`` [Hz]."""
    s = p["slowdown"]
    data = copy.deepcopy(base.spec.model_dump(exclude_none=True))
    data["speed"] = {"type": "ramp", "initial": s["initial"], "final": s["final"],
                     "start": s["start"], "duration": (s["initial"] - s["final"]) / decel}
    drive = data["rollers"][-1]["drive"]
    if gap > 0:
        drive["transmission"]["backlash"] = {"gap": gap}
    if brake > 0:
        drive["brake"] = brake
    data["disturbances"] = [] if ripple_hz is None else [
        {"type": "speed_ripple", "roller": "pull_roll", "amplitude": p["ripple"]["amplitude"],
         "frequency": ripple_hz}]
    return load_line(data)


def pair(base: webline.Line, decel: float, p: dict[str, Any], gap: float, *,
         brake: float = 0.0, ripple_hz: float | None = None) -> dict[str, object]:
    """One condition without and with backlash: statistics over the ramp and ``settle``."""
    s = p["slowdown"]
    duration = s["start"] + (s["initial"] - s["final"]) / decel + s["settle"]
    lines = [slowdown_line(base, decel, p, gap=g, brake=brake, ripple_hz=ripple_hz)
             for g in (0.0, gap)]
    r0, r1 = (webline.simulate(line, duration) for line in lines)
    w = r0.time >= s["start"]
    plan = compile_plan(lines[1])
    k, c = float(plan.drives[-1, L.D_KTRANS]), float(plan.drives[-1, L.D_CTRANS])
    rate = r1.motor_speed[:, -1] / plan.drives[-1, L.D_RATIO] - r1.omega[:, -1]
    phi = deviation_torque(r1.twist[:, -1], rate, k, c, gap)
    g = tension_deviation(lines[0], phi, float(r1.time[1] - r1.time[0]),
                          float(r1.twist[0, -1] - r0.twist[0, -1]))
    t0, t1 = r0.tension[w, -1], r1.tension[w, -1]
    pred = statistics_shift(t0, g[w])
    return {"decel_m_s2": decel, "brake_N_m": brake,
            "ripple_Hz": ripple_hz if ripple_hz is not None else 0.0,
            "min_spring_torque_without_N_m": float(k * r0.twist[w, -1].min()),
            "gap_open_fraction": float(np.mean(r1.contact[w, -1] == 0)),
            "tension_mean_without_lbf": float(t0.mean() / LBF),
            "mean_shift_pct": float(100 * (t1.mean() / t0.mean() - 1)),
            "mean_shift_pct_4_9": float(100 * pred.mean_shift / pred.mean_without),
            "amplification": float(t1.std() / t0.std()),
            "amplification_4_10": float(pred.std_with / pred.std_without),
            "max_tension_deviation_N": float(np.abs(r1.tension[:, -1] - r0.tension[:, -1]).max()),
            "status_with": r1.status}


def threshold_rows(base: webline.Line, margin: GapMargin, p: dict[str, Any]) -> list[dict]:
    """a*(f) and the slack threshold for the pull-roll ripple on the thesis's grid."""
    freqs = list(p["ripple"]["threshold_frequencies_hz"])
    g_tau, g_t = ripple_gains(base, "pull_roll", freqs)
    return [{"part": "gap_threshold", "frequency_Hz": f,
             "spring_torque_amplitude_N_m": float(gt * p["ripple"]["amplitude"]),
             "mean_spring_torque_N_m": margin.mean_torque,
             "gap_threshold_fpm": float(margin.mean_torque / gt / FPM),
             "slack_threshold_fpm": float(margin.tension / gT / FPM),
             "first": "gap" if margin.mean_torque / gt < margin.tension / gT else "slack"}
            for f, gt, gT in zip(freqs, g_tau, g_t, strict=True)]


def bound_rows(lines: dict[float, webline.Line], gaps: dict[float, float]) -> list[dict]:
    """The L1 bound of (4.8) on the tension a gap can add, per speed [FPM] (backlash-free
    ``lines``) and clearance [mm] (half gaps ``gaps`` [rad]): it bounds the mean shift and the
    change of the std for any motion in the gap, and the change of an amplitude by twice it."""
    return [{"part": "gap_bound", "speed_fpm": fpm, "backlash_mm": mm,
             "tension_bound_lbf": tension_bound(line, gap) / LBF}
            for fpm, line in lines.items() for mm, gap in gaps.items()]


def gap_rows(base: webline.Line, gap: float, quick: bool) -> tuple[list[dict], GapMargin]:
    """All part-3 rows for the line ``base`` (300 FPM, no backlash) and the half gap ``gap``."""
    p = params()
    margin = rewind_gap_margin(base)
    d_star = margin.decel_threshold
    rows: list[dict[str, Any]] = threshold_rows(base, margin, p)
    q = "quick_" if quick else ""
    for x in p["slowdown"][f"{q}multiples"]:
        rows.append({"part": "gap_slowdown", "multiple_of_threshold": x,
                     "predicted_open": bool(x > 1), **pair(base, x * d_star, p, gap)})
    x = p["ripple"]["multiple"]
    freqs = list(p["ripple"][f"{q}frequencies_hz"])
    g_tau, _ = ripple_gains(base, "pull_roll", freqs)
    for f, gt in zip(freqs, g_tau, strict=True):
        # τ̄ (1 - x) - a |G_τ| > 0: shut whatever the phases (the ramp's peak drop is x τ̄);
        # below 0 the gap opens if the ripple's trough meets the ramp's peak
        left = (1 - x) * margin.mean_torque - gt * p["ripple"]["amplitude"]
        rows.append({"part": "gap_ripple", "multiple_of_threshold": x,
                     "predicted_open": bool(left < 0), "margin_N_m": float(left),
                     **pair(base, x * d_star, p, gap, ripple_hz=f)})
    x = p["brake"]["multiple"]
    for brake in p["brake"][f"{q}torques_lbf_ft"]:
        tau_b = brake * LBF_FT
        rows.append({"part": "gap_brake", "multiple_of_threshold": x, "brake_lbf_ft": brake,
                     "predicted_open": bool(x * d_star * margin.torque_per_decel
                                            > margin.mean_torque + tau_b),
                     **pair(base, x * d_star, p, gap, brake=tau_b)})
    return rows, margin


def plot(plt: Any, rows: list[dict], margin: GapMargin) -> Any:
    """Thresholds against frequency; open share and amplification against frequency and
    brake, with the (4.10) prediction."""
    fig, ax = plt.subplots(1, 3, figsize=(12, 3.5))
    th = [r for r in rows if r["part"] == "gap_threshold"]
    f = [r["frequency_Hz"] for r in th]
    ax[0].semilogy(f, [r["gap_threshold_fpm"] for r in th], "o-", label="gap opens, a*(f)")
    ax[0].semilogy(f, [r["slack_threshold_fpm"] for r in th], "s-", label="web slack")
    ax[0].axhline(6.0, color="k", ls=":", label="thesis: 6 FPM")
    ax[0].set(xlabel="ripple frequency [Hz]", ylabel="ripple amplitude [FPM]",
              title="300 FPM, 10 lbf: thresholds")
    ax[0].legend(fontsize=7)
    for axis, part, key, label in ((ax[1], "gap_ripple", "ripple_Hz", "ripple frequency [Hz]"),
                                   (ax[2], "gap_brake", "brake_lbf_ft", "brake [lbf ft]")):
        sel = [r for r in rows if r["part"] == part]
        x = [r[key] for r in sel]
        axis.plot(x, [r["amplification"] for r in sel], "o-", label="amplification (sim)")
        axis.plot(x, [r["amplification_4_10"] for r in sel], "x--", label="(4.10) prediction")
        axis.plot(x, [1 + r["gap_open_fraction"] for r in sel], "s:", label="1 + gap-open share")
        title = (f"slow-down at {sel[0]['multiple_of_threshold']:g} d* "
                 f"(d* = {margin.decel_threshold:.3f} m/s²)")
        axis.set(xlabel=label, ylabel="[-]", title=title)
        axis.legend(fontsize=7)
    return fig
