"""Numbers in docs/errata.md that check a printed statement of the thesis: E-2.9 (Sec. 2.5's
"25 N"), E-3.7 ((3.45)) and E-4.6 (Sec. 4.3's 60 % and 46 %)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

LBF = 4.4482216152605


def test_speed_oscillation_to_tension_2_5():
    """E-2.9: 5 RPM at 0.5 m is 0.262 m/s; fed as an unwind speed ripple of 0.25 m/s at 5 Hz
    into span 1 of the HSWL by (6.8), the tension oscillates with EA dv/|j w L + v| = 11.6 N
    (2 %), not 25 N."""
    assert 5 * 2 * math.pi / 60 * 0.5 == pytest.approx(0.262, abs=5e-4)
    ea, length, v, t0 = 2000 * LBF, 20 * 0.3048, 500 * 0.00508, 12 * LBF
    w, dv = 2 * math.pi * 5.0, 0.25

    def rhs(t, y):
        v0 = v + dv * math.sin(w * t)
        return [(ea * (v - v0) + t0 * v0 - y[0] * v) / length]

    # starts at the equilibrium of equal speeds, T = t0
    sol = solve_ivp(rhs, (0, 12.0), [t0], max_step=1e-3, rtol=1e-9, atol=1e-9)
    late = sol.y[0][sol.t > 8.0]
    amplitude = 0.5 * float(np.ptp(late))
    predicted = ea * dv / abs(1j * w * length + v)
    assert predicted == pytest.approx(11.6, abs=0.05)
    assert amplitude == pytest.approx(predicted, rel=0.02)


def test_potential_3_45_gives_the_printed_equations_of_motion():
    """E-3.7: the spring forces of the printed equations after (3.45) are the gradient of
    1/2 k (xL - xm)^2, not of the printed 1/2 k (xm^2 + xL^2)."""
    k, h = 200.0, 1e-6
    rng = np.random.default_rng(0)
    for xm, xl in rng.normal(0, 0.01, (5, 2)):
        def grad(pot, xm=xm, xl=xl):
            return ((pot(xm + h, xl) - pot(xm - h, xl)) / (2 * h),
                    (pot(xm, xl + h) - pot(xm, xl - h)) / (2 * h))
        eom = (k * (xm - xl), -k * (xm - xl))
        assert grad(lambda a, b: 0.5 * k * (b - a) ** 2) == pytest.approx(eom, rel=1e-6)
        assert grad(lambda a, b: 0.5 * k * (a * a + b * b)) != pytest.approx(eom, rel=1e-3)


def test_percentages_of_section_4_3():
    """E-4.6: 1.95 -> 2.9 lbf is +48.7 % (60 % would need 3.12 lbf); 1.66 against 2.9 lbf is
    42.8 % less (46 % would need 3.07 lbf)."""
    without, with_backlash, with_brake = 1.95, 2.9, 1.66  # lbf, Figs 4.22, 4.23, 4.27
    rise = 100 * (with_backlash / without - 1)
    fall = 100 * (1 - with_brake / with_backlash)
    assert rise == pytest.approx(48.7, abs=0.05)
    assert fall == pytest.approx(42.8, abs=0.05)
    needed_for_60, needed_for_46 = without * 1.60, with_brake / (1 - 0.46)
    assert needed_for_60 == pytest.approx(3.12, abs=0.005)
    assert needed_for_46 == pytest.approx(3.07, abs=0.005)
