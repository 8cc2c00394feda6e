"""A line of your own, from scratch: a small film line described as a Python dict (the same
keys as a line file), simulated through a speed ramp, with its tension statistics printed.

Run: python examples/own_line.py
"""

import matplotlib.pyplot as plt

import webline

line = webline.load_line({
    "name": "film-line",
    "speed": {"type": "ramp", "initial": "100 m/min", "final": "300 m/min", "start": "1 s",
              "duration": "4 s"},
    "web": {"thickness": "25 um", "width": "600 mm", "density": "1390 kg/m**3",
            "modulus": "4.5 GPa"},
    "rollers": [
        {"name": "unwind", "type": "unwind", "radius": "300 mm", "core_radius": "76 mm",
         "inertia": "0.5 kg*m**2", "wound_in_tension": "140 N",
         "drive": {"torque_limit": "150 N*m"}},
        {"name": "pull", "type": "driven", "role": "master", "radius": "100 mm",
         "inertia": "0.05 kg*m**2", "drive": {"torque_limit": "60 N*m"}},
        {"name": "guide", "type": "idle", "radius": "50 mm", "inertia": "0.002 kg*m**2",
         "friction": "1e-4 N*m*s"},
        {"name": "rewind", "type": "rewind", "radius": "80 mm", "core_radius": "76 mm",
         "inertia": "0.2 kg*m**2", "drive": {"torque_limit": "150 N*m"}},
    ],
    "spans": [
        {"name": "unwind-span", "length": "2 m", "tension": "150 N"},
        {"name": "rewind-in", "length": "1.5 m"},
        {"name": "rewind-span", "length": "1 m", "tension": "120 N"},
    ],
})

result = webline.simulate(line, "8 s")
print(f"verdict: {result.status}")
for span, stats in result.summary()["spans"].items():
    error = f", largest error {stats['max_abs_error']:.2f} N" if "max_abs_error" in stats else ""
    print(f"{span:12s} mean {stats['mean']:7.2f} N  std {stats['std']:5.2f} N{error}")

# tensions through the speed ramp (1 s to 5 s), one line per span
_, ax = plt.subplots(figsize=(8, 3.5), layout="constrained")
result.signals.tension.plot.line(ax=ax, x="time", lw=1.0)
ax.set_title("film-line: span tensions through the speed ramp")
ax.grid(alpha=0.3)
plt.show()
