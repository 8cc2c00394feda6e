"""Taper tension on a branched line's rewind (docs/branching.md, "Taper"): the zone's tension
reference times f(D), D the roll's diameter (docs/winder.md W1)."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched

CORE = 2 * 76.2e-3  # m: the slitter's core diameter


def _slitter(taper: dict, roller: str = "rewind_3") -> dict:
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    for r in data["rollers"]:
        if r["name"] == roller:
            r["taper"] = taper
    return data


def test_a_hyperbolic_taper_makes_the_lanes_tension_follow_its_diameter():
    """f = 1 - taper (1 - D_c / D): with taper 0.5 the rewind_3 lane starts at 97.6 N (D =
    160 mm) and follows 100 N x f(D(t)) as its roll grows (to 92.6 N at 179 mm after 20 s).
    The reference falls at ~0.25 N/s; the tension loop (8 rad/s, PI) follows a ramp with an
    error of about the ramp's rate over its bandwidth, 0.03 N: tolerance 0.1 N."""
    taper = {"type": "hyperbolic", "taper": 0.5}
    ds = webline.simulate(load_branched(_slitter(taper)), scenario="thickness-profile").dataset
    tension = ds.tension.sel(span="lane_3_span").values
    diameter = 2 * ds.radius.sel(roll="rewind_3/lane_3").values
    wanted = 100.0 * (1 - 0.5 * (1 - CORE / diameter))
    assert tension[0] == pytest.approx(wanted[0], abs=1e-6)  # the operating point's
    assert np.max(np.abs(tension - wanted)) < 0.1
    assert wanted[-1] < wanted[0] - 4.0  # the taper did act: 5 N over the run


def test_a_linear_taper_without_its_largest_diameter_is_one_line():
    with pytest.raises(LineFileError, match=r"rollers\[5\]\.taper\.max_diameter"):
        load_branched(_slitter({"type": "linear", "taper": 0.3}))


def test_a_taper_on_a_differential_shaft_is_refused():
    data = _slitter({"type": "hyperbolic", "taper": 0.3}, "rewind_shaft")
    data["rollers"][4]["shaft"] = {"type": "differential", "slip_torque": 8.0,
                                   "core_inertia": 0.005}
    with pytest.raises(LineFileError, match=r"rollers\[4\]\.taper.*differential shaft"):
        load_branched(data)
