"""One verdict per case (issue 22): the status and findings of each case of a sweep or Monte
Carlo study are those of ``simulate(case).verdict``, built by the same function, over every
built-in line and scenario and over faulted lines (web break, runaway, unstable controller,
empty roll, slack span)."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.report.sweep_report import status_table, worst_cases_table

#: simulated time of a case [s]: long enough for each fault below to show (the runaway leaves
#: the envelope in ~0.1 s, the almost empty roll empties at ~1.9 s, the slack comes 0.5 s in)
SHORT = 1.0
#: a run with a break goes on this long after it [s], so that its monitor has time to act
AFTER_BREAK = 0.6


def nominal_sweep(line: webline.Line, scenario: str | None, duration: float):
    """A one-case sweep of ``line`` (its unwind's bearing friction swept over its own value:
    the line itself), and that case's line as ``simulate`` runs it."""
    friction = line.spec.rollers[0].friction
    ds = webline.sweep(line, {"rollers.0.friction": [friction]}, scenario=scenario,
                       duration=duration, workers=1)
    case = line if scenario is None else line.with_scenario(scenario)
    return ds, [case.replace({"rollers.0.friction": friction})]


def assert_same_verdicts(ds, lines: list[webline.Line], duration: float) -> list[str]:
    """Each case's status and headline (the status and its first findings, in words) in
    ``ds`` are those of its ``simulate`` run; the statuses."""
    statuses = []
    for c, case in enumerate(lines):
        verdict = webline.simulate(case, duration, raise_on_failure=False).verdict
        assert str(ds.status.values[c]) == verdict.status, (case.name, c, verdict.headline)
        assert str(ds.headline.values[c]) == verdict.headline, (case.name, c)
        statuses.append(verdict.status)
    return statuses


def _scenarios() -> list[tuple[str, str | None]]:
    out: list[tuple[str, str | None]] = []
    for name in ("hswl", "rockwell", "converter"):
        out += [(name, None)] + [(name, s) for s in webline.load_line(name).spec.scenarios]
    return out


@pytest.mark.parametrize(("name", "scenario"), _scenarios())
def test_every_built_in_scenario_has_its_run_verdict_in_a_sweep(name, scenario) -> None:
    line = webline.load_line(name)
    duration = SHORT
    if scenario is not None:
        breaks = [d for d in line.with_scenario(scenario).spec.disturbances
                  if d.type == "web_break"]
        if breaks:  # the break and the monitor's answer to it are inside the run
            duration = breaks[0].at + AFTER_BREAK
    ds, lines = nominal_sweep(line, scenario, duration)
    statuses = assert_same_verdicts(ds, lines, duration)
    if scenario == "web-break":
        assert statuses == ["warning"]  # detected by its loadcell: a warning, never ok
        assert "web break in" in str(ds.headline.values[0])


def _rockwell_break(stiffness: float = 5000.0) -> webline.Line:
    """rockwell whose web breaks after the dancer at 0.3 s, with the tension monitor off and
    a spring of ``stiffness`` [N/m] on the dancer: a stiff one holds it off its end stops, so
    nothing detects the break (``test_winder.test_undetected_web_break_fails_the_run``)."""
    data = webline.load_line("rockwell").spec.model_dump(exclude_none=True)
    data["rollers"][1]["dancer"].update(travel=0.3, position=0.15, stiffness=stiffness)
    data["disturbances"] = [{"type": "web_break", "span": "dancer_span", "at": 0.3,
                             "stop_time": 1.0, "threshold": 0.0}]
    return webline.load_line(data)


def _faulted() -> dict[str, tuple[webline.Line, str]]:
    """Faulted lines and the status their run gives."""
    hswl = webline.load_line("hswl")
    rollers = [r.model_dump(exclude_none=True) for r in hswl.spec.rollers]
    belt = [dict(r) for r in rollers]
    belt[2] = {**belt[2], "drive": {**belt[2]["drive"], "transmission": {
        "type": "belt", "stiffness": 5e4, "load_pulley_radius": 0.05}, "motor_inertia": 0.05,
        "feedback": "load", "torque_limit": 20.0}}
    speed_drop = {"type": "steps", "initial": "500 ft/min",
                  "steps": [{"time": 0.5, "value": "150 ft/min"}]}
    return {
        "undetected break": (_rockwell_break(), "failed"),
        "runaway": (hswl.replace({"rollers.master.controller.speed_bandwidth": "5000 rad/s",
                                  "rollers.master.drive.torque_limit": 1e6}), "failed"),
        "unstable": (hswl.replace(rollers=belt), "unstable"),
        "empty roll": (hswl.replace({"rollers.unwind.radius": "3.005 in"}), "failed"),
        "slack": (hswl.replace(speed=speed_drop), "warning"),
    }


