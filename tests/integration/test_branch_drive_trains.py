"""Compliant transmissions and drive brakes on a branched line (docs/branching.md, "Drive
trains"): the chain's keys ``drive.transmission`` (belt, shaft, backlash) and ``drive.brake``
on the laminator's lamination nip."""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.loop.layout import DI_TSTATE
from webline.sim.branches.plan import compile_branches

J_MOTOR = 0.02  # kg·m²: the nip's motor rotor (the nip keeps 0.48 of its 0.5 kg·m²)
J_LOAD = 0.48  # kg·m²: the nip roll itself
KB, R2 = 1e5, 0.1  # N/m, m: belt tight side, load pulley: K = Kb r2² = 1000 N·m/rad
BAND = (150.0, 320.0)  # rad/s: the belt mode's neighbourhood, between the web's modes
# (the next line modes: 108 rad/s, the film guide roller on its spans at 389 rad/s)


def _laminator(transmission: dict | None = None, brake: object = None,
               **controller: object) -> dict:
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    nip = next(r for r in data["rollers"] if r["name"] == "nip")
    if transmission is not None:
        nip["inertia"] = J_LOAD
        nip["drive"].update(motor_inertia=J_MOTOR, transmission=transmission,
                            feedback="motor")
    if brake is not None:
        nip["drive"]["brake"] = brake
    nip["controller"].update(controller)
    return data


def _belt(**extra: object) -> dict:
    return {"type": "belt", "stiffness": KB, "load_pulley_radius": R2, **extra}


def _modes(data: dict, loop: str) -> np.ndarray:
    plan = compile_branches(load_branched(data))
    values = np.linalg.eigvals(branch_linear_model(plan, operating_point(plan), loop).a)
    return values[(values.imag > BAND[0]) & (values.imag < BAND[1])]


def _two_inertias(web_stiffness: float) -> float:
    """Belt mode [rad/s] of motor and nip on the belt's spring K = Kb r2² (thesis 2.10, torque
    mode: the motor free), the nip tied to ground by the web's stiffness."""
    k = KB * R2**2
    mass = np.diag([J_MOTOR, J_LOAD])
    spring = np.array([[k, -k], [-k, k + web_stiffness]])
    return float(np.sqrt(np.max(np.linalg.eigvals(np.linalg.solve(mass, spring)).real)))


def test_a_belt_on_the_nip_rings_where_two_inertias_on_a_spring_do():
    """The open-loop model's belt mode against the hand formula. The web ties the nip (r =
    0.1 m) to the rollers around it: each span adds r² EA/L. With the guide rollers held
    that is r² Σ EA/L over the nip's three 2 m spans (7335 N·m/rad); with the light guides
    (0.8 kg at their surface, 50 kg for the nip) moving with the web, the spans to the next
    roll in series (3.5 m: 4191 N·m/rad); without it, two free inertias. These bracket the
    mode (228.2, 229.5, 231.2 rad/s: the web moves it by 1.3 %); the model, which also has
    the guides' own inertia and the web's transport damping, must lie in the bracket and
    within 0.2 % (a sixth of the web's effect) of the series estimate."""
    r2_ea_l = 0.01 * np.array([103.5e3, 630e3, 733.5e3])  # film, foil, laminate: r² EA
    free, series, held = (_two_inertias(0.0), _two_inertias(float(np.sum(r2_ea_l / 3.5))),
                          _two_inertias(float(np.sum(r2_ea_l / 2.0))))
    modes = _modes(_laminator(_belt()), "open")
    assert len(modes) == 1
    omega = float(modes[0].imag)
    assert free < omega < held
    assert abs(omega - series) < 2e-3 * series, (omega, free, series, held)
    assert abs(modes[0].real) < 0.01 * omega  # undamped belt: only the web's damping


