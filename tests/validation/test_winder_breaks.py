"""Breaks that end at rest (issue 21, item 1; docs/winder.md W5-W7): the open-loop winder's
speed limiter, detection by overspeed, the drives' hold after the stop and the verdict's
"stopped"."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.sim.elements import layout as L

#: after the stop every driven roller must stay below this fraction of line speed (issue 21)
REST = 0.02


def _after_stop(result) -> tuple[np.ndarray, float]:
    """Surface speeds [m/s] of the driven rollers from the end of the stop ramp on, and the
    line speed [m/s] at the break (the speed reference's value before the stop)."""
    brk = next(d for d in result.line.spec.disturbances if d.type == "web_break")
    detected, _ = result.break_monitor
    after = result.time >= detected + brk.stop_time
    assert after.sum() > 100  # the run goes on well past the stop
    line_speed = float(np.abs(result.speed_feedforward[result.time < brk.at]).max())
    return result.surface_speed[after][:, list(result.line.drives)], line_speed


def test_converter_web_break_ends_at_rest():
    """Today, after the stop every torque is off and the intact zones' tension and the
    air-loaded dancer pull web off the rolls: rollers run at 20-40 % of line speed for good.
    The drives now hold zero speed: every driven roller below 2 % of line speed (measured
    0.4 %: the speed loops' lag behind the ramp at the stop)."""
    result = webline.simulate(webline.load_line("converter"), scenario="web-break")
    speeds, line_speed = _after_stop(result)
    assert np.abs(speeds).max() < REST * line_speed
    finding = next(f for f in result.verdict.findings if f.kind == "web_break")
    assert "stopped" in finding.message
    fastest = finding.details["largest_driven_speed_after_stop_m_per_s"]
    assert fastest == pytest.approx(np.abs(speeds).max(), rel=1e-9)


def test_rockwell_web_break_comes_to_rest_or_names_the_roller():
    """rockwell's soft 10 rad/s speed loops hold the intact rewind zone (tension doubled
    during the stop) with a slow swing after it: the verdict may not say "stopped" then,
    but names the roller and its speed; the rollers are at rest by the end (today 9 % of
    line speed for good)."""
    result = webline.simulate(webline.load_line("rockwell"), scenario="web-break")
    speeds, line_speed = _after_stop(result)
    finding = next(f for f in result.verdict.findings if f.kind == "web_break")
    peak = np.abs(speeds).max(axis=0)
    if peak.max() < REST * line_speed:
        assert "stopped" in finding.message
    else:
        name = result.drive_names[int(np.argmax(peak))]
        assert "stopped" not in finding.message and name in finding.message
        assert f"{peak.max():.3g} m/s" in finding.message
    last = result.time[-len(speeds):] > result.time[-1] - 2.0
    assert np.abs(speeds[last]).max() < REST * line_speed  # the last 2 s at rest


def test_with_torque_off_the_verdict_names_the_roller_that_moves():
    """``hold = "off"`` (the old reaction): the converter's rollers run on after the stop,
    so the finding must not say "stopped": it names the fastest driven roller and its speed."""
    line = webline.load_line("converter").with_scenario("web-break")
    line = line.replace({"disturbances.0.hold": "off"})
    result = webline.simulate(line, 12.0)
    speeds, line_speed = _after_stop(result)
    worst = int(np.argmax(np.abs(speeds).max(axis=0)))
    name = result.drive_names[worst]
    assert np.abs(speeds).max() > 0.05 * line_speed  # it does move (measured 0.3 of 5 m/s)
    finding = next(f for f in result.verdict.findings if f.kind == "web_break")
    assert "stopped" not in finding.message and "did not come to rest" in finding.message
    assert name in finding.message
    assert finding.details["fastest_after_stop"] == name


def test_brakes_hold_the_rollers_after_the_stop():
    line = webline.load_line("converter").with_scenario("web-break")
    line = line.replace({"disturbances.0.hold": "brakes"})
    result = webline.simulate(line, 12.0)
    speeds, line_speed = _after_stop(result)
    # a set brake is static friction of the drive's torque limit at rest: held below it, the
    # roller does not turn (tests/validation/test_brakes_hold.py)
    assert np.abs(speeds).max() < REST * line_speed
    brk = next(d for d in line.spec.disturbances if d.type == "web_break")
    held = result.time >= result.break_monitor[0] + brk.stop_time
    assert np.all(result.torque_cmd[held] == 0.0)  # motors off, brakes on


def _open_loop_rockwell(**monitor) -> webline.Line:
    """rockwell with an open-loop (indirect tension) rewind whose zone breaks at 2 s."""
    line = webline.load_line("rockwell")
    return line.replace({
        "rollers.rewind.winder": {"mode": "open_loop", "inertia_compensation": True,
                                  "viscous_friction": line.rewind.friction},
        "disturbances": [{"type": "web_break", "span": "rewind_span_b", "at": 2.0,
                          "stop_time": 2.0, **monitor}]})


def test_open_loop_rewind_freed_by_a_break_stays_below_110_percent_of_line_speed():
    """Today the freed rewind keeps its tension torque T R / n with no web to take it and
    reaches 150-165 % of line speed by the end of the stop. The speed limiter (line
    reference + 5 % of line speed by default) bounds it."""
    line = _open_loop_rockwell()
    result = webline.simulate(line, 10.0)
    line_speed = line.spec.speed
    rewind = result.surface_speed[:, -1]
    assert rewind.max() < 1.10 * line_speed  # measured 1.068
    # and it comes to rest under zero-speed control: the rewind's speed PI, detuned for its
    # motor encoder across the belt (k_p 11 N s, k_i 56 N on a 1.24 kg m² roll: 2 rad/s,
    # zeta 0.2), rings down over seconds (measured 2.3 % at 6 s, 0.6 % from 9 s)
    assert np.abs(rewind[result.time > 9.0]).max() < REST * line_speed


def test_overspeed_of_a_freed_roll_detects_the_break():
    """With no loadcell read (open loop) and the diameter monitor off, the freed rewind
    reaches its speed limit: the monitor calls that a break."""
    line = _open_loop_rockwell(diameter_threshold=0.0)
    result = webline.simulate(line, 3.0)
    detected, how = result.break_monitor
    assert how == L.BREAK_OVERSPEED
    # measured ~40 ms: the freed 29 lb ft² roll accelerates at T R / J to 5 % over line speed
    assert 0.0 < detected - 2.0 < 0.2
    finding = next(f for f in result.verdict.findings if f.kind == "web_break")
    assert "overspeed" in finding.details["method"]
    # the drives table's speed reference of the open-loop drive is its limiter's
    before = result.time < 2.0
    limit = line.spec.speed * (1.0 + 0.05)
    np.testing.assert_allclose(result.speed_feedforward[before, -1], limit, rtol=1e-9)


def test_drives_table_shows_the_open_loop_drives_limiter_reference():
    """The report's drives table (and summary.json) give an open-loop drive's speed
    reference as the limiter's, line speed + 5 % of it, and its error against it."""
    from webline.report.text.display import Display
    from webline.report.text.tables import summary_values

    line = _open_loop_rockwell()
    result = webline.simulate(line.replace(disturbances=[]), 1.0)
    values = summary_values(result, Display())
    rewind = values["drives"]["rewind"]  # type: ignore[index]
    assert rewind["mean_reference"] == pytest.approx(1.05 * line.spec.speed, rel=1e-9)
    # the web holds the roll at line speed: 5 % below the limit
    assert rewind["mean_error"] == pytest.approx(-0.05 * line.spec.speed, rel=0.01)


def test_frozen_trims_fall_with_the_line_speed_during_the_stop():
    """During the stop ramp each frozen tension trim is its value at the detection times the
    ramp's factor s(t) = 1 - (t - t_d)/T (so none is left at the stop to move a roller):
    trim / s is constant to rounding."""
    result = webline.simulate(webline.load_line("converter"), scenario="web-break")
    detected, _ = result.break_monitor
    ramp = (result.time > detected + 0.01) & (result.time < detected + 4.9)
    factor = 1.0 - (result.time[ramp] - detected) / 5.0
    trims = result.trim[ramp] / factor[:, None]
    moving = np.abs(trims[0]) > 1e-6  # the tension drives' trims (the drum has none)
    assert moving.sum() >= 2  # infeed and rewind (the others trim by < 1 µm/s)
    first = np.broadcast_to(trims[0, moving], trims[:, moving].shape)
    np.testing.assert_allclose(trims[:, moving], first, rtol=1e-9)
    after = result.time >= detected + 5.0
    assert np.all(result.trim[after] == 0.0)


def test_an_intact_open_loop_zone_holds_at_most_its_standstill_tension():
    """rockwell's unwind zone breaks; its open-loop rewind zone stays intact. Held at zero
    speed (``hold = "zero_speed"``, the hold before issue 35) with its torque limited to the
    standstill torque 0.5 T_ref R / n, the rewind pays out web while the zone pulls harder,
    and the zone ends taut at no more than 0.5 T_ref (measured 19.8 N of 22.2 N: the speed PI
    holds wherever the motion stops), at rest. The default stall hold holds 0.5 T_ref itself
    (tests/validation/test_stall_tension.py)."""
    line = _open_loop_rockwell()
    line = line.replace({"disturbances": [{"type": "web_break", "span": "dancer_span",
                                           "at": 2.0, "stop_time": 2.0,
                                           "hold": "zero_speed"}]})
    result = webline.simulate(line, 12.0)
    k = line.zones[-1].loadcell
    stall = 0.5 * result.tension_ref[0, k]
    end = result.time > 11.0
    # 1 %: the rewind's bearing friction (0.01 lbf ft s at rest: none) and the idler's
    assert np.all(result.tension[end, k] < 1.01 * stall)
    assert np.all(result.tension[end, k] > 0.5 * stall)  # taut, not slack
    assert np.abs(result.surface_speed[end][:, list(line.drives)]).max() < 0.01 * line.spec.speed