@pytest.mark.parametrize("fault", list(_faulted()))
def test_faulted_lines_have_their_run_verdict_in_a_sweep(fault) -> None:
    line, status = _faulted()[fault]
    duration = 2.0 if fault == "empty roll" else SHORT  # the roll empties at ~1.9 s
    ds, lines = nominal_sweep(line, None, duration)
    assert assert_same_verdicts(ds, lines, duration) == [status]


def test_a_monte_carlo_of_break_detection_counts_the_undetected_breaks() -> None:
    """The dancer's spring drawn from 0..2000 N/m: a soft one lets the carriage reach its
    stop (the break is detected, a warning), a stiff one holds it off (undetected: failed;
    the switch lies between 500 and 1000 N/m at 1 s after the break). Each case's status is
    its run's, and the report's verdict table counts them."""
    line = _rockwell_break()
    dists = {"rollers.dancer.dancer.stiffness": "uniform(0 N/m, 2000 N/m)"}
    n, duration = 8, 1.3
    ds = webline.monte_carlo(line, dists, n, seed=3, duration=duration, workers=1)
    cases = [line.replace({"rollers.dancer.dancer.stiffness": float(k)})
             for k in ds["rollers.dancer.dancer.stiffness"].values]
    statuses = assert_same_verdicts(ds, cases, duration)
    failed = statuses.count("failed")
    assert 0 < failed < n and set(statuses) == {"warning", "failed"}
    rows = {row[0]: row for row in status_table(ds).rows}
    assert rows["failed"][1] == str(failed) and rows["warning"][1] == str(n - failed)
    assert rows["unstable or failed"][1] == str(failed)
    assert np.all(["did not detect" in h for h, s in zip(ds.headline.values, statuses,
                                                         strict=True) if s == "failed"])
    # the report names the failed cases first, with what their runs say
    worst = worst_cases_table(ds)
    assert worst is not None and len(worst.rows) == n  # every case had a break finding
    assert [row[1] for row in worst.rows] == ["failed"] * failed + ["warning"] * (n - failed)
    first = int(worst.rows[0][0])
    assert worst.rows[0][2] == str(ds.headline.values[first]) and statuses[first] == "failed"


def _with_break(line: webline.Line, span: str, at: float) -> webline.Line:
    """``line`` whose web breaks in ``span`` at ``at`` [s], stopping in 1 s: the checks look
    up to the break, the break's finding after it (the stop and the rest)."""
    data = line.spec.model_dump(exclude_none=True)
    data["disturbances"] = [{"type": "web_break", "span": span, "at": at, "stop_time": 1.0}]
    return webline.load_line(data)


def _winder_state_lines() -> dict[str, tuple[webline.Line, float, str]]:
    """Lines whose runs have a winder-state finding (tests/validation/test_winder_states.py),
    the duration [s] that shows it and the finding's kind."""
    rockwell, hswl = webline.load_line("rockwell"), webline.load_line("hswl")
    open_loop = {"mode": "open_loop", "inertia_compensation": True,
                 "viscous_friction": rockwell.rewind.friction}
    return {
        "dancer on its end stop": (rockwell.replace({
            "rollers.dancer.dancer.use": "none", "rollers.dancer.dancer.load": "150 N"}), 4.0,
            "dancer_end_stop"),
        "open-loop zone off its set tension": (rockwell.replace({"rollers.rewind.winder": {
            **open_loop, "viscous_friction": rockwell.rewind.friction + 0.174}}), 5.0,
            "tension_off_set"),
        "measured zone off its set tension": (rockwell.replace({
            "rollers.rewind.drive.torque_limit": "3 N*m"}), 4.0, "tension_off_set"),
        "misjudged diameter": (hswl.replace({
            "rollers.rewind.taper": {"type": "linear", "taper": 0.5, "max_diameter": "0.5 m"},
            "rollers.rewind.diameter": {"method": "thickness",
                                        "initial": 2 * hswl.rewind.radius + 0.020}}), 3.0,
            "diameter_error"),
        "zone off its tapered, ramped set tension": (rockwell.replace({
            "rollers.rewind.winder": {
                **open_loop, "viscous_friction": rockwell.rewind.friction + 0.174},
            "rollers.rewind.taper": {"type": "linear", "taper": 0.3, "max_diameter": "0.5 m"},
            "control.tension_ramp": {"standstill": 0.3, "time": "3 s"},
            "speed": {"type": "ramp", "initial": "0 ft/min", "final": "300 ft/min",
                      "start": "0.5 s", "duration": "2 s"}}), 4.0,
            "tension_off_set"),
        "zone off its set tension, then a break in it": (_with_break(rockwell.replace({
            "rollers.rewind.drive.torque_limit": "3 N*m"}), "rewind_span_b", 2.5), 4.0,
            "tension_off_set"),
        "diameter guessed twice the true one": (rockwell.replace({
            "rollers.rewind.winder": open_loop, "rollers.rewind.diameter": {
                "method": "thickness", "initial": 4 * rockwell.rewind.radius}}), 5.0,
            "diameter_error"),
    }