def test_the_layer_upset_rings_the_belt_at_the_linear_models_mode():
    """After the film zone's 30 N step the twist rate ω_m/n - ω_L rings at the closed-loop
    model's belt mode (a soft master speed loop on the motor, 1 and 10 N·m per m/s, leaves
    it lightly damped: ζ ≈ 0.01, so a 1 s window resolves it). Hann window, 64k-point
    spectrum: the peak is found to well under the 6.3 rad/s bin; 1 % covers that and the
    fixed-step integration (0.14 % of phase per period at 230 rad/s, 1 ms / 4)."""
    data = _laminator(_belt(), speed_kp=1.0, speed_ki=10.0)
    closed = _modes(data, "closed")
    assert len(closed) == 1 and closed[0].real < 0.0
    result = webline.simulate(load_branched(data), 3.0, scenario="layer-upset")
    assert result.failure is None
    ds = result.dataset
    t = ds.time.values
    rate = (ds.motor_omega.sel(drive="nip") - ds.omega.sel(node="nip")).values
    window = t >= 2.0
    y = rate[window] - np.polyval(np.polyfit(t[window], rate[window], 3), t[window])
    spectrum = np.abs(np.fft.rfft(y * np.hanning(len(y)), 1 << 16))
    omega = 2 * np.pi * np.fft.rfftfreq(1 << 16, t[1] - t[0])
    band = (omega > BAND[0]) & (omega < BAND[1])
    peak = float(omega[band][np.argmax(spectrum[band])])
    assert abs(peak - closed[0].imag) < 0.01 * closed[0].imag, (peak, closed)
    before = rate[(t > 1.0) & (t < 2.0)]
    assert np.ptp(before) < 1e-6  # the operating point: the belt still before the upset


GAP = 0.005  # rad at the load shaft: the nip may move ±Δ before the teeth touch


def test_backlash_opens_its_dead_zone_between_motor_and_nip_at_a_torque_reversal():
    """A slow-down (150 -> 30 m/min in 1 s) makes the nip's motor brake it: the transmitted
    torque T_s reverses. In contact, twist = θm/n - θL = T_s/K ± Δ (physics.backlash), with
    T_s = n (τ - J_m dω_m/dt) from the motor's own balance; so twist - T_s/K is +Δ while it
    drives and -Δ while it brakes: the motor-load angle difference jumps by the dead zone's
    width 2Δ beyond the spring's share. Tolerance 1 % of Δ (seen: 0.04 %): the recorded
    dω_m/dt is a 1 kHz central difference, J_m times its error over K is the rest."""
    data = _laminator(_belt(backlash={"gap": GAP}))
    data["speed"] = {"type": "ramp", "initial": "150 m/min", "final": "30 m/min",
                     "start": "0.5 s", "duration": "1 s"}
    result = webline.simulate(load_branched(data), 1.5)
    assert result.failure is None
    ds = result.dataset
    t = ds.time.values
    omega_m = ds.motor_omega.sel(drive="nip").values  # ratio 1
    torque = ds.torque.sel(drive="nip").values
    passed = torque - J_MOTOR * np.gradient(omega_m, t)
    offset = ds.twist.sel(drive="nip").values - passed / (KB * R2**2)
    driving, braking = (t > 0.2) & (t < 0.5), (t > 0.8) & (t < 1.5)
    assert np.all(passed[driving] > 0.5) and np.all(passed[braking] < -2.0)
    assert np.max(np.abs(offset[driving] - GAP)) < 0.01 * GAP
    assert np.max(np.abs(offset[braking] + GAP)) < 0.01 * GAP


def test_a_brake_on_the_nip_costs_its_motor_the_brake_torque():
    """drive.brake is a torque on the roller opposing its rotation (thesis 4.12), Coulomb-like
    as on a chain: at the operating point the nip's motor gives b tanh(ω/0.1 rad/s) more
    (ω = 25 rad/s: the full brake, to 1e-100), the other drives the same; and over a run
    (0.3 s, the rolls' radii drifting) the braked nip's motor gives the brake's 5 N·m more
    than the free one's at every record (to 1e-6 N·m: the operating points' solver)."""
    brake = 5.0
    for transmission in (None, _belt()):
        plain = compile_branches(load_branched(_laminator(transmission)))
        braked = compile_branches(load_branched(_laminator(transmission, brake=f"{brake} N*m")))
        free, held = operating_point(plain), operating_point(braked)
        omega = held.x[braked.offsets[0] + 4]
        expected = brake * math.tanh(omega / 0.1)
        assert held.torque[2] - free.torque[2] == pytest.approx(expected, rel=1e-7)
        others = [0, 1, 3]
        assert np.allclose(held.torque[others], free.torque[others], rtol=1e-7)
    runs = [webline.simulate(load_branched(_laminator(brake=b)), 0.3).dataset
            for b in (None, f"{brake} N*m")]
    extra = runs[1].torque.sel(drive="nip").values - runs[0].torque.sel(drive="nip").values
    assert np.max(np.abs(extra - brake)) < 1e-6


