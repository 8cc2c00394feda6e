"""Slip analyses: wrap and friction needs, (5.45), and the entry-slip / adhesion / exit-slip
regions of (5.19)-(5.22) by the carry-and-clip model (docs/slip.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import webline
from webline.analysis import slip as an
from webline.analysis.slip_regions import Arc, only_exit_arc, simulate_arc
from webline.physics import slip as sl


@settings(deadline=None)
@given(st.floats(5.0, 500.0), st.floats(0.2, 5.0), st.floats(0.05, 0.5), st.floats(0.0, 2.0))
def test_minimum_wrap_and_friction_sit_exactly_on_the_stiction_limit(t_in, r, mu, t_c):
    """At the smallest wrap (or friction) the tension difference equals the stiction limit of
    ``physics.slip`` in its direction; a little more wrap holds it, a little less does not."""
    t_out = t_c + r * (t_in - t_c)
    if abs(math.log(r)) < 1e-6:
        return
    wrap = float(an.min_wrap(t_in, t_out, mu, t_c))
    direction = 1.0 if t_in > t_out else -1.0
    limit = sl.stiction_limit(t_in, wrap, mu, t_c, direction)
    assert abs(t_in - t_out) == pytest.approx(limit, rel=1e-9)
    assert sl.slip_state(t_in, t_out, wrap * 1.001, mu, mu, t_c, 0) == 0
    assert sl.slip_state(t_in, t_out, wrap * 0.999, mu, mu, t_c, 0) == 1
    assert float(an.min_friction(t_in, t_out, wrap, t_c)) == pytest.approx(mu, rel=1e-12)
    assert float(an.slip_arc(t_in, t_out, mu, t_c)) == pytest.approx(
        sl.slip_arc(t_in, t_out, mu, t_c), rel=1e-12)


def test_slowly_varying_ratio_is_one_at_the_printed_limit():
    """(5.45): |dt/dτ| < μ v t / R; the ratio is 1 at equality (t_c = 0 as printed)."""
    mu, v, t, r = 0.2, 5.0, 100.0, 0.1
    assert float(an.slowly_varying_ratio(mu * v * t / r, t, v, r, mu)) == pytest.approx(1.0)
    assert float(an.slowly_varying_ratio(-0.5 * mu * v * t / r, t, v, r, mu)) == \
        pytest.approx(0.5)


def test_hswl_needs_at_the_operating_point():
    """HSWL (all zones at 14.35 lbf): driven rollers see equal tensions and need nothing; the
    idler needs μα = ln(T_out/T_in), its bearing drag over its radius (plus t_c)."""
    line = webline.load_line("hswl")
    op = webline.operating_point(line)
    wraps = {"master": math.pi, "process": math.pi, "idler": math.pi / 2}
    needs = {n.roller: n for n in an.operating_needs(line, op, wraps, 0.2)}
    assert needs["master"].mu_wrap == pytest.approx(0.0, abs=1e-12)
    idler = needs["idler"]
    t_c = an.mass_per_length(line) * op.speed[3] ** 2
    assert idler.mu_wrap == pytest.approx(math.log((op.tension[3] - t_c) / (op.tension[2] - t_c)))
    assert 0 < idler.mu_wrap < 0.01 and idler.margin > 0


# --- entry-slip, adhesion and exit-slip regions ---------------------------------------------

ARC = Arc(wrap=math.pi / 2, radius=0.05, speed=2.0, mu=0.2, ea=1e4, t_c=0.5, cells=400)


@pytest.mark.parametrize(("t_in", "t_out"), [(100.0, 80.0), (80.0, 100.0)])
def test_steady_contact_has_only_the_exit_slip_arc_of_5_13(t_in, t_out):
    """Steady tensions: the web adheres from the entry (it enters at the roller speed,
    exactly) and slips on an exit arc φ of (5.13) with the centrifugal term, either sign of
    t_out - t_in (Sec. 5.2-5.3, E-5.1); it leaves at v (1 - ε_in)/(1 - ε_out), the creep."""
    run = simulate_arc(ARC, lambda t: t_in, lambda t: t_out, 0.01)
    phi = sl.slip_arc(t_in, t_out, ARC.mu, ARC.t_c)
    assert run.entry[-1] == 0.0
    assert ARC.wrap - run.exit[-1] == pytest.approx(phi, abs=ARC.wrap / ARC.cells)
    assert run.v_in[-1] == pytest.approx(ARC.speed, rel=1e-13)
    creep = ARC.speed * (1 - t_in / ARC.ea) / (1 - t_out / ARC.ea)
    assert run.v_out[-1] == pytest.approx(creep, rel=1e-13)


def test_entry_slip_region_opens_exactly_when_5_45_fails():
    """Entering tension rising as t_c + (T0 - t_c) e^{kt} (constant d ln(T - t_c)/dt = k):
    below the limit of (5.45), k < μω, the web keeps adhering at the entry and enters at the
    roller speed; above it an entry slip region opens, here meeting the exit one, and the web
    enters slower by (k - μω) ∫ ε R dθ over the entry region (the material there stretches at
    that excess rate): R (T - t_c)(1 - e^{-μγ})(k - μω)/(μ EA)."""
    mw = ARC.mu * ARC.speed / ARC.radius
    for factor in (0.8, 1.5):
        k = factor * mw
        run = simulate_arc(ARC, lambda t, k=k: 0.5 + 99.5 * math.exp(k * t),
                           lambda t, k=k: 0.5 + 89.5 * math.exp(k * t), 0.03)
        t_now = 0.5 + 99.5 * math.exp(k * run.time[-1])
        gamma = run.entry[-1]
        if factor < 1:
            assert gamma == 0.0
            assert run.v_in[-1] == pytest.approx(ARC.speed, rel=1e-12)
        else:
            assert gamma > 0.5
            slow = (ARC.radius * (t_now - ARC.t_c) * (1 - math.exp(-ARC.mu * gamma))
                    * (k - mw) / (ARC.mu * ARC.ea))
            assert ARC.speed - run.v_in[-1] == pytest.approx(slow, rel=0.03)


def test_a_step_in_the_entering_tension_slips_the_entry_arc_of_the_matching_condition():
    """A step of the entering tension from 100 to 120 N: in the step it happens, the web slips
    over the entry arc γ where T_in e^{-μγ} meets the frozen tension (the matching condition
    at γ of Sec. 5.4, E-5.5); afterwards the material adheres and carries that profile round."""
    step_at = 0.005
    run = simulate_arc(ARC, lambda t: 100.0 if t < step_at else 120.0, lambda t: 95.0, 0.01)
    j = int(np.searchsorted(run.time, step_at))
    gamma = math.log((120.0 - ARC.t_c) / (100.0 - ARC.t_c)) / ARC.mu
    assert run.entry[j] == pytest.approx(gamma, abs=ARC.wrap / ARC.cells)
    assert run.entry[j + 1] == 0.0
    assert run.v_in[j] < ARC.speed  # the entering web is pulled back as it stretches


@settings(max_examples=15, deadline=None)
@given(st.lists(st.floats(60.0, 140.0), min_size=4, max_size=4),
       st.floats(70.0, 130.0), st.floats(0.005, 0.03))
def test_at_most_one_entry_and_one_exit_slip_region(levels, t_out, dwell):
    """Any history of entering tensions within the capstan limit: the slipping material at any
    instant forms at most two regions, one at the entry and one at the exit — the three
    regions of Fig. 5.9/5.15 are the general case (the carried profile is μ-Lipschitz in
    ln(T - t_c), so each cone clips a set that touches its apex)."""
    arc = Arc(wrap=math.pi, radius=0.05, speed=2.0, mu=0.3, ea=1e4, t_c=0.5, cells=60)

    def t_in(t: float) -> float:
        return levels[min(int(t / dwell), 3)]

    run = simulate_arc(arc, t_in, lambda t: t_out, 4 * dwell)
    assert run.inner.max() == 0
    assert np.all(run.entry[~run.gross] <= run.exit[~run.gross] + 1e-12)
    # unstrained web on the arc changes only by what enters minus what leaves (speeds are
    # step averages, at the mid-step strain)
    h = arc.step
    ok = ~np.isnan(run.v_in)
    mid = np.array([0.5 * (t_in(t) + t_in(max(t - h, 0.0))) for t in run.time])
    flux = run.v_in * (1 - mid / arc.ea) - run.v_out * (1 - t_out / arc.ea)
    change = np.diff(np.concatenate(([run.stored[0] - flux[0] * h], run.stored)))
    assert np.allclose(change[ok], flux[ok] * h, rtol=0, atol=1e-12)


def test_gross_slip_is_flagged_beyond_the_capstan_limit():
    run = simulate_arc(ARC, lambda t: 100.0, lambda t: 100.0 * math.exp(ARC.mu * ARC.wrap) + 5,
                       0.002)
    assert run.gross.all() and np.isnan(run.v_in).all()


def test_only_exit_arc_uses_the_adhered_window():
    """The whole-window form of (5.45): a steady history passes, a rise of the entering
    tension faster than μω(T - t_c) within the adhered window fails, a slow one passes."""
    dt = 1e-4
    steady = np.full(200, 100.0)
    assert only_exit_arc(steady, dt, ARC, 90.0)
    mw = ARC.mu * ARC.speed / ARC.radius
    fast = 0.5 + 99.5 * np.exp(1.5 * mw * dt * np.arange(200))
    slow = 0.5 + 99.5 * np.exp(0.5 * mw * dt * np.arange(200))
    assert not only_exit_arc(fast, dt, ARC, fast[-1] * 0.9)
    assert only_exit_arc(slow, dt, ARC, slow[-1] * 0.9)
