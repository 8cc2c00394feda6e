"""Web breaks on a branched line (docs/branching.md, "Web breaks"): what a break cuts on a web
tree, the monitor, the stop ramp and the hold after it, and the verdict."""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.optimize import curve_fit

import webline
from webline.errors import LineFileError
from webline.model.web_graph import BranchedLine, load_branched
from webline.sim.branches.disturb import broken_segment
from webline.sim.branches.loop import layout as B

AT, STOP = 1.0, 5.0  # the break [s] and the stop ramp [s]
#: the slitter's full unwind (J = 1 + 69.8 kg·m², ω = 12.5 rad/s) needs J ω / T to stop in T
#: on top of the r T = 120 N·m its web pulls it with: within its 400 N·m from T = 3.2 s on
#: (a 2 s stop saturates it and slackens the base web), so the lane break stops in 5 s


def _with_break(name: str, brk: dict, duration: float, **scenario: object) -> BranchedLine:
    """``name`` with a scenario "b" of the break ``brk``, held at zero speed unless it says
    (the hold these tests derive; the default stall hold: test_stall_tension)."""
    data = load_branched(name).spec.model_dump(exclude_none=True)
    brk = {"hold": "zero_speed", **brk}
    data["scenarios"] = {"b": {"duration": duration, "break": brk, **scenario}}
    return load_branched(data)


@pytest.fixture(scope="module")
def lane_break():
    """The slitter, lane_1 (on the shaft it shares with lane_2) broken at 1 s."""
    line = _with_break("slitter", {"span": "lane_1_span", "at": AT, "stop_time": STOP}, 9.0)
    return webline.simulate(line, scenario="b")


def test_a_break_cuts_the_spans_between_the_rollers_that_grip_the_web():
    """Idle rollers pass the free end on; driven rollers and rolls grip it. A lane's end
    stops at the slitter (the base web carries the other lanes), a base web's runs into
    every lane, a layer's stops at the nip (the other layer carries the laminate)."""
    def names(line, span):
        line = load_branched(line)
        k = next(s.index for s in line.spans if s.name == span)
        return [line.spans[m].name for m in broken_segment(line, k)]

    assert names("slitter", "lane_1_span") == ["lane_1_span"]
    assert names("slitter", "knife_span") == ["knife_span", "lane_1_span", "lane_2_span",
                                              "lane_3_span"]
    assert names("slitter", "base[0]") == ["base[0]", "unwind_zone"]  # through the guide
    assert names("laminator", "foil_zone") == ["foil[0]", "foil_zone"]
    assert names("laminator", "laminate[1]") == ["laminate_zone", "laminate[1]"]
    # an idle nip (the roller after it the master): the laminate's free end runs back
    # through it into both layers; a layer's still stops at the nip
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    rollers = {r["name"]: r for r in data["rollers"]}
    data["rollers"] = [
        {"name": "nip", "type": "idle", "radius": 0.1, "inertia": 0.01} if r["name"] == "nip"
        else {**rollers["nip"], "name": "guide_laminate", "radius": 0.05}
        if r["name"] == "guide_laminate" else r for r in data["rollers"]]
    data["webs"][2]["spans"][0].pop("tension")
    data["webs"][2]["spans"][1]["tension"] = "180 N"
    assert names(data, "laminate_zone") == ["film[0]", "film_zone", "foil[0]", "foil_zone",
                                            "laminate_zone"]
    assert names(data, "foil_zone") == ["foil[0]", "foil_zone"]
    # a base web's only lane: its free end runs back through the idle slitter
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    data["webs"] = data["webs"][:2]
    data["rollers"] = [r for r in data["rollers"] if r["name"] != "rewind_3"]
    assert names(data, "lane_1_span") == ["knife_span", "lane_1_span"]


