"""A gain sweep in a loop: the RMS tension error of the HSWL's process zone during the
speed change, for several tension-loop bandwidths of its cascaded PI.

Run: python examples/gain_sweep.py
"""

import webline

base = webline.load_line("hswl")
print("tension bandwidth   RMS error span2 [N]   largest error [N]")
for bandwidth in ("2 rad/s", "4 rad/s", "8 rad/s", "16 rad/s"):
    line = base.replace({"rollers.process.controller.tension_bandwidth": bandwidth})
    stats = webline.simulate(line, "12 s", scenario="speed-change").summary()["spans"]["span2"]
    print(f"{bandwidth:>17s}   {stats['rms_error']:19.4f}   {stats['max_abs_error']:17.4f}")
