"""With constant references the simulated line settles on ``operating_point`` (issue 2).

Equilibrium speeds follow thesis (6.22, 6.31, 6.36) generalised: v_i (EA - T_i^up) is the
same for every node. Equilibrium inputs follow (6.20, 6.28, 6.32, 6.37) re-derived (see
docs/errata.md E-6.1, E-6.4): n u = J dω/dt - r (T_out - T_in) + friction.
"""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.sim.elements import layout as L


def settle(line: webline.Line, duration: float) -> tuple[webline.Result, webline.OperatingPoint]:
    result = webline.simulate(line, duration)
    radii = result.radius[-1]
    op = webline.operating_point(line, duration, unwind_radius=radii[0], rewind_radius=radii[-1])
    return result, op


@pytest.mark.parametrize("name", ["hswl", "six"])
def test_steady_state_matches_operating_point(name, hswl, six):
    base = {"hswl": hswl, "six": six}[name]
    line = base
    # Start away from equilibrium: a tension step of +10 % in every zone at t = 1 s.
    spans = line.spec.model_dump(exclude_none=True)["spans"]
    for span in spans:
        if "tension" in span:
            span["tension"] = {"type": "steps", "initial": span["tension"],
                               "steps": [{"time": 1.0, "value": 1.1 * span["tension"]}]}
    line = line.replace(spans=spans)
    result, op = settle(line, 40.0)
    # Tensions: the PI integrators remove the error; the only drift left is the slow change of
    # roll radius (microns per second), so 1e-6 relative is a real test of the equilibrium.
    np.testing.assert_allclose(result.tension[-1], op.tension, rtol=1e-6)
    np.testing.assert_allclose(result.tension[-1][[z.loadcell for z in line.zones]],
                               [1.1 * base.spec.spans[z.loadcell].tension for z in line.zones],
                               rtol=1e-6)
    np.testing.assert_allclose(result.speed[-1], op.speed, rtol=1e-6)
    np.testing.assert_allclose(result.torque[-1], op.torque, rtol=1e-4, atol=1e-6)


def test_equilibrium_speeds_follow_mass_flow(six):
    """(6.22)/(6.31)/(6.36): v_i = v_master (EA - T_master^up)/(EA - T_i^up) to first order;
    ``six`` conserves web mass exactly (E-6.6): v_i/(EA + T_i^up) is the same at every node."""
    op = webline.operating_point(six)
    ea = six.ea
    upstream = np.concatenate(([six.unwind.wound_in_tension], op.tension))
    assert six.exact
    flow = op.speed / (ea + upstream)
    np.testing.assert_allclose(flow, flow[six.master], rtol=1e-14)
    assert op.speed[six.master] == pytest.approx(5.0)  # 300 m/min


def test_hswl_equilibrium_inputs_match_thesis_form(hswl):
    """Table 6.1 numbers in the re-derived (6.20), (6.28), (6.37) at constant speed.

    Motor torque is positive in the web direction here (the thesis's u0 brakes), and the roll
    equations use J dω/dt = torque (E-6.1), so for the unwind
    u0 = -(R0 t1 - b ω0 - J0 δ v0² / (2π R0³)) / n0.
    """
    op = webline.operating_point(hswl)
    web = hswl.spec.web
    r0, v0, t1, j0 = op.radius[0], op.speed[0], op.tension[0], op.inertia[0]
    b = hswl.spec.rollers[0].friction
    expected_u0 = -(r0 * t1 - b * v0 / r0 - j0 * web.thickness * v0**2 / (2 * np.pi * r0**3)) / 0.5
    assert op.torque[0] == pytest.approx(expected_u0, rel=1e-12)
    r1, v1 = op.radius[1], op.speed[1]
    expected_u1 = (b * v1 / r1 - r1 * (op.tension[1] - op.tension[0])) / 1.0  # (6.28)
    assert op.torque[1] == pytest.approx(expected_u1, rel=1e-12)
    # (6.22): the unwind runs faster than the master by (AE - t_r)/(AE - t0)
    assert v0 / v1 == pytest.approx((hswl.ea - t1) / (hswl.ea - hswl.unwind.wound_in_tension))


def test_constant_reference_run_stays_at_equilibrium(hswl):
    """Started at the operating point, nothing moves (beyond the slow radius drift)."""
    result = webline.simulate(hswl, 5.0)
    op = webline.operating_point(hswl)
    assert np.abs(result.tension - op.tension).max() < 1e-6 * op.tension.max()
    assert result.settings["substeps"] >= 1
    assert result.plan.drives[:, L.D_ROLE].tolist() == [1, 0, 1, 1]
