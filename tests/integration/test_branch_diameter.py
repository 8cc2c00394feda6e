"""Diameter calculators on a branched line's rolls (docs/branching.md, "Diameter
calculation"; docs/winder.md W2): the controllers use the calculated radius."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched


def _slitter(diameter: dict, roller: str = "rewind_3") -> dict:
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    for r in data["rollers"]:
        if r["name"] == roller:
            r["diameter"] = diameter
    return data


def _run(diameter: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ds = webline.simulate(load_branched(_slitter(diameter)), 6.0).dataset
    return (ds.time.values, ds.control_radius.sel(drive="rewind_3").values,
            ds.radius.sel(roll="rewind_3/lane_3").values)


def test_a_speed_ratio_calculator_finds_the_diameter_from_a_wrong_guess():
    """R = v_line / ω through a 0.2 s filter from a guess 10 % high (88 mm for 80 mm). The
    wrong radius first runs the roll at the wrong speed, so ω (and R_raw) settle with the
    tension loop, not with the filter alone (measured: 1.3 mm off at 1 s); at the end what is
    left is the filter's lag on a growing roll, ṙ τ = 0.5 mm/s x 0.2 s = 0.1 mm (measured
    0.099 mm), plus the lane's strain against the reference's (< 1e-3 of R: 0.08 mm):
    within 0.25 mm."""
    t, calc, true = _run({"method": "speed_ratio", "line_speed": "reference",
                          "initial": "176 mm"})
    assert calc[0] == pytest.approx(0.088, abs=5e-5)  # after its first tick: 8 mm x dt/τ
    assert abs(calc[-1] - true[-1]) < 2.5e-4
    assert abs(calc[np.searchsorted(t, 0.2)] - true[0]) > 2e-3  # it did start wrong


def test_a_thickness_calculator_follows_the_roll_it_counts():
    """R += h |ω| dt / 2π per tick is the roll's own dr/dt = h ω / 2π (6.6), sampled at
    1 kHz: the same radius to the sampling's error (measured 0.5 µm while the roll grows
    2.9 mm in 6 s; ω sampled once a tick, |ω| itself the measured one): within 1 µm."""
    _, calc, true = _run({"method": "thickness"})
    assert np.max(np.abs(calc - true)) < 1e-6
    assert true[-1] - true[0] > 2e-3  # the roll did grow


def test_a_preset_sets_the_calculated_diameter_at_its_time():
    """W2a: a "measured" preset at 0.5 s puts the true radius in, a given one (200 mm) at
    1 s its half; the tick after, the calculator has moved one filter step from there
    (|R_raw - R| dt / τ: 0.12 mm for the ~24 mm R_raw is off, 0.04 mm for 8 mm)."""
    t, calc, true = _run({"method": "speed_ratio", "line_speed": "reference",
                          "initial": "176 mm",
                          "preset": [{"at": 0.5}, {"at": 1.0, "diameter": "200 mm"}]})
    before, at = np.searchsorted(t, 0.499), np.searchsorted(t, 0.5)
    assert abs(calc[before] - true[before]) > 1e-3  # still converging from the guess
    assert abs(calc[at] - true[at]) < 5e-5
    assert calc[np.searchsorted(t, 1.0)] == pytest.approx(0.1, abs=2e-4)


def test_a_diameter_source_that_is_a_roll_is_one_line():
    with pytest.raises(LineFileError, match=r"rollers\[5\]\.diameter\.line_speed"):
        load_branched(_slitter({"method": "speed_ratio", "line_speed": "unwind"}))
