"""The belt step of thesis Sec. 2.5 under the thesis's setup, and where the sustained
oscillation of Figs 2.11-2.12 can and cannot come from (part of study ``belt-step``).

Three setups per belt, each a PI placed on the rigid model (``belt_step_sec2_5.toml``,
``[thesis_setup]``) and stepped 200 RPM with the drive's torque limit:

* ``motor 1 ms``: the encoder on the motor shaft as the feedback (what Sec. 2.5 says ran);
* ``motor 35.36 ms``: the same, sampled at the only sample time the thesis lists (Appendix B);
* ``load 1 ms``: the load speed (the tachogenerator) as the feedback.

Each gives the least damped oscillatory mode of the sampled closed loop (as s = ln z / ts), the
load speed's FFT peak over the last ``window`` of the run and the half peak-to-peak amplitude
there [RPM]. A sweep of kp (motor feedback) shows where the belt mode sits and how it is damped.
"""

from __future__ import annotations

import numpy as np

from webline.analysis.drivetrain import belt, equivalent
from webline.analysis.drivetrain.params import hswl_unwind_belt_drive, load_parameter_set
from webline.analysis.drivetrain.sampled import equivalent_eigenvalues, sampled_pi, step

RPM = 60.0 / (2.0 * np.pi)
# thesis Sec. 2.5: FFT peaks of Fig. 2.12 ("approximately 5 Hz" for 12 mm, "near 10 Hz" for
# 24 and 36 mm), the sustained amplitude of Fig. 2.11 (12 mm: "around 5 RPM") and the stated
# (2.37) frequencies "5.5, 7, 8.6 Hz" (rad/s, E-2.6)
THESIS_PEAK_HZ = {"12mm": 5.0, "24mm": 10.0, "36mm": 10.0}
THESIS_AMPLITUDE_RPM = {"12mm": 5.0}
THESIS_STATED_237 = {"12mm": 5.5, "24mm": 7.0, "36mm": 8.6}
SETUPS = (("motor 1 ms", "motor", "fast_sample"), ("motor 35.36 ms", "motor", "listing_sample"),
          ("load 1 ms", "load", "fast_sample"))


def least_damped(lam: np.ndarray) -> complex:
    """The oscillatory eigenvalue (Im > 0.5 rad/s) with the largest real part [1/s]."""
    osc = lam[lam.imag > 0.5]
    return complex(osc[np.argmax(osc.real)])


def setup_run(belt_name: str, feedback: str, ts: float, *, duration: float,
              window: float) -> dict[str, float]:
    """One setup: mode, FFT peak [Hz] and amplitude [RPM] of the load speed in the last
    ``window`` [s] of a ``duration`` [s] run after a 200 RPM step of the speed reference."""
    p = load_parameter_set("belt_step_sec2_5")
    q = p["thesis_setup"]
    drive = hswl_unwind_belt_drive(belt_name)
    tune = equivalent.pi_motor_side if feedback == "motor" else equivalent.pi_load_side
    gains = tune(drive, q["bandwidth"], q["damping"])
    a, b = belt.open_loop_matrices(drive)
    k = 1 if feedback == "motor" else 3
    loop = sampled_pi(a, b[:, 0], k, k - 1, gains.kp, gains.ki, ts,
                      "difference" if feedback == "motor" else "ideal")
    mode = least_damped(equivalent_eigenvalues(loop))
    # the same 200 RPM motor step: a load-speed loop gets the load's share of it
    ref = p["run"]["step"] * (1.0 if feedback == "motor" else drive.r_motor / drive.r_load)
    n = round(duration / ts)
    xs, us = step(loop, ref, n, limit=q["torque_limit"])
    late = np.arange(n + 1) * ts > duration - window
    load = xs[late, 3]
    m = int(late.sum())
    freq = np.fft.rfftfreq(8 * m, ts)
    spectrum = np.abs(np.fft.rfft((load - load.mean()) * np.hanning(m), 8 * m))
    band = freq > 0.2
    amplitude = 0.5 * float(np.ptp(load)) * RPM
    return {"kp_N_m_s": gains.kp, "ki_N_m": gains.ki,
            "mode_real_1_s": mode.real, "mode_Hz": abs(mode.imag) / (2 * np.pi),
            "fft_peak_Hz": float(freq[band][np.argmax(spectrum[band])]) if amplitude > 1e-3
            else float("nan"),
            "amplitude_rpm": amplitude,
            "torque_limited_pct": 100.0 * float(np.mean(np.abs(us[late[:-1]])
                                                          >= q["torque_limit"] * (1 - 1e-12)))}


