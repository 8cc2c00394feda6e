"""Shared pieces of the branched-line tests: the foil's own span equations integrated from
recorded speeds (the nip's independent check), and the laminator slit into two lanes."""

from __future__ import annotations

import tomllib
from collections.abc import Callable
from importlib import resources
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from webline.model.web_graph import BranchedLine, load_branched


def foil_zone_check(dataset: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(recorded, solved, deviation) of the laminator's foil spans (foil[0], foil_zone):
    their tensions as recorded, as the foil's own span equations (6.8) give them from the
    recorded speeds of the foil unwind, its guide and the nip alone (scipy, adaptive,
    independent of the kernel), and each span's largest deviation from its start [N]."""
    t = dataset["time"].values
    speeds = [dataset["radius"].sel(roll="unwind_foil/foil").values
              * dataset["omega"].sel(node="unwind_foil").values,
              0.05 * dataset["omega"].sel(node="guide_foil").values,
              0.1 * dataset["omega"].sel(node="nip").values]
    ea, lengths, wound = 630e3, (1.5, 2.0), 50.0

    def rate(time: float, x: np.ndarray) -> list[float]:
        v = [np.interp(time, t, s) for s in speeds]
        tension = np.maximum(x, 0.0)
        return [(ea * (v[1] - v[0]) + wound * v[0] - tension[0] * v[1]) / lengths[0],
                (ea * (v[2] - v[1]) + tension[0] * v[1] - tension[1] * v[2]) / lengths[1]]

    recorded = dataset["tension"].sel(span=["foil[0]", "foil_zone"]).values.T
    solved = solve_ivp(rate, (0.0, t[-1]), recorded[:, 0], t_eval=t, rtol=1e-11, atol=1e-9,
                       max_step=1e-3).y
    deviation = np.max(np.abs(recorded - recorded[:, :1]), axis=1)
    return recorded, solved, deviation


def laminated_then_slit(change: Callable[[dict[str, Any]], None] | None = None
                        ) -> BranchedLine:
    """The laminator with its laminate slit at a knife into two lanes (90 N each) on the
    rewind's shaft: a tree that merges and then splits. ``change`` edits the file's data
    first."""
    data = tomllib.loads(resources.files("webline.data.lines").joinpath(
        "laminator.toml").read_text("utf-8"))
    rewind = data["rollers"].pop()
    data["rollers"] += [{"name": "knife", "type": "idle", "radius": "50 mm",
                         "inertia": "0.002 kg*m**2", "friction": "1e-4 N*m*s"}, rewind]
    data["webs"][2]["path"] = ["nip", "guide_laminate", "knife"]
    data["webs"][2]["spans"] = [{"name": "laminate_zone", "length": "2 m"}, {"length": "1 m"}]
    for lane in ("lane_a", "lane_b"):
        data["webs"].append({"name": lane, "slit_from": "laminate", "width": "0.5 m",
                             "path": ["knife", "rewind"],
                             "spans": [{"name": f"{lane}_span", "length": "2 m",
                                        "tension": "90 N"}]})
    data["scenarios"] = {}
    if change is not None:
        change(data)
    return load_branched(data)
