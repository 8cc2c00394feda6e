"""From a line to python-control: the closed-loop linear model of the HSWL, the frequency
response from the process zone's tension reference (zone 2, as `webline show` numbers it) to
its loadcell's tension, and its -3 dB bandwidth.

Run: python examples/bode.py
"""

import control
import matplotlib.pyplot as plt
import numpy as np

import webline

closed = webline.linearize("hswl", loop="closed")
print(f"{closed.nstates} states; inputs: {', '.join(closed.input_labels)}")
reference = "zone2_tension_ref"
path = closed[closed.output_labels.index("span2_tension"), closed.input_labels.index(reference)]
omega = np.logspace(-1, 3, 400)  # [rad/s]
magnitude, phase, omega = control.frequency_response(path, omega)
gain_db = 20 * np.log10(np.abs(magnitude))
bandwidth = omega[np.argmax(gain_db < gain_db[0] - 3.0)]
print(f"{reference} -> span2_tension: {gain_db[0]:.2f} dB at {omega[0]:.2g} rad/s, "
      f"-3 dB bandwidth {bandwidth:.2f} rad/s ({bandwidth / (2 * np.pi):.2f} Hz)")

# the Bode plot of the same path (control.bode_plot(path) draws it too)
fig, (gain_ax, phase_ax) = plt.subplots(2, 1, sharex=True, figsize=(7, 5), layout="constrained")
gain_ax.semilogx(omega, gain_db)
gain_ax.axvline(bandwidth, color="k", ls="--", lw=0.8, label=f"-3 dB at {bandwidth:.2f} rad/s")
gain_ax.set_ylabel("gain [dB]")
gain_ax.legend()
phase_ax.semilogx(omega, np.degrees(np.unwrap(phase)))
phase_ax.set_ylabel("phase [deg]")
phase_ax.set_xlabel("frequency [rad/s]")
fig.suptitle(f"hswl closed loop: {reference} -> span2_tension")
for ax in (gain_ax, phase_ax):
    ax.grid(alpha=0.3, which="both")
plt.show()