def test_a_lane_break_is_detected_in_the_sample_it_happens(lane_break):
    """The cut zone carries nothing from the break on (its release wave crosses the 2 m span
    at c = sqrt(E/ρ) = 1.8 km/s in 1.1 ms, which the model makes instantaneous), so lane_1's
    loadcell reads 0 < 0.2 x 100 N at the first 1 kHz sample at or after the break."""
    settings = lane_break.settings
    assert 0.0 <= settings["break_detected_s"] - AT <= lane_break.plan.dt
    assert settings["break_method"] == B.BREAK_TENSION
    line = lane_break.plan.line
    assert line.spans[int(settings["break_where"])].name == "lane_1_span"
    ds = lane_break.dataset
    after = ds.time.values >= AT
    assert np.all(ds.tension.sel(span="lane_1_span").values[after] == 0.0)


def test_the_line_ramps_to_a_stop_and_holds_zero_speed(lane_break):
    """Speed reference v s(t), s from 1 to 0 in the stop time: the master (pull) follows it
    within a·2/ω_s = (5 m/s / 5 s)·(2 / 40 rad/s) = 0.05 m/s (a critically damped 40 rad/s
    speed loop lags a ramp by about 2/ω_s). From the stop every roller's surface speed is
    within that of 0, and 1 s later (e^-40 of it) every driven roller is below 1e-4 m/s.
    The idle guide and slitter ring on (about 1.5 mm/s, a few µm, at their span modes):
    at rest the transport damping is gone and bearing friction alone damps them
    (docs/branching.md, "At rest"); they do not grow: nothing runs away."""
    ds = lane_break.dataset
    t = ds.time.values
    detected = lane_break.settings["break_detected_s"]
    ramp = (t >= detected) & (t <= detected + STOP)
    reference = 5.0 * (1.0 - (t[ramp] - detected) / STOP)
    lag = (5.0 / STOP) * 2.0 / 40.0
    assert np.max(np.abs(ds.speed.sel(node="pull").values[ramp] - reference)) < lag
    speed = np.abs(ds.speed.values)
    assert np.max(speed[t >= detected + STOP]) < lag
    driven = [list(ds.node.values).index(n) for n in ("unwind", "pull", "rewind_shaft",
                                                       "rewind_3")]
    assert np.max(speed[t >= detected + STOP + 1.0][:, driven]) < 1e-4
    first, last = (t >= detected + STOP + 1.0) & (t < detected + STOP + 1.5), t >= t[-1] - 0.5
    # (two lightly damped modes beat: measured up to 3.5 % above the first window's peak)
    assert np.all(np.max(speed[last], axis=0) <= 1.05 * np.max(speed[first], axis=0))
    assert lane_break.failure is None


def test_the_other_lane_on_the_shaft_stays_within_its_bound_until_the_stop(lane_break):
    """lane_2 shares the shaft with the broken lane_1; lane_3, on its own identical rewind,
    sees the same stop. What lane_2 has more: the shaft loses lane_1's load r T_1 = 8 N·m;
    its speed PI takes it up in its integrator, so the shaft's surface runs ahead by
    ∫Δv dt = r T_1 / k_i,s, stretching lane_2 by at most (EA_2 / L) r T_1 / k_i,s = 57.6 N
    (no transport relaxation, no give at the slitter: an upper bound; measured 33.8 N).
    So until the stop lane_2 stays between its tension at the break and that bound above
    lane_3's own excursion, and lane_1's loss only ever raises it."""
    plan, ds = lane_break.plan, lane_break.dataset
    t = ds.time.values
    stop = lane_break.settings["break_detected_s"] + STOP
    window = (t >= AT) & (t <= stop)
    before = np.searchsorted(t, AT) - 1
    lane_2 = ds.tension.sel(span="lane_2_span").values
    lane_3 = ds.tension.sel(span="lane_3_span").values
    excess_2 = lane_2[window] - lane_2[before]
    excess_3 = lane_3[window] - lane_3[before]
    k2 = next(s.index for s in plan.line.spans if s.name == "lane_2_span")
    shaft = list(ds.drive.values).index("rewind_shaft")
    bound = (plan.sf[k2, B.SF_EA] / plan.sf[k2, B.SF_LENGTH] * 0.08 * 100.0
             / plan.df[shaft, B.D_KIS])
    assert bound == pytest.approx(57.57, abs=0.01)
    assert np.max(excess_2 - excess_3) <= bound
    assert np.max(excess_2 - excess_3) > 0.5 * bound  # the lost load shows (0.59 x bound)
    assert np.min(excess_2 - excess_3) > -1e-3
    assert np.max(excess_2) <= np.max(excess_3) + bound


