"""A gain sweep in a loop: the RMS tension error of the HSWL's process zone during the
speed change, for several tension-loop bandwidths of its cascaded PI.

Run: python examples/gain_sweep.py
"""

import matplotlib.pyplot as plt

import webline

base = webline.load_line("hswl")
print("tension bandwidth   RMS error span2 [N]   largest error [N]")
_, ax = plt.subplots(figsize=(8, 3.5), layout="constrained")
for bandwidth in ("2 rad/s", "4 rad/s", "8 rad/s", "16 rad/s"):
    line = base.replace({"rollers.process.controller.tension_bandwidth": bandwidth})
    result = webline.simulate(line, "12 s", scenario="speed-change")
    stats = result.summary()["spans"]["span2"]
    print(f"{bandwidth:>17s}   {stats['rms_error']:19.4f}   {stats['max_abs_error']:17.4f}")
    result.signals.tension.sel(span="span2").plot(ax=ax, label=bandwidth, lw=1.0)
ax.set_title("hswl speed change: tension of span2 for each tension-loop bandwidth")
ax.legend(title="tension bandwidth")
ax.grid(alpha=0.3)
plt.show()
