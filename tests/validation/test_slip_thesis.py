"""Web slip: the free span of thesis Sec. 5.8 (Table 5.1, Fig. 5.17) in the standalone
reference model, and what the slip model must show (issue 6). Parameters from
``webline/data/slip/free_span_sec5_8.toml``."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest

from webline.physics import slip as sl
from webline.studies import slip_example as se
from webline.studies.result import StudyResult
from webline.studies.slip_chain import (
    Chain,
    Contact,
    Roller,
    constant,
    initial_state,
    simulate_fixed,
    steady_state,
)

LBF = se.LBF
P = se.load_free_span()
PERIOD = 1.0 / P.frequency


def test_table_5_1_is_read_as_printed():
    assert P.ea / LBF == pytest.approx(40000.0)
    assert P.length == pytest.approx(10 * 0.3048)
    assert P.viscous == pytest.approx(2000 * LBF / 0.3048)
    assert P.wrap == pytest.approx(math.pi / 2)
    assert (P.mu, P.mu_k) == (0.1, 0.02)
    assert P.speed_after / P.speed_before == pytest.approx(1.001)
    assert (P.t1 / LBF, P.t2_initial / LBF, P.t3 / LBF) == pytest.approx((40.0, 42.0, 42.0))


def test_table_start_is_not_an_equilibrium_of_5_46():
    """(5.46) at t2 = 42 lbf, t1 = 40 lbf, equal roller speeds: L2 dt2/dt = v (t1 - t2) != 0;
    with no slip t2 relaxes to t1 with time constant L2/v (0.6 s); the printed (5.47) has its
    own equilibrium where -s = v (t2 - t1)/(EA - t2), s = (t2 (1 - p(1 - e^{-μα})) - t3)/b:
    (42 - 0.970927 t2)/2000 = (1000/60)(t2 - 40)/(40000 - t2), t2 = 41.752 lbf by hand."""
    run = se.run_case(P, slip="none", disturbance=False, how="table", duration=0.6)
    tau = P.length / P.speed_after
    k = round(tau / P.step)
    expected = P.t1 + (P.t2_initial - P.t1) * math.exp(-run.time[k] / tau)
    # (5.46) with v1 = v2 is linear: t2 - t1 decays exactly as e^{-vt/L}; RK4 at 1 ms: 1e-9 rel
    assert run.tension[k, 0] == pytest.approx(expected, rel=1e-9)
    printed = se.run_case(P, slip="printed", disturbance=False, how="equilibrium",
                          duration=0.01)
    assert printed.tension[0, 0] / LBF == pytest.approx(41.752, abs=1e-3)


def test_enough_friction_gives_exactly_the_no_slip_result():
    """With friction that holds every tension the disturbance brings, the slip model's t2 is
    the no-slip model's, bit for bit (a stuck roller returns s = 0.0 exactly)."""
    no_slip = se.run_case(P, slip="none", disturbance=True, duration=1.0)
    stuck = se.run_case(P, slip="webline", disturbance=True, duration=1.0, mu=1.0, mu_k=0.5)
    assert np.array_equal(stuck.tension, no_slip.tension)
    assert not stuck.state[:, 1].any()


def test_no_slip_span_ignores_the_downstream_tension():
    """(5.34): with no slip t2 does not depend on t3 — the dashed line of Fig. 5.17."""
    plain = se.run_case(P, slip="none", disturbance=False, duration=1.0)
    disturbed = se.run_case(P, slip="none", disturbance=True, duration=1.0)
    assert np.array_equal(plain.tension, disturbed.tension)


def test_upstream_response_to_a_downstream_disturbance_vanishes_as_friction_grows():
    """No stiction (μ0 = μ'): the 2 Hz disturbance in t3 moves the upstream tension t2 while
    the roller slips; the response falls as μ grows and is exactly zero once the capstan holds
    t3's extremes against t2 (``threshold_friction``: μα >= ln(47/40))."""
    threshold = se.threshold_friction(P)
    assert threshold == pytest.approx(math.log((47 * LBF - 0.77) / (40 * LBF - 0.77)) / P.wrap,
                                      rel=1e-3)
    rows = se.friction_sweep(P, [0.005, 0.02, 0.06, 0.1, 1.02 * threshold], duration=1.5)
    amplitudes = [r["t2_peak_to_peak_lbf"] for r in rows]
    assert amplitudes[0] > 0.5  # lbf: a clearly visible upstream response
    assert all(a > b for a, b in itertools.pairwise(amplitudes))
    assert amplitudes[-1] == 0.0
    assert rows[-1]["slip_fraction"] == 0.0


@pytest.mark.parametrize("disturbance", [False, True])
def test_second_law_holds_at_every_step(disturbance):
    """F·s >= 0 at every sample of every webline run (stiction, no stiction), and the printed
    (5.47) violates it in the disturbed case."""
    for kwargs in ({}, {"mu": 0.02, "mu_k": 0.02}, {"mu": 0.05, "mu_k": 0.01}):
        run = se.run_case(P, slip="webline", disturbance=disturbance, duration=1.0, **kwargs)
        assert run.power[:, 1].min() >= 0.0
        assert np.all(run.slip[:, 1] * (run.tension[:, 0] - P.t3 - (
            P.amplitude * np.sin(2 * np.pi * P.frequency * run.time) if disturbance else 0.0))
            >= 0.0)
    if disturbance:
        printed = se.run_case(P, slip="printed", disturbance=True, how="table", duration=1.0)
        assert printed.power[:, 1].min() < 0.0


