"""``linearize`` agrees with a finite-difference Jacobian of the nonlinear model, and the
closed loop of hswl at 500 ft/min is stable (issue 2)."""

from __future__ import annotations

import numpy as np
import pytest
from fd_helpers import jacobian, plant_derivative

import webline
from webline.physics.span import draw_ratio
from webline.sim.elements import layout as L


@pytest.mark.parametrize("name", ["hswl", "six"])
def test_open_loop_matches_finite_differences(name, hswl, six):
    line = {"hswl": hswl, "six": six}[name]
    op = webline.operating_point(line)
    f, z0, _ = plant_derivative(line, op)
    sys = webline.linearize(line, loop="open")
    fd = jacobian(f, z0, op.torque, np.maximum(np.abs(z0), 1.0))
    n = sys.nstates
    # central differences are accurate to ~1e-8 relative here; the model is smooth
    np.testing.assert_allclose(sys.A, fd, rtol=1e-6, atol=1e-6 * np.abs(sys.A).max())
    # input matrix: torque commands enter through the motor lag
    fd_b = jacobian(lambda u, z: f(z, u), op.torque, z0, np.ones(len(op.torque)))
    np.testing.assert_allclose(sys.B[:, : len(op.torque)], fd_b, rtol=1e-6, atol=1e-9)
    assert sys.A.shape == (n, n)


def continuous_pi(plan, op, z, xi, refs):
    """Cascaded PI of every drive written out directly (independent of controller_matrices)."""
    line = plan.line
    n_s = line.n_spans
    u, dxi = [], []
    j = 0
    for d, i in enumerate(line.drives):
        row = plan.drives[d]
        up = int(row[L.D_UPREF])
        t_up = line.unwind.wound_in_tension if up < 0 else refs[up]
        t_m = refs[int(plan.offsets[6])]
        ff = refs[0] * draw_ratio(line.ea, t_up, t_m, line.exact)
        gain = 1.0
        if row[L.D_ADAPTIVE]:
            gain = op.inertia[i] / (row[L.D_GAINNORM] * plan.nodes[i, L.N_RATIO] * op.radius[i])
        i_s = xi[j]
        j += 1
        trim = 0.0
        if row[L.D_ROLE] == L.ROLE_TENSION:
            e_t = refs[int(row[L.D_REF])] - z[int(row[L.D_LOADCELL])]
            trim = row[L.D_SIGMA] * (row[L.D_KPT] * e_t + xi[j])
            dxi_t = row[L.D_KIT] * e_t
            j += 1
        e_v = ff + trim - op.radius[i] * z[n_s + i]
        u.append(gain * row[L.D_KPS] * e_v + i_s)
        dxi.append(gain * row[L.D_KIS] * e_v)
        if row[L.D_ROLE] == L.ROLE_TENSION:
            dxi.append(dxi_t)
    return np.array(u), np.array(dxi)


def test_closed_loop_matches_finite_differences(six):
    op = webline.operating_point(six)
    f, z0, plan = plant_derivative(six, op)
    sys = webline.linearize(six, loop="closed")
    refs = np.array([op.line_speed] + [op.tension[z.loadcell] for z in six.zones])
    n_z = len(z0)
    _, istate = plan.initial_state(op)
    xi0 = np.array([v for d, row in enumerate(plan.drives)
                    for v in ([istate[d, 0], istate[d, 1]] if row[L.D_ROLE] else [istate[d, 0]])])

    def closed(w: np.ndarray, _: object) -> np.ndarray:
        z, xi = w[:n_z], w[n_z:]
        u, dxi = continuous_pi(plan, op, z, xi, refs)
        return np.concatenate([f(z, u), dxi])

    w0 = np.concatenate([z0, xi0])
    # an equilibrium, except that the rolls' ω drifts as their radius changes (op.accel)
    expected = np.zeros_like(w0)
    expected[six.n_spans:six.n_spans + six.n_nodes] = op.accel
    np.testing.assert_allclose(closed(w0, None), expected, atol=1e-9)
    fd = jacobian(closed, w0, None, np.maximum(np.abs(w0), 1.0))
    np.testing.assert_allclose(sys.A, fd, rtol=1e-5, atol=1e-6 * np.abs(sys.A).max())


def test_hswl_closed_loop_stable_at_500_fpm(hswl):
    assert hswl.spec.speed == pytest.approx(500 * 0.3048 / 60)
    eig = np.linalg.eigvals(webline.linearize(hswl, loop="closed").A)
    assert eig.real.max() < -0.5  # every mode decays at least as e^(-t/2 s)
    # and the dominant (slowest) modes are well damped
    slow = eig[np.abs(eig) < 30]
    assert (-slow.real / np.abs(slow)).min() > 0.7