def test_a_direct_drive_has_no_twist_and_keeps_its_run():
    """A direct drive's motor is its roller: it has no transmission to twist (NaN, as a
    single-path run's rigid drive) and its motor speed is the roller's, bit for bit."""
    ds = webline.simulate(load_branched(_laminator(brake=None)), 0.05).dataset
    assert "motor_omega" not in ds  # no compliant drive: no load-side motor speed
    assert np.all(np.isnan(ds.twist.values)) and np.all(np.isnan(ds.contact.values))
    data = _laminator(_belt())
    ds = webline.simulate(load_branched(data), 0.05).dataset
    direct = [d for d in ds.drive.values if d != "nip"]
    assert np.all(np.isnan(ds.twist.sel(drive=direct).values))
    for d in direct:
        assert np.array_equal(ds.motor_omega.sel(drive=d).values, ds.omega.sel(node=d).values)


@pytest.mark.parametrize(("change", "key", "fragment"), [
    (lambda d: d["rollers"][4]["drive"].update(transmission=_belt()),
     "rollers[4].drive.motor_inertia", "needs the motor's inertia"),
    (lambda d: d["rollers"][4]["drive"].update(
        transmission={"type": "shaft", "stiffness": -5.0}, motor_inertia=0.01),
     "rollers[4].drive.transmission", ""),
    (lambda d: d["rollers"][4]["drive"].update(
        transmission=_belt(backlash={"gap": 0.01, "asymmetry": 1.5}), motor_inertia=0.01),
     "rollers[4].drive.transmission", ""),
    (lambda d: d["rollers"][0]["drive"].update(transmission=_belt(), motor_inertia=0.01),
     "scenarios.roll-change.roll_change.roller", "needs a direct drive on the roll"),
    (lambda d: d["rollers"][4]["drive"].update(brake="-3 N*m"), "rollers[4].drive.brake", ""),
    (lambda d: (d["rollers"][0]["drive"].update(transmission=_belt(), motor_inertia=0.01),
                d["scenarios"].pop("roll-change")),
     "scenarios.flying-splice.splice.roll", "a flying splice needs a direct drive"),
    (lambda d: (d["rollers"][4]["drive"].update(brake="3 N*m"), d.__setitem__(
        "disturbances", [{"type": "roller_drag", "roller": "nip", "torque": "1 N*m"}])),
     "disturbances[0].roller", "already has a drag or brake torque"),
])
def test_bad_drive_trains_are_refused_in_one_line(change, key, fragment):
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    data["scenarios"]["roll-change"]["roll_change"]["roller"] = data["rollers"][0]["name"]
    change(data)
    with pytest.raises(LineFileError) as info:
        load_branched(data)
    text = str(info.value)
    assert key in text and fragment in text and "\n" not in text.strip()


def test_the_cli_names_the_key_of_a_transmission_without_a_motor_inertia(tmp_path):
    from typer.testing import CliRunner

    from webline.cli import app

    text = resources.files("webline.data.lines").joinpath("laminator.toml").read_text("utf-8")
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(
        'drive = { ratio = 1.0, torque_limit = "100 N*m", torque_lag = "2 ms" }\ncontroller = '
        '{ type = "cascaded_pi", speed_bandwidth = "40 rad/s", damping = 1.0 }',
        'drive = { ratio = 1.0, torque_limit = "100 N*m", torque_lag = "2 ms", transmission = '
        '{ type = "shaft", stiffness = "500 N*m" } }\ncontroller = '
        '{ type = "cascaded_pi", speed_bandwidth = "40 rad/s", damping = 1.0 }', 1),
        encoding="utf-8")
    assert "shaft" in bad.read_text("utf-8")
    result = CliRunner().invoke(app, ["run", str(bad), "-o", str(tmp_path / "o")])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "rollers[4].drive.motor_inertia" in lines[0]
    assert "Traceback" not in result.output


