"""Three controller families on the same line and scenario: the industrial cascaded PI, the
decentralized state feedback and the decentralized adaptive controller of thesis Ch. 6, each
with its default design, compared by the RMS tension error of every loadcell span.

Run: python examples/compare_controllers.py
"""

import matplotlib.pyplot as plt

import webline
from webline.control.select import with_controller

base = webline.load_line("hswl").with_scenario("disturbance")
print(f"{'controller':15s} " + " ".join(f"{z.loadcell + 1:>10d}" for z in base.zones)
      + "   (RMS tension error [N] per loadcell span)")
_, ax = plt.subplots(figsize=(8, 3.5), layout="constrained")
for family in ("cascaded_pi", "state_feedback", "adaptive"):
    result = webline.simulate(with_controller(base, family), "10 s")
    spans = result.summary()["spans"]
    errors = [spans[base.span_name(z.loadcell)]["rms_error"] for z in base.zones]
    print(f"{family:15s} " + " ".join(f"{e:10.4f}" for e in errors) + f"   {result.status}")
    result.signals.tension.sel(span="span2").plot(ax=ax, label=family, lw=1.0)
ax.set_title("hswl, disturbance scenario: tension of span2 (the process zone)")
ax.legend()
ax.grid(alpha=0.3)
plt.show()
