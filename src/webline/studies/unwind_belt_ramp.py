"""Study ``unwind-belt-ramp``: the HSWL unwind under a speed ramp from 200 to 1000 ft/min with a
rigid drive and with the 36, 24 and 12 mm belts (thesis Sec. 4.2, Figs 4.5-4.8).

The built-in ``hswl`` line is run with the unwind drive of ``hswl_unwind_ramp_ch4.toml`` (every
assumed value is listed there; belt stiffnesses from ``hswl_unwind_belt_sec2_5.toml``): motor
inertia on the motor side, motor-speed feedback (4.1j), a belt (4.2) or a rigid drive (4.1a),
a wound-in tension ripple. Each case's linearized closed loop is checked to be stable before
it runs. Measured: the span-1 tension's standard deviation and peak-to-peak after the ramp
(the oscillation the thesis sees grow as the belt narrows), its peak during the ramp, and the
least damped closed-loop mode.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

import webline
from webline.analysis.drivetrain.params import load_parameter_set
from webline.line import Line, load_line
from webline.studies.output import finish, pyplot, save
from webline.studies.result import StudyResult

CASES = ("rigid", "36mm", "24mm", "12mm")
FIGURES = {"rigid": "fig4_5", "36mm": "fig4_6", "24mm": "fig4_7", "12mm": "fig4_8"}


def case_line(case: str) -> Line:
    """The ``hswl`` line with the study's ramp, ripple and unwind drive (``case``: 'rigid' or a
    belt width '36mm', '24mm', '12mm')."""
    p = load_parameter_set("hswl_unwind_ramp_ch4")
    belts = load_parameter_set("hswl_unwind_belt_sec2_5")["belt_stiffness"]
    u = p["unwind_drive"]
    data = load_line("hswl").spec.model_dump(exclude_none=True)
    data["speed"] = {"type": "ramp", **p["ramp"]}
    data["disturbances"] = [{"type": "wound_in_ripple", **p["wound_in_ripple"]}]
    data["scenarios"] = {}
    unwind = data["rollers"][0]
    unwind["drive"].update(motor_inertia=u["motor_inertia"], motor_friction=u["motor_friction"],
                           feedback="motor")
    unwind["controller"].update(speed_kp=u["speed_kp"], speed_ki=u["speed_ki"],
                                tension_bandwidth=u["tension_bandwidth"])
    if case != "rigid":
        unwind["drive"]["transmission"] = {"type": "belt", "stiffness": belts[case],
                                           "load_pulley_radius": u["load_pulley_radius"]}
    data["name"] = f"hswl-unwind-{case}"
    return load_line(data)


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Run the four cases; write Figs 4.5-4.8 analogues, a comparison, ``table.csv`` and
    ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    p = load_parameter_set("hswl_unwind_ramp_ch4")
    duration = p["run"]["quick_duration"] if quick else p["run"]["duration"]
    ramp_end = p["ramp"]["start"] + p["ramp"]["duration"]
    after = ramp_end + p["run"]["settle_after_ramp"]
    plt = pyplot()
    fpm = 1.0 / 0.00508
    lbf = 1.0 / 4.4482216152605
    figures, rows, results = [], [], {}
    for case in CASES:
        line = case_line(case)
        modes = np.linalg.eigvals(webline.linearize(line).A)
        least = modes[np.argmax(modes.real)]
        if least.real >= 0:
            raise RuntimeError(f"unwind-belt-ramp: {case} closed loop unstable ({least})")
        result = webline.simulate(line, duration)
        results[case] = result
        t, tension = result.time, result.tension[:, 0]
        late = t >= after
        ramp = (t >= p["ramp"]["start"]) & (t <= ramp_end)
        ref = result.tension_ref[:, 0]
        fig, axes = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
        axes[0].plot(t, result.speed[:, 1] * fpm, label="web speed (master)")
        axes[0].plot(t, result.speed[:, 0] * fpm, label="unwind surface speed", lw=0.8)
        axes[0].set_ylabel("speed [ft/min]")
        axes[0].legend(fontsize=8)
        axes[1].plot(t, tension * lbf, label="span 1 tension")
        axes[1].plot(t, ref * lbf, "k--", lw=0.8, label="reference")
        axes[1].set(xlabel="time [s]", ylabel="tension [lbf]")
        axes[1].legend(fontsize=8)
        axes[0].set_title(f"{FIGURES[case].replace('fig', 'Fig. ').replace('_', '.')}: "
                          f"{'rigid drive' if case == 'rigid' else case + ' belt'}")
        figures.append(save(fig, out_dir / f"{FIGURES[case]}_{case}.png"))
        rows.append({
            "case": case,
            "least_damped_mode_real_1_s": float(least.real),
            "least_damped_mode_imag_rad_s": float(abs(least.imag)),
            "tension_std_after_ramp_N": float(tension[late].std()),
            "tension_peak_to_peak_after_ramp_N": float(np.ptp(tension[late])),
            "tension_peak_during_ramp_N": float(tension[ramp].max()),
            "tension_reference_N": float(ref[-1]),
            "unwind_speed_std_after_ramp_m_s": float(result.speed[late, 0].std()),
        })
    fig, ax = plt.subplots(figsize=(7, 3.5))
    for case, result in results.items():
        ax.plot(result.time, result.tension[:, 0] * lbf, lw=0.8, label=case)
    ax.set(xlabel="time [s]", ylabel="span 1 tension [lbf]", title="Rigid drive and belts")
    ax.legend(fontsize=8)
    figures.append(save(fig, out_dir / "comparison.png"))
    summary = "unwind-belt-ramp (thesis Sec. 4.2, Figs 4.5-4.8)\n" + "\n".join(
        f"{r['case']}: span-1 tension std after the ramp {r['tension_std_after_ramp_N']:.2f} N, "
        f"peak-to-peak {r['tension_peak_to_peak_after_ramp_N']:.2f} N, peak during the ramp "
        f"{r['tension_peak_during_ramp_N']:.1f} N (reference {r['tension_reference_N']:.1f} N); "
        f"least damped mode {r['least_damped_mode_real_1_s']:.3f} "
        f"+- {r['least_damped_mode_imag_rad_s']:.2f}j 1/s" for r in rows)
    summary += "\n" + claims({str(r["case"]): r for r in rows})
    return finish("unwind-belt-ramp", out_dir, figures, rows, summary)


#: the rigid drive counts as "settling where the 36 mm belt oscillates" when its span-1
#: oscillation after the ramp is under half the 36 mm belt's
CONTRAST = 0.5


def claims(rows: dict[str, dict[str, Any]]) -> str:
    """The thesis's two statements about Figs 4.5-4.8 (it prints no amplitudes) beside
    webline's span-1 tension std after the ramp [N] per case (``rows`` of the study's table by
    case), each with a verdict computed from them."""
    std = {case: row["tension_std_after_ramp_N"] for case, row in rows.items()}
    belts = [std[c] for c in ("36mm", "24mm", "12mm")]
    grows = belts == sorted(belts) and belts[0] < belts[-1]
    contrast = std["rigid"] < CONTRAST * std["36mm"]
    rigid = rows["rigid"]
    return "\n".join([
        "thesis: the oscillation grows as the belt narrows, 36 -> 24 -> 12 mm (Figs 4.6-4.8); "
        f"webline: std {belts[0]:.2f} -> {belts[1]:.2f} -> {belts[2]:.2f} N: "
        + ("reproduced" if grows else "not reproduced"),
        "thesis: the rigid drive settles where the 36 mm belt keeps oscillating (Fig. 4.5 "
        f"against 4.6); webline: std {std['rigid']:.2f} N rigid against {std['36mm']:.2f} N: "
        + ("reproduced" if contrast else
           f"not reproduced: the rigid drive oscillates too, "
           f"{abs(1 - std['rigid'] / std['36mm']):.0%} "
           f"{'less' if std['rigid'] <= std['36mm'] else 'more'} (its least damped mode "
           f"{rigid['least_damped_mode_real_1_s']:.3f} +- "
           f"{rigid['least_damped_mode_imag_rad_s']:.2f}j 1/s has no belt in it)"),
    ])