def test_stick_slip_does_not_chatter_and_matches_the_event_located_reference():
    """Stiction with the 2 Hz disturbance (Table 5.1): the fixed-step path (state updated once
    per 1 ms tick) switches exactly as often as the reference that locates every switch, each
    switch within one tick of the reference's, and t2 differs by at most what the slip rate
    after a break-away builds in one tick (|ds| EA/L dt, ~0.01 lbf)."""
    fixed = se.run_case(P, slip="webline", disturbance=True, duration=1.5)
    ref = se.run_case(P, slip="webline", disturbance=True, duration=1.5, reference=True)
    assert fixed.switches[1] == ref.switches[1] >= 2
    shift = np.abs(np.array(fixed.switch_times[1]) - np.array(ref.switch_times[1]))
    assert shift.max() <= P.step
    jump = (sl.stiction_limit(P.t1, P.wrap, P.mu, 0.0, -1.0) * (1 - P.mu_k / P.mu)) / P.viscous
    bound = jump * P.ea / P.length * P.step
    assert np.abs(fixed.tension[:, 0] - ref.tension[:, 0]).max() <= bound
    # no chattering: consecutive switches are far apart compared with the tick
    assert np.diff(fixed.switch_times[1]).min() > 50 * P.step


def _two_span_chain(mu: float) -> Chain:
    """Roller 0 -> span (6 m) -> roller 1 (slips) -> span (9 m) -> roller 2, which draws 2e-5
    and whose speed ripples by 1e-3 at 3 Hz (a downstream disturbance); t0 = 150 N upstream."""
    v = 5.0

    def ripple(t: float) -> float:
        return v * (1.0 + 2e-5 + 1e-3 * math.sin(2 * math.pi * 3.0 * t))

    contact = Contact(wrap=1.0, mu=mu, mu_k=0.6 * mu, viscous=400.0, mass_per_length=0.02)
    return Chain(ea=1e5, lengths=(6.0, 9.0),
                 rollers=(Roller(speed=constant(v)), Roller(speed=constant(v), contact=contact),
                          Roller(speed=ripple)),
                 tension_in=constant(150.0))


def test_web_length_is_conserved_across_a_slipping_roller():
    """Unstrained web in at roller 0 - out at roller 2 = change of web stored in both spans,
    to round-off (RK4 keeps this linear invariant exactly), while roller 1 slips most of the
    time. Feeding span 2 at the roller's surface speed instead of the web speed (the mistake
    the check guards against) would lose the web slid, ∫ s (1 - ε) dt, five orders larger."""
    chain = _two_span_chain(mu=0.01)
    y0, modes = steady_state(chain, 0.0, initial_state(chain, np.array([150.0, 150.0])))
    run = simulate_fixed(chain, y0, modes, 2.0, 1e-3)
    assert np.mean(run.state[:, 1]) > 0.5 and run.switches[1] > 10
    travelled = 10.0  # m of web through the chain
    # round-off: ~2000 steps on quantities of ~10 m at 1e-16 each
    assert np.abs(run.balance).max() < 1e-14 * travelled * 2000
    # the length slid, by quadrature of the sampled slip velocity and as integrated (1 %: the
    # trapezoid straddles the 1 ms after each of the ~20 break-aways, where s jumps)
    assert np.trapezoid(run.slip[:, 1], run.time) == pytest.approx(run.slid[-1, 1], rel=1e-2)
    lost = np.trapezoid(run.slip[:, 1] * (1 - run.tension[:, 0] / chain.ea), run.time)
    assert abs(lost) > 1e5 * np.abs(run.balance).max()


def test_slip_example_study_runs_end_to_end(tmp_path):
    """The study (shortened) through its registry entry point: figure written, every case
    tabulated, webline's runs conserve web and never dissipate negative power; the other
    tables are in the JSON file next to the figure."""
    result = se.run(tmp_path, quick=True)
    assert isinstance(result, StudyResult) and result.name == "slip-example"
    assert result.figures and all(p.exists() and p.stat().st_size > 10_000
                                  for p in result.figures)
    cases = {row["case"]: row for row in result.table}
    assert len(cases) == 7
    for name, row in cases.items():
        assert row["max_web_balance_m"] < 1e-9
        if name.startswith("webline"):
            assert row["min_slip_power_W"] >= 0.0
    assert cases["webline: slip"]["t2_max_lbf"] == cases["webline: no slip"]["t2_max_lbf"]
    assert cases["as printed: slip (5.47) + 2 Hz t3"]["min_slip_power_W"] < 0.0
    tables = json.loads((tmp_path / "slip_example.json").read_text())["tables"]
    check = tables["fixed_step_check"][0]
    assert check["switches fixed 1 ms"] == check["switches events"]
    assert "not an equilibrium" in result.summary
