"""Lanes on one shaft drifting apart: the built-in slitter with lane_1 1 % thicker than lane_2
on the same rewind shaft (docs/branching.md). The shaft's drive holds the two lanes' tension
sum; the thicker lane's roll grows faster, so its tension rises and the other's falls at
d(T1 - T2)/dt = EA v (h1 - h2) / (2π r²) to first order.

Run: python examples/slitter_lanes.py
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import webline

result = webline.simulate("slitter", 10.0, scenario="thickness-profile")
ds = result.dataset
t = ds["time"].values
lane_1 = ds["tension"].sel(span="lane_1_span").values
lane_2 = ds["tension"].sel(span="lane_2_span").values
for when in (0.0, 5.0, 10.0):
    k = int(np.argmin(np.abs(t - when)))
    print(f"t = {t[k]:4.1f} s   lane_1 {lane_1[k]:6.1f} N   lane_2 {lane_2[k]:6.1f} N   "
          f"sum {lane_1[k] + lane_2[k]:6.1f} N")
window = (t >= 4.0) & (t <= 6.0)
measured = np.polyfit(t[window], (lane_1 - lane_2)[window], 1)[0]
radius = float(ds["radius"].sel(roll="rewind_shaft/lane_2").sel(time=5.0, method="nearest"))
first_order = 90e3 * 5.0 * 0.5e-6 / (2 * math.pi * radius**2)  # EA v Δh / (2π r²)
print(f"drift rate {measured:.2f} N/s (first order: {first_order:.2f} N/s at r = "
      f"{radius * 1e3:.1f} mm)")
# the lanes part until each is more than 20 % off its set 100 N ([checks] tension_tolerance)
findings = sorted(f"{f.kind} {f.where}" for f in result.verdict.findings)
print(f"verdict: {result.verdict.status} ({'; '.join(findings) or 'no findings'})")

_, ax = plt.subplots(figsize=(8, 3.5), layout="constrained")
ax.plot(t, lane_1, label="lane_1 (1 % thicker)")
ax.plot(t, lane_2, label="lane_2")
ax.plot(t, (lane_1 + lane_2) / 2, "k--", lw=0.8, label="their mean (the drive holds it)")
ax.set_xlabel("time [s]")
ax.set_ylabel("tension [N]")
ax.set_title("slitter: two lanes on one rewind shaft drift apart")
ax.legend()
ax.grid(alpha=0.3)
plt.show()
