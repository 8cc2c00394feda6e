"""Study ``belt-step``: speed step and FFT of the load speed of the HSWL unwind belt drive with
the 12, 24 and 36 mm belts (thesis Sec. 2.5, Figs 2.10-2.12).

Model: the two-inertia belt drive (2.10) with the motor-side PI (2.3) of the data file
``hswl_unwind_belt_sec2_5.toml`` (every assumed value is listed there; the step size and the
run length are in ``belt_step_sec2_5.toml``). The loop is linear, so it is stepped exactly
(zero-order hold of the constant reference, matrix exponential) at 1 kHz.

Outputs: the motor and load speeds after a 200 RPM step of the motor speed reference (Fig. 2.10),
the load speed's oscillation about its final value (Fig. 2.11) and its FFT (Fig. 2.12). The FFT
peak is compared with the closed-loop belt mode (eigenvalues of the loop) and with the two
open-loop natural frequencies of ``analysis.drivetrain.belt.natural_frequencies``: the motor in
velocity mode (2.37) and in torque mode (two free inertias).

The thesis's setup (``studies.belt_step_thesis``): motor-encoder feedback as Sec. 2.5 states,
the same loop sampled at Appendix B's 35.36 ms, and load-side feedback, each stepped with the
torque limit; the summary puts the thesis's FFT peaks, its 5 RPM amplitude and its stated
(2.37) frequencies (rad/s printed as Hz, E-2.6) beside webline's, and says which setup, if
any, sustains an oscillation (E-2.8).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from webline.analysis.drivetrain import belt, equivalent
from webline.analysis.drivetrain.params import hswl_unwind_belt_drive, load_parameter_set
from webline.analysis.drivetrain.sampled import zoh
from webline.studies import belt_step_thesis as thesis
from webline.studies.output import finish, pyplot, save
from webline.studies.result import StudyResult

BELTS = ("12mm", "24mm", "36mm")


def step_response(belt_name: str, *, duration: float, dt: float,
                  step: float) -> dict[str, np.ndarray | float]:
    """Motor and load speeds [rad/s] after a ``step`` [rad/s] of the motor speed reference at
    t = 0, on a grid of ``dt`` [s] up to ``duration`` [s], with the FFT of the load speed."""
    spec = load_parameter_set("hswl_unwind_belt_sec2_5")["speed_loop"]
    drive = hswl_unwind_belt_drive(belt_name)
    gains = equivalent.pi_motor_side(drive, spec["bandwidth"], spec["damping"])
    a, b = belt.closed_loop_matrices(drive, gains, "motor")
    ad, bd = zoh(a, b, dt)
    bd = bd * step
    n = round(duration / dt) + 1
    states = np.empty((n, 5))
    x = np.zeros(5)
    for i in range(n):
        states[i] = x
        x = ad @ x + bd
    t = np.arange(n) * dt
    load = states[:, 3]
    final = step * drive.r_motor / drive.r_load  # rigid ratio: the belt does not slip
    pad = 8 * n  # zero padding: a finer frequency grid for locating the peak
    freq = np.fft.rfftfreq(pad, dt)
    spectrum = np.abs(np.fft.rfft((load - final) * np.hanning(n), pad)) * 2.0 / n
    lam = np.linalg.eigvals(belt.homogeneous_matrix(drive, gains, "motor"))
    mode = lam[np.argmax(np.abs(lam.imag))]
    nat = belt.natural_frequencies(drive)
    band = freq > 0.2  # above the speed loop's slow real poles
    return {"t": t, "motor": states[:, 1], "load": load, "final": final, "freq": freq,
            "spectrum": spectrum,
            "peak_hz": float(freq[band][np.argmax(spectrum[band])]),
            "belt_mode_hz": float(abs(mode.imag) / (2 * np.pi)),
            "belt_mode_damping": float(-mode.real / abs(mode)),
            "velocity_mode_hz": nat.velocity_mode_hz, "torque_mode_hz": nat.torque_mode_hz,
            "kp": gains.kp, "ki": gains.ki}


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Step each belt; write Figs 2.10-2.12 analogues, ``table.csv`` and ``summary.txt``."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    p = load_parameter_set("belt_step_sec2_5")["run"]
    duration = p["quick_duration"] if quick else p["duration"]
    runs = {name: step_response(name, duration=duration, dt=p["time_step"], step=p["step"])
            for name in BELTS}
    rpm = 60.0 / (2 * np.pi)
    plt = pyplot()
    figures = []
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    for ax, (name, r) in zip(axes, runs.items(), strict=True):
        ax.plot(r["t"], r["motor"] * rpm, label="motor")
        ax.plot(r["t"], r["load"] * rpm, label="load")
        ax.set_ylabel("speed [RPM]")
        ax.set_title(f"{name} belt: {p['step'] * rpm:.0f} RPM step of the motor reference")
        ax.legend(loc="lower right")
    axes[-1].set_xlabel("time [s]")
    figures.append(save(fig, out_dir / "fig2_10_step.png"))
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    for ax, (name, r) in zip(axes, runs.items(), strict=True):
        ax.plot(r["t"], (r["load"] - r["final"]) * rpm)
        ax.set_ylabel("load - final [RPM]")
        ax.set_title(f"{name} belt: load speed about its final value")
    axes[-1].set_xlabel("time [s]")
    figures.append(save(fig, out_dir / "fig2_11_load_speed.png"))
    fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    for ax, (name, r) in zip(axes, runs.items(), strict=True):
        ax.plot(r["freq"], r["spectrum"] * rpm)
        for key, style in (("belt_mode_hz", "--"), ("velocity_mode_hz", ":"),
                           ("torque_mode_hz", "-.")):
            ax.axvline(r[key], ls=style, color="k", lw=0.8, label=key.replace("_", " "))
        ax.set_xlim(0, 12)
        ax.set_ylabel("|FFT| [RPM]")
        ax.set_title(f"{name} belt: FFT of the load speed (peak {r['peak_hz']:.2f} Hz)")
    axes[0].legend(fontsize=7)
    axes[-1].set_xlabel("frequency [Hz]")
    figures.append(save(fig, out_dir / "fig2_12_fft.png"))
    rows: list[dict[str, object]] = []
    for name, r in runs.items():
        load = np.asarray(r["load"])
        rows.append({
            "belt": name, "speed_kp_N_m_s": r["kp"], "speed_ki_N_m": r["ki"],
            "fft_peak_Hz": r["peak_hz"], "closed_loop_belt_mode_Hz": r["belt_mode_hz"],
            "closed_loop_belt_mode_damping": r["belt_mode_damping"],
            "velocity_mode_Hz": r["velocity_mode_hz"], "torque_mode_Hz": r["torque_mode_hz"],
            "load_overshoot_pct": float(100 * (load.max() / r["final"] - 1.0)),
        })
    fig, axes = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    kps = np.geomspace(0.1, 1000.0, 121)
    for name in BELTS:
        hz, zeta = thesis.kp_sweep(name, kps)
        axes[0].semilogx(kps, hz, label=name)
        axes[1].semilogx(kps, zeta, label=name)
    for peak in set(thesis.THESIS_PEAK_HZ.values()):
        axes[0].axhline(peak, ls=":", color="k", lw=0.8)
    axes[0].set(ylabel="belt mode [Hz]",
                title="Motor-feedback PI: belt mode against kp (dotted: thesis FFT peaks)")
    axes[1].set(xlabel="speed kp [N m s]", ylabel="damping ratio")
    axes[0].legend(fontsize=8)
    figures.append(save(fig, out_dir / "belt_mode_vs_kp.png"))
    setups = thesis.thesis_rows(BELTS, quick=quick)
    limits = {name: thesis.light_damping_limit(name) for name in BELTS}
    j_motor = {name: equivalent.inertia_motor_side(hswl_unwind_belt_drive(name))
               for name in BELTS}
    summary = "belt-step (thesis Sec. 2.5, Figs 2.10-2.12)\n" + "\n".join(
        f"{r['belt']}: FFT peak {r['fft_peak_Hz']:.3f} Hz, closed-loop belt mode "
        f"{r['closed_loop_belt_mode_Hz']:.3f} Hz (damping {r['closed_loop_belt_mode_damping']:.3f})"
        f", velocity mode {r['velocity_mode_Hz']:.3f} Hz, torque mode {r['torque_mode_Hz']:.3f} Hz,"
        f" load overshoot {r['load_overshoot_pct']:.0f} %" for r in rows)
    summary += ("\nthesis stated (2.37), webline (2.37) in rad/s: " + ", ".join(
        f"{r['belt']} {r['thesis_stated_2_37']} 'Hz' vs {r['webline_2_37_rad_s']:.2f} rad/s"
        for r in setups if r["setup"] == thesis.SETUPS[0][0]) + " (the thesis's unit is rad/s)")
    summary += "\nthesis setup (200 RPM step, torque limit):\n" + "\n".join(
        thesis.verdict(r) for r in setups)
    summary += "\nmotor feedback, continuous: belt mode damping ratio < 0.1 only for " + \
        ", ".join(f"{b} kp < {k:.2f} N m s ({hz:.2f} Hz; a rigid-loop bandwidth "
                  f"{k / (2 * j_motor[b]):.3f} rad/s)" for b, (k, hz) in limits.items())
    return finish("belt-step", out_dir, figures, rows + setups, summary)
