"""Study ``solid-motion``: the solid-motion construction of backlash (thesis Sec. 3.2,
Figs 3.5-3.8) for the example of the data file ``solid_motion_sec3_2.toml`` (every assumed value
is listed there), checked against a direct simulation with plastic impacts.

Figures: Fig. 3.5 (the load's deviation zL from the centre of mass, inside the reduced gap
±br/2), Fig. 3.6 (velocity deviations of load and motor), Fig. 3.7 (velocities of the solid, the
load and the motor), Fig. 3.8 (displacements). Table: the reduced gap (3.10), the ratio
ρ = br/Y, the harmonic gain and phase of the load speed (construction and closed form) and the
largest difference of the load speed between the construction and the plastic-impact simulation.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from webline.analysis.drivetrain import backlash
from webline.studies.output import finish, pyplot, save
from webline.studies.result import StudyResult


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Construct and simulate the example; write Figs 3.5-3.8, ``table.csv``, ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    case = backlash.thesis_example()
    periods = 3.0 if quick else 6.0
    segments = backlash.construct(case, periods)
    t = np.linspace(segments[0].t0, segments[-1].t1, int(periods * 2000) + 1)
    motion = backlash.sample(case, segments, t)
    pieces = backlash.simulate_plastic(case, periods)
    t_sim = np.concatenate([p[0] for p in pieces])
    v_sim = np.concatenate([p[1][3] for p in pieces])
    order = np.argsort(t_sim, kind="stable")
    v_interp = np.interp(t, t_sim[order], v_sim[order])
    # away from the impacts (where a step in time shifts a jump) the two must agree
    jumps = np.array([s.t1 for s in segments])
    away = np.min(np.abs(t[:, None] - jumps[None, :]), axis=1) > 1e-3 * case.period
    max_diff = float(np.max(np.abs(v_interp - motion.load_velocity)[away]))
    br = backlash.reduced_gap(case.m_motor, case.m_load, case.half_gap)
    rho = backlash.gap_ratio(case)
    gain, phase = backlash.harmonic_gain_phase(case, periods=int(periods))
    gain_cf, phase_cf = backlash.harmonic_gain_phase_closed_form(rho)
    impacts = sum(1 for s in segments if s.kind == "free")

    plt = pyplot()
    mm, ms = 1e3, 1e3  # m -> mm, m/s -> mm/s
    figures = []
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(t, (motion.x_load - motion.y) * mm, label="load deviation zL")
    ax.axhline(0.5 * br * mm, color="k", ls="--", lw=0.8, label="±br/2 (3.10)")
    ax.axhline(-0.5 * br * mm, color="k", ls="--", lw=0.8)
    ax.set(xlabel="time [s]", ylabel="zL [mm]", title="Fig. 3.5: load deviation from the solid")
    ax.legend(fontsize=8)
    figures.append(save(fig, out_dir / "fig3_5_construction.png"))
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(t, motion.load_deviation_velocity * ms, label="load dzL/dt")
    ax.plot(t, motion.motor_deviation_velocity * ms, label="motor dzm/dt")
    ax.set(xlabel="time [s]", ylabel="[mm/s]", title="Fig. 3.6: velocity deviations")
    ax.legend(fontsize=8)
    figures.append(save(fig, out_dir / "fig3_6_deviations.png"))
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(t, motion.solid_velocity * ms, "k--", lw=0.8, label="solid")
    ax.plot(t, motion.load_velocity * ms, label="load (construction)")
    ax.plot(t, motion.motor_velocity * ms, label="motor (construction)")
    ax.plot(t_sim[order], v_sim[order] * ms, ":", label="load (plastic-impact simulation)")
    ax.set(xlabel="time [s]", ylabel="velocity [mm/s]", title="Fig. 3.7: velocities")
    ax.legend(fontsize=8)
    figures.append(save(fig, out_dir / "fig3_7_velocities.png"))
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(t, motion.y * mm, "k--", lw=0.8, label="solid")
    ax.plot(t, motion.x_load * mm, label="load")
    ax.plot(t, motion.x_motor * mm, label="motor")
    ax.set(xlabel="time [s]", ylabel="displacement [mm]", title="Fig. 3.8: displacements")
    ax.legend(fontsize=8)
    figures.append(save(fig, out_dir / "fig3_8_displacements.png"))
    rows: list[dict[str, object]] = [{
        "motor_mass_kg": case.m_motor, "load_mass_kg": case.m_load,
        "clearance_mm": 2e3 * case.half_gap, "reduced_gap_mm": br * 1e3,
        "solid_speed_amplitude_mm_s": case.speed_amplitude * 1e3,
        "solid_amplitude_mm": case.speed_amplitude / case.omega * 1e3, "rho": rho,
        "harmonic_gain": gain, "harmonic_gain_closed_form": gain_cf,
        "harmonic_phase_deg": float(np.degrees(phase)),
        "harmonic_phase_closed_form_deg": float(np.degrees(phase_cf)),
        "free_flights": impacts, "periods": periods,
        "max_load_speed_difference_vs_plastic_sim_mm_s": max_diff * 1e3,
    }]
    r = rows[0]
    summary = (f"solid-motion (thesis Sec. 3.2, Figs 3.5-3.8)\nreduced gap br = "
               f"{r['reduced_gap_mm']:.4f} mm, rho = br/Y = {rho:.5f}; load-speed harmonic gain "
               f"{gain:.6f} (closed form {gain_cf:.6f}), phase {r['harmonic_phase_deg']:.3f} deg "
               f"(closed form {r['harmonic_phase_closed_form_deg']:.3f}); {impacts} free flights "
               f"in {periods:g} periods; construction vs plastic-impact simulation: load speed "
               f"within {r['max_load_speed_difference_vs_plastic_sim_mm_s']:.2e} mm/s")
    return finish("solid-motion", out_dir, figures, rows, summary)