def kp_sweep(belt_name: str, kps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Frequency [Hz] and damping ratio of the motor-feedback loop's belt mode (the fastest
    oscillatory pair; continuous, ki/kp as the placement's) for each kp [N·m·s]."""
    drive = hswl_unwind_belt_drive(belt_name)
    q = load_parameter_set("belt_step_sec2_5")["thesis_setup"]
    ratio = q["bandwidth"] / (2.0 * q["damping"])  # ki/kp of the placement
    hz, zeta = np.empty(len(kps)), np.empty(len(kps))
    for j, kp in enumerate(kps):
        lam = np.linalg.eigvals(belt.homogeneous_matrix(
            drive, equivalent.SpeedPI(kp=float(kp), ki=float(kp) * ratio), "motor"))
        mode = lam[np.argmax(lam.imag)]
        hz[j], zeta[j] = abs(mode.imag) / (2 * np.pi), -mode.real / abs(mode)
    return hz, zeta


def light_damping_limit(belt_name: str, zeta_max: float = 0.1) -> tuple[float, float]:
    """The largest kp [N·m·s] (motor feedback) for which the belt mode's damping ratio stays
    below ``zeta_max``, and the mode's frequency there [Hz] (bisection on a log grid)."""
    kps = np.geomspace(1e-3, 1e3, 601)
    hz, zeta = kp_sweep(belt_name, kps)
    light = np.nonzero(zeta < zeta_max)[0]
    first_heavy = int(np.argmax(zeta >= zeta_max))
    j = light[light < first_heavy][-1] if first_heavy > 0 else 0
    return float(kps[j]), float(hz[j])


def thesis_rows(belts: tuple[str, ...], *, quick: bool) -> list[dict[str, object]]:
    """Every setup for every belt, with the thesis's numbers beside webline's."""
    q = load_parameter_set("belt_step_sec2_5")["thesis_setup"]
    duration = q["quick_duration"] if quick else q["duration"]
    rows: list[dict[str, object]] = []
    for name in belts:
        nat = belt.natural_frequencies(hswl_unwind_belt_drive(name))
        for label, feedback, sample in SETUPS:
            r = setup_run(name, feedback, q[sample], duration=duration, window=q["window"])
            rows.append({"belt": name, "setup": label, **r,
                         "thesis_fft_peak_Hz": THESIS_PEAK_HZ[name],
                         "thesis_amplitude_rpm": THESIS_AMPLITUDE_RPM.get(name, float("nan")),
                         "torque_mode_Hz": nat.torque_mode_hz,
                         "thesis_stated_2_37": THESIS_STATED_237[name],
                         "webline_2_37_rad_s": nat.velocity_mode_hz * 2 * np.pi})
    return rows


def verdict(row: dict[str, object]) -> str:
    """One sentence computed from a row: does the setup sustain an oscillation, at what
    frequency and amplitude, against the thesis's."""
    v = {k: float(x) for k, x in row.items() if isinstance(x, (int, float))}
    head = (f"{row['belt']} {row['setup']}: belt mode {v['mode_real_1_s']:+.2f} 1/s at "
            f"{v['mode_Hz']:.2f} Hz, ")
    if v["amplitude_rpm"] < 0.01:
        return head + "settles (no sustained oscillation)"
    thesis_amp = v["thesis_amplitude_rpm"]
    amp = f"{v['amplitude_rpm']:.3g} RPM" + (
        f" (thesis {thesis_amp:.0f} RPM)" if np.isfinite(thesis_amp) else "")
    trend = "grows until the torque limit" if v["mode_real_1_s"] > 0 else "decays"
    return (head + trend + f"; last window: FFT peak {v['fft_peak_Hz']:.2f} Hz (thesis ~"
            f"{v['thesis_fft_peak_Hz']:.0f} Hz), amplitude {amp}, torque at its limit "
            f"{v['torque_limited_pct']:.0f} % of the time")