def test_the_web_length_balance_holds_across_the_cut(lane_break):
    """Once cut, Σ_intact L/(1 + x/EA) + out - in is conserved per web (the broken span's
    web no longer counts, what crosses the cut ends is counted where it leaves or joins the
    intact web; the broken span's frozen stretch keeps its content at L): the balance of
    every web, counting all its spans, is constant before the break and after it, to
    rounding (< 1e-9 m; it jumps at the break by the broken span's L ε/(1 + ε), the stretch
    let go: exact transport, docs/errata.md E-6.6)."""
    ds = lane_break.dataset
    t = ds.time.values
    balance = ds.web_stored.values + ds.web_out.values - ds.web_in.values
    assert np.all(np.ptp(balance[t < AT], axis=0) < 1e-9)
    assert np.all(np.ptp(balance[t > AT], axis=0) < 1e-9)  # (measured 3e-13 m over 8 s)
    eps = 100.0 / 90e3
    jump = 2.0 * eps / (1.0 + eps)  # lane_1's L ε/(1 + ε) let go: 2.2 mm, which is no drift
    assert np.ptp(balance[:, 1]) == pytest.approx(jump, rel=1e-3)
    assert all(row["length_balance_drift_m"] < 1e-9 for row in lane_break.web_summary())


def test_the_verdict_says_what_the_run_shows(lane_break):
    findings = [f for f in lane_break.verdict.findings if f.kind == "web_break"]
    assert [f.where for f in findings] == ["lane_1"]
    message = findings[0].message
    assert "web break in lane_1_span at t = 1 s detected by tension below its threshold " \
           "(loadcell lane_1_span) after 0 ms" in message
    assert "stopped by t = 6 s, the drives holding zero speed" in message
    assert findings[0].level == "warning"
    assert not [f for f in lane_break.verdict.findings if f.kind == "slack"]  # (cut, not slack)


def test_the_report_draws_the_reference_the_drives_had(lane_break):
    """After the detection the line-speed reference is the stop ramp, not the profile: the
    report's speed caption measures the master against that (0.0102 m/s; against the 5 m/s
    profile it would say 5 m/s)."""
    from webline.report.plots.branch_figures import profile_values, speeds_caption

    reference = profile_values(lane_break, 0)
    t = lane_break.time
    assert reference[-1] == 0.0 and reference[np.searchsorted(t, AT) - 1] == 5.0
    within = float(re.search(r"follows the reference within ([0-9.e-]+) m/s",
                             speeds_caption(lane_break)).group(1))
    assert within < 0.05  # the ramp-following bound a·2/ω_s above


