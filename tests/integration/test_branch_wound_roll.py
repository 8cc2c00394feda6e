"""Wound rolls on branched lines (docs/wound-roll.md, "Branched lines"): the slitter's shaft
winds one roll per lane and rewind_3 its own, the laminator's rewind the laminate; each gets
the chain's roll from its own records (sim.branches.findings.wound_rolls), its findings in
the verdict under its web, its figure, summary.json entry and results.nc group."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

import webline
from webline.errors import LineFileError
from webline.report.branch_report import write_branch_report

#: a film stack (Pfeiffer K1, K2 as docs/wound-roll.md's PET example), rolls of 0.3 m
TABLE = {"k1": "5 kPa", "k2": 100, "diameter": "0.3 m"}
H, WIDTH = 50e-6, 0.4  # the slitter's web thickness and lane width [m]


@pytest.fixture(scope="module")
def slit() -> webline.RunResult:
    """2 s of the slitter, lane_3 (on its own rewind) at 150 N, the shaft's lanes at 100 N;
    the shaft's rolls kept at r = 85 mm during winding too."""
    line = webline.load_line("slitter").replace({
        "rollers.rewind_shaft.roll_stress": {**TABLE, "at_radii": ["85 mm"]},
        "rollers.rewind_3.roll_stress": TABLE,
        "webs.lane_3.spans.lane_3_span.tension": "150 N",
    })
    return webline.simulate(line, 2.0)


def test_each_lane_has_its_roll_with_its_own_tension(slit) -> None:
    rolls = slit.wound_rolls
    assert list(rolls) == ["rewind_shaft/lane_1", "rewind_shaft/lane_2", "rewind_3/lane_3"]
    assert slit.wound_roll is rolls["rewind_shaft/lane_1"]  # the first, as a chain's one
    for name, tension in (("rewind_shaft/lane_1", 100.0), ("rewind_3/lane_3", 150.0)):
        roll = rolls[name]
        # 0.3 m roll on a 76.2 mm core of 50 um layers, counted from the lane's thickness
        assert len(roll.stress.radius) == round((0.15 - 0.0762) / H)
        # the layers the run did not wind: the lane's own set tension over its own width
        outside = ~roll.layers.in_run
        np.testing.assert_allclose(roll.layers.stress[outside], tension / (WIDTH * H),
                                   rtol=1e-12)
        # the layers it wound: the lane's span tension as recorded, within 2 % of its set
        np.testing.assert_allclose(roll.layers.tension[roll.layers.in_run], tension, rtol=0.02)
        # the outer layer presses what is under it with T h / r (thin ring), to round-off
        s = roll.stress
        assert s.pressure[-1] == pytest.approx(s.wound_on[-1] * H / s.radius[-1], rel=1e-12)


def test_a_tighter_lane_winds_a_harder_roll_everywhere(slit) -> None:
    """lane_3 at 1.5 x the tension of lane_1 and lane_2: its pressure is exactly 1.5 x at
    the outer layer (T h / r) and more below it: under more pressure Pfeiffer's stack is
    stiffer (E_r = K2 (P + K1)), g² = E_t / E_r smaller, so each layer's load reaches further
    down (w ~ r^±g). The two shaft lanes, alike in width and set tension, within 2 %."""
    p1, p2, p3 = (slit.wound_rolls[n].stress.pressure for n in
                  ("rewind_shaft/lane_1", "rewind_shaft/lane_2", "rewind_3/lane_3"))
    assert p3[-1] / p1[-1] == pytest.approx(1.5, rel=1e-12)
    assert np.all(p3 / p1 >= 1.5 * (1 - 1e-9))
    assert p3[0] / p1[0] > 2.0  # at the core: far more than the tension ratio
    np.testing.assert_allclose(p2, p1, rtol=0.02)


def test_snapshot_at_a_radius_is_the_roll_truncated_there(slit) -> None:
    roll = slit.wound_rolls["rewind_shaft/lane_1"]
    (snap,) = roll.snapshots
    m = 176  # layers on when the surface reaches 85 mm: 76.2 mm + 176 x 50 um
    assert len(snap.stress.radius) == m
    assert snap.stress.radius[-1] + H == pytest.approx(0.085, rel=1e-12)
    # the pressure then: less than at the end (the layers above press it further)
    assert np.all(snap.stress.pressure <= roll.stress.pressure[:m] * (1 + 1e-12))
    assert slit.wound_rolls["rewind_3/lane_3"].snapshots == ()


def test_findings_report_summary_and_file(slit, tmp_path) -> None:
    hoop = [f for f in slit.verdict.findings if f.kind == "roll_hoop"]
    assert {f.where for f in hoop} == {"lane_1", "lane_2", "lane_3"}  # under its lane's row
    assert all(f.message.startswith(("rewind_shaft/lane_", "rewind_3/lane_3")) for f in hoop)
    files = write_branch_report(slit, tmp_path)
    names = {p.name for p in files.figures}
    assert {"wound_roll_rewind_shaft_lane_1.png", "wound_roll_rewind_3_lane_3.png"} <= names
    summary = json.loads(files.summary.read_text(encoding="utf-8"))
    assert [r["rewind"] for r in summary["wound_rolls"]] == list(slit.wound_rolls)
    assert summary["wound_rolls"][0]["snapshots"][0]["radius_m"] == pytest.approx(0.085)
    assert "Wound rolls" in files.report.read_text(encoding="utf-8")
    path = slit.to_netcdf(tmp_path / "results.nc")
    with xr.open_dataset(path, group="wound_roll/rewind_3/lane_3", engine="h5netcdf") as ds:
        np.testing.assert_array_equal(ds.pressure.values,
                                      slit.wound_rolls["rewind_3/lane_3"].stress.pressure)


