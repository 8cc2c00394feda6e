"""Kelvin-Voigt spans (issue 15 item 7, docs/winder.md "Viscoelastic span"): T = EA (ε + τ dε/dt),
the state the elastic stretch moved by mass conservation."""

from __future__ import annotations

import numpy as np
import pytest
from fd_helpers import jacobian, plant_derivative
from scipy.optimize import curve_fit
from test_linearize import continuous_pi

import webline
from webline.errors import LineFileError
from webline.sim.elements import layout as L
from webline.sim.linear.linearize import linear_model

IDLER, SPANS = "eccentric", ("rewind_span_a", "rewind_span_b")  # rockwell's idle roller


def viscoelastic(line: webline.Line, tau: float, spans=SPANS) -> webline.Line:
    changes: dict[str, object] = {}
    for name in spans:
        changes |= {f"spans.{name}.model": "kelvin-voigt", f"spans.{name}.retardation": tau}
    return line.replace(changes)


def test_vanishing_retardation_is_the_elastic_span(hswl):
    line = hswl.with_scenario("speed-change")
    elastic = webline.simulate(line, 8.0)
    kv = webline.simulate(viscoelastic(line, 1e-12, ("span2", "span3a")), 8.0)
    assert kv.plan.offsets[L.O_KV] == 1  # the viscoelastic code path ran
    scale = np.abs(elastic.tension).max()
    assert np.abs(kv.tension - elastic.tension).max() < 1e-9 * scale
    assert np.abs(kv.speed - elastic.speed).max() < 1e-9 * np.abs(elastic.speed).max()


def test_linear_rows_match_finite_differences_of_the_kernel():
    """Open-loop A, and the output rows of the felt tension, against central differences
    of the compiled right-hand side (which computes T = s + τ ds/dt itself)."""
    line = viscoelastic(webline.load_line("rockwell"), 5e-3, (*SPANS, "unwind_span"))
    op = webline.operating_point(line)
    f, z0, plan = plant_derivative(line, op)
    sys = linear_model(line, loop="open")
    scale = np.maximum(np.abs(z0), 1.0)
    fd = jacobian(f, z0, op.torque, scale)
    np.testing.assert_allclose(sys.a, fd, rtol=1e-6, atol=1e-6 * np.abs(sys.a).max())
    n_s = line.n_spans
    # the damper really entered the node rows: the idler's row moves with the speeds
    elastic = linear_model(webline.load_line("rockwell"), loop="open")
    i = n_s + [r.name for r in line.spec.rollers].index(IDLER)
    assert np.abs(sys.a[i] - elastic.a[i]).max() > 1.0
    # felt tension rows: T(z) = s + τ f_s(z), differenced through the kernel's own T
    tau = plan.spans[:, L.S_TAU]
    felt = lambda z, u: z[:n_s] + tau * f(z, u)[:n_s]  # noqa: E731
    fd_c = jacobian(felt, z0, op.torque, scale)
    np.testing.assert_allclose(sys.c[:n_s], fd_c, rtol=1e-6, atol=1e-6 * np.abs(fd_c).max())


def test_closed_loop_controllers_read_the_felt_tension(six):
    """The six-section line with every span Kelvin-Voigt (τ = 5 ms): the closed loop's A
    against central differences of the plant with the cascaded PI written out directly,
    each loadcell reading s + τ ds/dt of its span (ds/dt from the kernel)."""
    data = six.spec.model_dump(exclude_none=True)
    for span in data["spans"]:
        span |= {"model": "kelvin-voigt", "retardation": 5e-3}
    line = webline.load_line(data)
    op = webline.operating_point(line)
    f, z0, plan = plant_derivative(line, op)
    tau, n_s, n_z = plan.spans[:, L.S_TAU], line.n_spans, len(z0)
    refs = np.array([op.line_speed] + [op.tension[z.loadcell] for z in line.zones])
    _, istate = plan.initial_state(op)
    xi0 = np.array([v for d, row in enumerate(plan.drives)
                    for v in ([istate[d, 0], istate[d, 1]] if row[L.D_ROLE] else [istate[d, 0]])])

    def closed(w: np.ndarray, _: object) -> np.ndarray:
        z, xi = w[:n_z], w[n_z:]
        felt = z.copy()
        felt[:n_s] += tau * f(z, op.torque)[:n_s]  # ds/dt does not depend on the torques
        u, dxi = continuous_pi(plan, op, felt, xi, refs)
        return np.concatenate([f(z, u), dxi])

    w0 = np.concatenate([z0, xi0])
    fd = jacobian(closed, w0, None, np.maximum(np.abs(w0), 1.0))
    a = linear_model(line).a
    np.testing.assert_allclose(a, fd, rtol=1e-5, atol=1e-6 * np.abs(a).max())
    assert np.abs(a - linear_model(six).a).max() > 1.0  # the damper changed the loop


def _idler_mode(line: webline.Line) -> complex:
    """The closed-loop eigenvalue [1/s] with the largest share in the idler's speed."""
    model = linear_model(line)
    w, v = np.linalg.eig(model.a)
    share = np.abs(v[model.states.index(f"{IDLER}_omega")]) / np.abs(v).max(axis=0)
    return complex(w[np.argmax(share * (w.imag > 0))])