def test_a_foil_break_drops_the_laminate_by_the_foils_share():
    """The foil breaks before the nip; the monitor is off (threshold 0, no diameter check)
    and the rewind holds speed only (tension gains 0), so the laminate zone settles where
    (B1) puts it at its speeds: T = s_in v_a / v_b with s_in the film's tension alone (B2,
    one term less), i.e. it drops by T_foil v_a / v_b (v_a = v_b: no draw across the nip).
    Against the same run without the break (which removes the common drift of the rewind's
    growing roll) the drop settles exponentially (a slow mode: the speed PIs' integrators
    follow the falling load) and its fitted end value is T_foil within 1 %: the rewind's PI
    follows its roll's load ramp T ṙ with a speed error T ṙ / k_i, which the 60 N less
    changes by 60 ṙ / k_i (ṙ = h v / 2π r = 0.16 mm/s), EA_L 60 ṙ / (k_i v) = 0.47 N."""
    speed_only = {"rollers.rewind.controller.tension_kp": 0.0,
                  "rollers.rewind.controller.tension_ki": 0.0}
    line = _with_break("laminator", {"span": "foil_zone", "at": AT, "threshold": 0.0,
                                     "diameter_threshold": 0.0}, 40.0, set=speed_only)
    broken = webline.simulate(line, scenario="b", raise_on_failure=False)
    data = line.spec.model_dump(exclude_none=True)
    data["scenarios"] = {"n": {"duration": 40.0, "set": speed_only}}
    intact = webline.simulate(load_branched(data), scenario="n")
    t = broken.time
    drop = (broken.dataset.tension.sel(span="laminate_zone").values
            - intact.dataset.tension.sel(span="laminate_zone").values)
    foil = intact.dataset.tension.sel(span="foil_zone").values[np.searchsorted(t, AT) - 1]
    late = t >= 4.0
    (end, _, tau), _ = curve_fit(lambda s, d, a, tau: d + a * np.exp(-(s - 4.0) / tau),
                                 t[late], drop[late], p0=(-foil, 20.0, 8.0))
    assert end == pytest.approx(-foil, rel=0.01)
    assert 2.0 < tau < 20.0  # slow, as the speed loops' integrators make it
    # the foil's guide, idle in the cut, turns free: it coasts down on its bearing friction
    # alone, v = v_0 e^(-(t - at) b / J) (b = 1e-4 N·m·s, J = 0.002 kg·m²: 20 s)
    guide = broken.dataset.speed.sel(node="guide_foil").values
    at = np.searchsorted(t, AT)
    coast = guide[at] * np.exp(-(t[at:] - t[at]) * 1e-4 / 0.002)
    assert np.max(np.abs(guide[at:] / coast - 1.0)) < 1e-6  # (measured 7e-15)
    film = broken.dataset.tension.sel(span="film_zone").values
    assert np.max(np.abs(film[t > 5.0] - 120.0)) < 0.5  # the film zone is held on
    verdict = broken.verdict
    assert verdict.status == "failed"
    assert "web break in foil_zone at t = 1 s not detected by the end of the run" in (
        verdict.headline)


def test_a_base_web_break_cuts_every_lane():
    """The knife span breaks: the free end runs through the idle slitter into every lane
    (each loses its feed), one finding per web and lane it cuts; the run ends mid-ramp."""
    line = _with_break("slitter", {"span": "knife_span", "at": 0.5, "stop_time": STOP}, 1.0)
    result = webline.simulate(line, scenario="b")
    findings = [f for f in result.verdict.findings if f.kind == "web_break"]
    assert [f.where for f in findings] == ["base", "lane_1", "lane_2", "lane_3"]
    assert "still ramping down at the end of the run" in findings[0].message
    t = result.time
    assert np.all(result.dataset.tension.values[t >= 0.5][:, 2:] == 0.0)
    # the pull roll grips the base web: before it the web is intact and taut (it dips to
    # 148 N as the pull roll, freed of the knife span's 30 N·m forward pull, slows)
    assert np.min(result.dataset.tension.sel(span="unwind_zone").values) > 100.0


def test_a_freed_rewind_is_found_by_its_diameter_running_the_wrong_way():
    """lane_3's rewind with a speed-ratio calculator (R = v_line / ω, 0.2 s filter), the
    tension monitor off (threshold 0), lane_3 broken at 1 s. Its loadcell reads 0, so its
    tension PI speeds it up by k_p,T T_ref = 0.036 m/s at once and k_i,T T_ref = 0.14 m/s
    per second; R_raw = R v / (v + Δv) shrinks, and 5 mm of diameter (Δv / v = 3.1 %,
    0.155 m/s) is reached by the PI alone within (0.155 - 0.036) / 0.14 = 0.84 s, plus the
    filter's 0.2 s: within 1.04 s (measured 485 ms: the freed roll's lost load r T = 8 N·m
    speeds it up too). The drives then switch off at the stop (``hold = "off"``)."""
    line = load_branched(_slitter_with([]))
    data = line.spec.model_dump(exclude_none=True)
    for roller in data["rollers"]:
        if roller["name"] == "rewind_3":
            roller["diameter"] = {"method": "speed_ratio", "line_speed": "reference"}
    data["scenarios"] = {"b": {"duration": 7.0, "break": {
        "span": "lane_3_span", "at": AT, "threshold": 0.0, "stop_time": STOP,
        "hold": "off"}}}
    result = webline.simulate(load_branched(data), scenario="b")
    settings = result.settings
    assert settings["break_method"] == B.BREAK_DIAMETER
    drives = list(result.dataset.drive.values)
    assert drives[int(settings["break_where"])] == "rewind_3"
    assert 0.05 < settings["break_detected_s"] - AT < 1.04
    t = result.time
    stopped = t >= settings["break_detected_s"] + STOP + result.plan.dt
    assert np.all(result.dataset.torque_cmd.values[stopped] == 0.0)
    message = next(f.message for f in result.verdict.findings if f.kind == "web_break")
    assert "detected by the calculated diameter running the wrong way (drive rewind_3)" in (
        message)
    assert "the drives with their torque off" in message