def test_the_laminate_rolls_as_one_web_of_its_layers() -> None:
    """The laminator's roll: the laminate's thickness (23 + 9 um) and width (1 m), its
    modulus the layers' EA over that section."""
    line = webline.load_line("laminator").replace(
        {"rollers.rewind.roll_stress": {**TABLE, "diameter": "0.2 m"}})
    result = webline.simulate(line, 1.0)
    (name, roll), = result.wound_rolls.items()
    assert name == "rewind/laminate"
    h = 32e-6
    assert roll.stress.thickness == pytest.approx(h, rel=1e-12)
    np.testing.assert_allclose(roll.layers.stress, roll.layers.tension / (1.0 * h), rtol=1e-12)
    s = roll.stress
    assert s.pressure[-1] == pytest.approx(s.wound_on[-1] * h / s.radius[-1], rel=1e-12)
    assert any(f.kind == "roll_hoop" and f.where == "laminate" for f in result.verdict.findings)


@pytest.mark.parametrize(("radius", "problem"), [
    ("50 mm", r"rollers\[4\]\.roll_stress\.at_radii\[1\]: 0\.05 m is inside the core"),
    ("0.2 m", r"rollers\[4\]\.roll_stress\.at_radii\[1\]: 0\.2 m is beyond the finished roll"),
])
def test_a_snapshot_outside_the_roll_is_refused(radius: str, problem: str) -> None:
    line = webline.load_line("slitter")
    with pytest.raises(LineFileError, match=problem):
        line.replace({"rollers.rewind_shaft.roll_stress": {**TABLE,
                                                           "at_radii": ["0.1 m", radius]}})


def test_after_a_rewind_splice_the_roll_is_the_one_passed_on() -> None:
    """The laminator's rewind spliced at 2 s from a 0.3 m roll onto a new 0.16 m core: the
    roll is the finished one (as on a chain), its surface at the radius it had at the
    splice, the layers the run wound all wound before it."""
    import copy
    import tomllib
    from importlib import resources

    from webline.model.web_graph import load_branched

    data = tomllib.loads(resources.files("webline.data.lines").joinpath("laminator.toml")
                         .read_text("utf-8"))
    data = copy.deepcopy(data)
    data.pop("scenarios", None)
    rewind = data["rollers"][6]
    rewind |= {"radius": "0.3 m", "roll_stress": {"k1": "5 kPa", "k2": 100}}
    data["disturbances"] = [{"type": "flying_splice", "roll": "rewind", "at": "2 s",
                             "new_diameter": "0.16 m"}]
    result = webline.simulate(load_branched(data), 3.0)
    radius = result.dataset["radius"].sel(roll="rewind/laminate").values
    j = int(np.searchsorted(result.time, 2.0 - 1e-9))
    assert radius[j] == pytest.approx(0.08)  # the new core on the shaft
    roll = result.wound_roll
    assert roll.stress.radius[0] == pytest.approx(0.0762)  # the old roll's core
    assert roll.stress.outer_radius == pytest.approx(radius[j - 1], abs=32e-6)
    # 2 s at 150 m/min wind 5 m: 5 m x 32 um / (2 pi 0.3 m) = 2.7 layers, before the splice
    wound = roll.layers.time[roll.layers.in_run]
    assert 2 <= wound.size <= 3 and wound.max() < 2.0


def test_a_differential_shafts_lanes_wind_at_slip_torque_over_radius() -> None:
    """Lanes on a differential (slip) shaft have no set tension: each is held at Q / R by
    its clutch (docs/branching.md, "Differential shafts"), so its steady roll winds the
    layers the run did not at Q / r (a hyperbolic taper of the slip), and the run's layers
    at their recorded tension, Q / R within 3 % (the cores' acceleration and drag)."""
    q = 8.0  # [N·m]: 100 N at the lanes' starting radius of 80 mm
    line = webline.load_line("slitter").replace({
        "rollers.rewind_shaft.shaft": {"type": "differential", "slip_torque": f"{q} N*m",
                                       "overspeed": 0.02, "core_inertia": "0.005 kg*m**2"},
        "rollers.rewind_shaft.roll_stress": TABLE,
    })
    roll = webline.simulate(line, 2.0).wound_rolls["rewind_shaft/lane_1"]
    lay = roll.layers
    out = ~lay.in_run
    np.testing.assert_allclose(lay.tension[out], q / lay.radius[out], rtol=1e-12)
    np.testing.assert_allclose(lay.tension[lay.in_run], q / lay.radius[lay.in_run], rtol=0.03)
    # Q / r falls outwards: the steady roll's outer layers are wound softer than its inner
    assert roll.steady.wound_on[-1] == pytest.approx(q / 0.15 / (WIDTH * H), rel=1e-3)


def test_a_narrower_lane_winds_at_its_own_width() -> None:
    """lane_3 slit 300 mm wide at the same 100 N: its wound-on stress is T / (w h) over its
    own width, 4/3 of the 400 mm lanes', and so is its outer layer's pressure."""
    line = webline.load_line("slitter").replace({
        "rollers.rewind_shaft.roll_stress": TABLE, "rollers.rewind_3.roll_stress": TABLE,
        "webs.lane_3.width": "300 mm",
    })
    rolls = webline.simulate(line, 1.0).wound_rolls
    narrow, wide = rolls["rewind_3/lane_3"], rolls["rewind_shaft/lane_1"]
    out = ~narrow.layers.in_run
    np.testing.assert_allclose(narrow.layers.stress[out], 100.0 / (0.3 * H), rtol=1e-12)
    assert narrow.stress.pressure[-1] / wide.stress.pressure[-1] == pytest.approx(4 / 3,
                                                                                  rel=1e-12)
    assert np.all(narrow.stress.pressure > wide.stress.pressure)