@pytest.mark.parametrize("tau", [1e-3, 3e-3])
def test_step_response_shows_the_damping_of_the_linear_model(tau):
    """rockwell's idle roller between its two rewind spans is a mass between two web
    springs: m = J/r², k = EA (1/L_a + 1/L_b), ω_n = √(k/m) (145 rad/s). A Kelvin-Voigt
    damper in both spans adds τ k to the damping, so ζ = ζ_elastic + τ ω_n / 2. A drag
    torque step on the idler rings this mode; its fitted decay and frequency match the
    closed-loop linear model, whose damping matches the hand formula."""
    rockwell = webline.load_line("rockwell")
    line = viscoelastic(rockwell, tau)
    plan_nodes = line.spec.rollers[[r.name for r in line.spec.rollers].index(IDLER)]
    lengths = {s.name: s.length for s in line.spec.spans}
    k = line.ea * sum(1.0 / lengths[s] for s in SPANS)
    omega_n = np.sqrt(k * plan_nodes.radius**2 / plan_nodes.inertia)  # type: ignore[union-attr]
    elastic, mode = _idler_mode(rockwell), _idler_mode(line)
    zeta = lambda lam: -lam.real / abs(lam)  # noqa: E731
    assert abs(mode) == pytest.approx(omega_n, rel=0.02)
    # hand formula within 3 % (the transport terms T v/L and the loops shift it slightly)
    assert zeta(mode) == pytest.approx(zeta(elastic) + tau * omega_n / 2, rel=0.03)
    # the simulated ring-down after a 0.02 N·m drag step on the idler at 0.2 s
    stepped = line.replace(disturbances=[{"type": "roller_drag", "roller": IDLER, "torque": {
        "type": "steps", "initial": 0.0, "steps": [{"time": 0.2, "value": 0.02}]}}])
    result = webline.simulate(stepped, 0.6)
    after = result.time > 0.2
    t = result.time[after] - 0.2
    y = result.omega[after, [r.name for r in line.spec.rollers].index(IDLER)]

    def ring(t, c0, c1, amp, sigma, omega, phase):
        return c0 + c1 * t + amp * np.exp(-sigma * t) * np.cos(omega * t + phase)

    guess = (y[-1], 0.0, y[0] - y[-1], -mode.real, mode.imag, 0.0)
    (_, _, _, sigma, omega, _), _ = curve_fit(ring, t, y, p0=guess, maxfev=20000)
    assert sigma == pytest.approx(-mode.real, rel=0.05)
    assert omega == pytest.approx(mode.imag, rel=0.02)
    assert sigma > 5 * -elastic.real  # the damper, not the elastic line, sets the decay


def test_damper_dissipates_energy():
    """Power of the damper force T_d = T - max(s, 0) into the span, T_d dε/dt L with dε/dt
    taken from the recorded stretch by finite differences (independent of the kernel's
    damper law), is never negative, and its integral is τ ∫ (ds/dt)² L / EA over the taut
    records. The fast ramp slackens the span for a while: no damper force there."""
    tau = 5e-3
    line = viscoelastic(webline.load_line("rockwell"), tau).replace(
        speed={"type": "ramp", "initial": "100 ft/min", "final": "300 ft/min", "start": 0.2,
               "duration": 0.5})
    result = webline.simulate(line, 1.5)
    k = line.n_spans - 1  # rewind_span_b
    s, felt, time = result.stretch[:, k], result.tension[:, k], result.time
    rate = np.gradient(s, time)
    length = line.spec.spans[k].length
    damper = felt - np.maximum(s, 0.0)
    power = damper * rate / line.ea * length  # [W]
    slack = s <= 0.0
    assert slack.any() and np.all(damper[slack] == 0.0)  # slack: no damper force
    assert np.abs(damper).max() > 10.0  # the damper carries force in the ramp
    # finite differences of a 145 rad/s ring at 1 ms err by ~(ωh)²/6 = 0.4 %, and more at
    # the kinks where the span goes slack or taut: allow 2 % of the largest power there
    assert power.min() > -0.02 * np.abs(power).max()
    dt = np.diff(time)
    dissipated = np.sum(power[1:] * dt)
    taut = ~slack[1:] & ~slack[:-1]
    expected = tau * np.sum((rate[1:] ** 2 * dt)[taut]) * length / line.ea
    assert dissipated > 0.0
    assert dissipated == pytest.approx(expected, rel=0.02)
    # the elastic spans of the same line feel their stretch, as before
    np.testing.assert_array_equal(result.tension[:, :2], np.maximum(result.stretch[:, :2], 0))


@pytest.mark.parametrize("change, key", [
    ({"spans.rewind_span_b.model": "kelvin-voigt"}, "spans[3].retardation"),
    ({"spans.rewind_span_b.retardation": "5 ms"}, "spans[3].retardation"),
    ({"spans.rewind_span_b.model": "maxwell"}, "spans[3].model"),
])
def test_bad_span_models_are_refused(change, key):
    with pytest.raises(LineFileError) as info:
        webline.load_line("rockwell").replace(change)
    assert key in str(info.value)