def test_the_brakes_hold_the_line_after_the_stop():
    """``hold = "brakes"``: torque off and each driven roller's brake (its torque limit x
    ratio) set at the end of the ramp: static friction at rest (the unwind, held by its
    intact zone's 300 N at 0.4 m, 120 N·m of 400 N·m, does not turn: it crept at 3.4 mm/s
    under the smoothed Coulomb brake before issue 35). So half a second after the stop every
    driven roller is below 0.02 m/s, the verdict says stopped, every torque command is 0."""
    line = _with_break("slitter", {"span": "lane_1_span", "at": AT, "stop_time": STOP,
                                   "hold": "brakes"}, 8.0)
    result = webline.simulate(line, scenario="b")
    t = result.time
    stop = result.settings["break_detected_s"] + STOP
    after = t >= stop + result.plan.dt
    assert np.all(result.dataset.torque_cmd.values[after] == 0.0)
    driven = [result.plan.line.spec.rollers[i].name for i in result.plan.line.drives]
    speed = np.abs(result.dataset.speed.sel(node=driven).values[after])
    assert np.max(speed[t[after] >= stop + 0.5]) < 0.02  # the unwind's creep and less
    message = next(f.message for f in result.verdict.findings if f.kind == "web_break")
    assert "stopped by t = 6 s, the drives with their torque off and brakes set" in message


def test_a_web_break_disturbance_is_the_scenarios_break():
    brk = {"span": "lane_1_span", "at": 0.2, "stop_time": 1.0}
    by_scenario = webline.simulate(_with_break("slitter", brk, 0.5), scenario="b")
    line = load_branched(_slitter_with([{"type": "web_break", **brk}]))
    by_disturbance = webline.simulate(line, 0.5)
    assert np.array_equal(by_scenario.rec, by_disturbance.rec)
    assert by_scenario.verdict.headline == by_disturbance.verdict.headline


def _slitter_with(disturbances: list[dict], scenario: dict | None = None) -> dict:
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    data["disturbances"] = disturbances
    if scenario is not None:
        data["scenarios"] = {"b": {"duration": 1.0, **scenario}}
    return data


BREAK = {"type": "web_break", "span": "lane_1_span", "at": 1.0}


@pytest.mark.parametrize("disturbances, scenario, key, problem", [
    ([{**BREAK, "span": "lane_9"}], None, "disturbances[0].span", "no span named 'lane_9'"),
    ([{**BREAK, "hold": "hands"}], None, "disturbances[0].hold", ""),
    ([BREAK, BREAK], None, "disturbances[1]", "one web_break per run"),
    ([], {"break": {"span": "nowhere", "at": 1.0}}, "scenarios.b.break.span",
     "no span named 'nowhere'"),
    ([BREAK], {"break": {"span": "lane_2_span", "at": 1.0}}, "scenarios.b.break",
     "one web break per run"),
    ([{**BREAK, "stop_time": "0 s"}], None, "disturbances[0].stop_time", "must be > 0"),
    ([{**BREAK, "threshold": 1.5}], None, "disturbances[0].threshold", ""),
])
def test_a_bad_break_is_one_line_naming_its_key(disturbances, scenario, key, problem):
    with pytest.raises(LineFileError, match=re.escape(key) + ".*" + re.escape(problem)):
        load_branched(_slitter_with(disturbances, scenario))
