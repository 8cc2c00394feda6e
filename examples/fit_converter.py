"""Fit two parameters of the built-in converter to a (synthetic) recording of its start-up.

    python examples/fit_converter.py

A drive log is simulated from a converter whose chill-roll inertia and web modulus differ
from its line file, with sensor noise and a logger's clock offset; the line file is replayed
against it, then the two values are fitted with their 95 % intervals (docs/commissioning.md).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import webline
from webline.twin.traces.synthetic import synthetic_csv

TRUTH = {"rollers.chill.inertia": 2.4, "web.modulus": 3.3e9}  # SI: kg m², Pa

with tempfile.TemporaryDirectory() as folder:
    log = synthetic_csv(Path(folder) / "startup.csv", "converter", changes=TRUTH,
                        duration=10.0, scenario="startup", offset=12.0, seed=8)
    line = webline.load_line("converter").with_scenario("startup")
    data = webline.load_measurements(log, line)
    print(data.report())

    before = webline.replay(line, data)
    print("replay of the line file, torque[chill] RMS error: "
          f"{before.metrics.set_index('signal').loc['torque[chill]', 'rms']:.3f} N*m")

    result = webline.fit(line, data, {"rollers.chill.inertia": "0.5 .. 8 kg*m**2",
                                      "web.modulus": "2 .. 6 GPa"})
    print(result)
    for i, p in enumerate(result.parameters):
        low, high = result.ci95[i]
        inside = "inside" if low <= TRUTH[p.path] <= high else "OUTSIDE"
        print(f"{p.path}: true {TRUTH[p.path]:.4g} {p.unit} {inside} the 95 % interval")

    # the chill roll's torque: recorded, replayed with the line file, and with the fitted line
    after = webline.replay(result.fitted_line, data)
    _, ax = plt.subplots(figsize=(8, 3.5), layout="constrained")
    ax.plot(before.time, before.measured["torque[chill]"], color="0.6", lw=0.8, label="recorded")
    ax.plot(before.time, before.run.values["torque[chill]"], label="line file")
    ax.plot(after.time, after.run.values["torque[chill]"], "--", label="fitted line")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("torque[chill] [N·m]")
    ax.set_title("converter start-up: the fit closes the gap to the recording")
    ax.legend()
    ax.grid(alpha=0.3)
    plt.show()