def test_a_shaft_with_backlash_drives_the_slitters_three_lanes():
    """The slitter's rewind shaft (three lanes on one shaft) through a compliant shaft with
    backlash: at the operating point the twist carries the drive's steady torque less what
    the motor's deceleration takes (the lanes grow: at a held surface speed the shaft slows,
    dω/dt = -ω dR/dt / R = -h ω² / (2π R), 0.39 rad/s² here): twist = (n τ - n² J_m dω/dt) / k
    + Δ (to 1e-12 rad: the operating point's solver); a run from there holds each lane at
    its 100 N (to 0.5 N) with the teeth touching throughout. (Measured on the load, the
    auto-tuned speed PI destabilises the shaft's mode, as on a chain: thesis Sec. 2.4.)"""
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    shaft = next(r for r in data["rollers"] if r["name"] == "rewind_shaft")
    stiffness, gap = 2000.0, 0.002
    shaft["drive"].update(motor_inertia=0.05, feedback="motor", transmission={
        "type": "shaft", "stiffness": stiffness, "backlash": {"gap": gap}})
    line = load_branched(data)
    plan = compile_branches(line)
    point = operating_point(plan)
    d = line.drives.index(line.node_index["rewind_shaft"])
    twist = point.x[int(plan.di[d, DI_TSTATE]) + 1]
    i = line.node_index["rewind_shaft"]
    j = next(j for j, r in enumerate(line.rolls) if r.node == i)
    omega, radius = point.x[plan.offsets[0] + i], line.rolls[j].radius
    accel = -line.materials[line.rolls[j].web].thickness * omega**2 / (2 * np.pi * radius)
    assert twist == pytest.approx((point.torque[d] - 0.05 * accel) / stiffness + gap, abs=1e-12)
    modes = np.linalg.eigvals(branch_linear_model(plan, point, "closed").a)
    assert np.max(modes.real) < 0.0
    shaft["drive"]["feedback"] = "load"
    on_load = compile_branches(load_branched(data))
    modes = np.linalg.eigvals(branch_linear_model(on_load, operating_point(on_load)).a)
    assert np.max(modes.real) > 1.0
    ds = webline.simulate(line, 1.0).dataset
    lanes = ds.tension.sel(span=["lane_1_span", "lane_2_span", "lane_3_span"]).values
    assert np.max(np.abs(lanes - 100.0)) < 0.5
    assert np.all(ds.twist.sel(drive="rewind_shaft").values > gap)


def test_show_lists_a_branched_drives_transmission_and_brake():
    """The drives table of ``webline show`` and the report words a compliant drive as the
    chain's does; a line of direct drives keeps its table as it was."""
    from webline.report.text.branch_tables import line_tables

    def drives(data: dict) -> object:
        return next(t for t in line_tables(load_branched(data)) if t.key == "drives")

    plain = drives(_laminator())
    assert "transmission" not in plain.columns
    table = drives(_laminator(_belt(backlash={"gap": GAP}), brake="2 N*m"))
    row = dict(zip(table.columns, next(r for r in table.rows if r[0] == "nip"), strict=True))
    assert row["transmission"].startswith("belt") and row["speed measured on"] == "motor"
    assert row["backlash"] != "none" and row["brake"].startswith("2")
    other = dict(zip(table.columns, table.rows[0], strict=True))
    assert other["transmission"] == "direct" and other["brake"] == "none"


def test_a_belted_rewinds_inertia_compensation_still_counts_its_motor():
    """Inertia compensation (W3) accelerates everything the motor must: the roll, the rotating
    parts and the motor. Across a belt the motor's n² J_m is no longer in the roller's
    inertia, so the compensation adds it back: the torque it asks is the direct drive's
    (same parts, same motor), to round-off (1e-12 relative)."""
    from webline.sim.branches.loop.winder import compensation

    torques = []
    for transmission in (None, _belt()):
        data = load_branched("laminator").spec.model_dump(exclude_none=True)
        rewind = next(r for r in data["rollers"] if r["name"] == "rewind")
        rewind["winder"] = {"inertia_compensation": True}
        rewind["drive"]["motor_inertia"] = 0.05
        if transmission is not None:
            rewind["drive"].update(transmission=transmission, feedback="motor")
        plan = compile_branches(load_branched(data))
        d = plan.line.drives.index(plan.line.node_index["rewind"])
        i = plan.line.node_index["rewind"]
        torques.append(compensation(d, i, 0.08, 31.25, 0.25, plan.nodes, plan.rolls, plan.df,
                                    plan.prof_t, plan.prof_v, plan.prof_off))
    assert torques[0] > 0.0
    assert torques[1] == pytest.approx(torques[0], rel=1e-12)