@pytest.mark.parametrize("case", list(_winder_state_lines()))
def test_winder_state_findings_are_in_a_sweep_cases_verdict(case) -> None:
    """Today a batch misses the winder-state findings: the case says ok where its run
    warns of a dancer on its stop, a zone off its set tension, a misjudged diameter."""
    line, duration, kind = _winder_state_lines()[case]
    ds, lines = nominal_sweep(line, None, duration)
    assert_same_verdicts(ds, lines, duration)
    verdict = webline.simulate(lines[0], duration, raise_on_failure=False).verdict
    assert kind in {f.kind for f in verdict.findings}  # the case shows what it is for
    assert_same_findings(lines[0], duration)


def test_cases_of_one_batch_keep_their_own_winder_states() -> None:
    """rockwell's dancer as a store swept over its load, in one batch: 88 N (2 x the zone
    tension) holds the carriage off its stops, 150 N rests it on one from 1.4 s. Each case
    has its own run's verdict, so one case's slot never leaks into another's."""
    line = webline.load_line("rockwell").replace({"rollers.dancer.dancer.use": "none"})
    loads = ["88 N", "150 N"]
    duration = 4.0
    ds = webline.sweep(line, {"rollers.dancer.dancer.load": loads}, duration=duration,
                       workers=1)
    cases = [line.replace({"rollers.dancer.dancer.load": load}) for load in loads]
    assert_same_verdicts(ds, cases, duration)
    stops = ["end stop" in str(h) for h in ds.headline.values]
    assert stops == [False, True]


@pytest.mark.parametrize("name", ["rockwell", "converter"])
def test_a_full_length_web_break_has_its_run_verdict_in_a_sweep(name) -> None:
    """The whole web-break scenario (12 s: the stop and the rest after it): today a batch
    keeps no roller speeds, so its break finding says whether the rollers came to rest 'is
    not known' where the run's says they did (or which one did not, and from when)."""
    line = webline.load_line(name)
    duration = float(line.spec.scenarios["web-break"].duration)
    ds, lines = nominal_sweep(line, "web-break", duration)
    assert assert_same_verdicts(ds, lines, duration) == ["warning"]
    assert "not known" not in str(ds.headline.values[0])
    assert_same_findings(lines[0], duration)


def assert_same_findings(case: webline.Line, duration: float) -> None:
    """Every finding of ``case``'s batch verdict (``sweep_dataset.case_verdict``) has the
    level, kind, place, time and message of its run's, and the same details: numbers to
    1e-9 relative (the batch's compiled reduction and the run's numpy may round the last
    bits differently; a rounding of the printed 3-4 digits would already fail the message)."""
    from webline.sim.sweeps.batch import run_batch
    from webline.sim.sweeps.cases import build_cases
    from webline.sim.sweeps.sweep_dataset import case_verdict

    built = build_cases(case, [{}], duration)
    out = run_batch(built.plans, built.states, np.array(built.n_ticks),
                    np.array(built.substeps), np.array(built.every), workers=1)
    batch = case_verdict(built.plans[0], out, 0).findings
    run = webline.simulate(case, duration, raise_on_failure=False).verdict.findings
    assert [(f.level, f.kind, f.where, f.message) for f in batch] == [
        (f.level, f.kind, f.where, f.message) for f in run]
    for b, r in zip(batch, run, strict=True):
        assert (b.time is None) == (r.time is None)
        if r.time is not None:
            assert b.time == pytest.approx(r.time, rel=1e-9, nan_ok=True)
        assert b.details.keys() == r.details.keys(), b.kind
        for key, value in r.details.items():
            if isinstance(value, float):
                assert b.details[key] == pytest.approx(value, rel=1e-9, nan_ok=True), key
            else:
                assert b.details[key] == value, key
