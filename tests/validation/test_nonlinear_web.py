"""Nonlinear webs (issue 26 item 3, docs/nonlinear-web.md): a stress-strain law T = F(s) on the
span's stretch s = EA·ε, which mass conservation moves exactly as before."""

from __future__ import annotations

import numpy as np
import pytest
from fd_helpers import jacobian, plant_derivative

import webline
from webline.physics import web_law
from webline.sim import layout as L
from webline.sim.linearize import linear_model

E = 0.3e9  # rockwell's paper modulus [Pa]
POWER = {"law": "power", "exponent": 1.6, "reference_strain": 0.004}


def three_roller(tension: str = "40 N", law: dict | None = None,
                 speed: str = "30 m/min") -> webline.Line:
    """Unwind (tension PI), pull roll (master), rewind (tension PI): two spans, each a zone;
    the web is rockwell's paper (0.19 mm x 6 in, 0.3 GPa)."""
    drive = {"ratio": 1.0, "torque_limit": "80 N*m", "torque_lag": "2 ms"}
    pi = {"type": "cascaded_pi", "speed_bandwidth": "10 rad/s", "tension_bandwidth": "4 rad/s",
          "damping": 1.0}
    web = {"thickness": "0.19 mm", "width": "6 in", "density": "400 kg/m**3", "modulus": E}
    if law is not None:
        web["stress_strain"] = law
        if law["law"] == "table":
            del web["modulus"]
    return webline.load_line({
        "name": "three-roller", "speed": speed, "web": web,
        "rollers": [
            {"name": "unwind", "type": "unwind", "radius": "5 in", "core_radius": "1.5 in",
             "inertia": "1 lb*ft**2", "friction": "0.01 lbf*ft*s", "wound_in_tension": tension,
             "drive": drive, "controller": pi},
            {"name": "pull", "type": "driven", "role": "master", "radius": "3 in",
             "inertia": "0.05 kg*m**2", "friction": "0.001 N*m*s", "drive": drive,
             "controller": {"type": "cascaded_pi", "speed_bandwidth": "10 rad/s",
                            "damping": 1.0}},
            {"name": "rewind", "type": "rewind", "radius": "3.5 in", "core_radius": "3 in",
             "inertia": "2 lb*ft**2", "friction": "0.01 lbf*ft*s", "drive": drive,
             "controller": pi}],
        "spans": [{"name": "span1", "length": "5 ft", "tension": tension},
                  {"name": "span2", "length": "4 ft", "tension": tension}],
    })


@pytest.fixture(scope="module")
def rockwell() -> webline.Line:
    return webline.load_line("rockwell")


def test_linear_law_named_and_as_table_is_bit_identical(rockwell):
    """The linear law by name, and as a two-point table equal to it, run the very same
    floating-point operations as a file without the key (np.array_equal, no tolerance)."""
    line = rockwell.with_scenario("backlash-slowdown")
    base = webline.simulate(line, 4.0)
    named = webline.simulate(line.replace({"web.stress_strain": {"law": "linear"}}), 4.0)
    # 3 MPa / 0.01 is 3e8 Pa in binary too, so the table's modulus equals the file's
    table = {"law": "table", "strain": [0.0, 0.01], "stress": ["0 MPa", "3 MPa"]}
    as_table = line.replace({"web.stress_strain": table, "web.modulus": None})
    assert as_table.ea == line.ea and not as_table.nonlinear
    tabled = webline.simulate(as_table, 4.0)
    for run in (named, tabled):
        assert run.plan.offsets[L.O_LAW] == 0 and run.plan.offsets[L.O_KV] == 0
        assert np.array_equal(run.states, base.states)
        assert np.array_equal(run.tension, base.tension)


def test_law_functions_against_their_definitions():
    """Power law T = S_r (s/S_r)^n, its slope and inverse; a table's segments and slope
    beyond its last point; a slack span carries nothing."""
    power = np.array([web_law.POWER, 20.0, 1.6])
    for s in (0.5, 20.0, 75.0):
        t = web_law.law_tension(s, power)
        assert t == pytest.approx(20.0 * (s / 20.0) ** 1.6, rel=1e-15)
        assert web_law.law_stretch(t, power) == pytest.approx(s, rel=1e-13)  # round trip
        h = 1e-6 * s  # central difference: error ~h² f''' ~ 1e-12 relative
        fd = (web_law.law_tension(s + h, power) - web_law.law_tension(s - h, power)) / (2 * h)
        assert web_law.law_slope(s, power) == pytest.approx(fd, rel=1e-8)
    table = np.array([web_law.TABLE, 3, 0.0, 10.0, 20.0, 0.0, 10.0, 13.0])  # bilinear, h=0.3
    assert web_law.law_tension(5.0, table) == 5.0
    assert web_law.law_tension(30.0, table) == pytest.approx(16.0)  # 13 + 0.3 x 10
    assert web_law.law_slope(15.0, table) == pytest.approx(0.3)
    assert web_law.law_stretch(16.0, table) == pytest.approx(30.0)
    assert web_law.law_tension(-3.0, table) == 0.0 and web_law.law_tension(-3.0, power) == 0.0


@pytest.mark.parametrize("law", [POWER, {"law": "bilinear", "yield_strain": 0.002,
                                         "hardening": 0.4}])
@pytest.mark.parametrize("retardation", [None, 5e-3])
def test_linearization_matches_finite_differences_of_the_kernel(law, retardation):
    """Open-loop A and the felt-tension output rows against central differences of the
    compiled right-hand side, with the law (and a Kelvin-Voigt damper on top). The bilinear
    web runs at 40 N, strain 0.46 %: beyond its 0.2 % yield, away from the kink."""
    line = three_roller("40 N", law)
    if retardation is not None:
        line = line.replace({f"spans.{n}.model": "kelvin-voigt" for n in ("span1", "span2")}
                            | {f"spans.{n}.retardation": retardation
                               for n in ("span1", "span2")})
    op = webline.operating_point(line)
    f, z0, plan = plant_derivative(line, op)
    assert plan.offsets[L.O_LAW] == 1
    sys = linear_model(line, loop="open")
    scale = np.maximum(np.abs(z0), 1.0)
    fd = jacobian(f, z0, op.torque, scale)
    # central differences of a smooth rhs at 1e-6 relative steps: ~1e-9 relative error
    np.testing.assert_allclose(sys.a, fd, rtol=1e-6, atol=1e-6 * np.abs(sys.a).max())
    n_s = line.n_spans
    tau = plan.spans[:, L.S_TAU]
    law_arr = line.law
    felt = lambda z, u: (np.array([web_law.law_tension(s, law_arr) for s in z[:n_s]])  # noqa: E731
                         + tau * f(z, u)[:n_s])
    fd_c = jacobian(felt, z0, op.torque, scale)
    np.testing.assert_allclose(sys.c[:n_s], fd_c, rtol=1e-6, atol=1e-6 * np.abs(fd_c).max())
    # the closed loop's eigenvalues are those of the kernel's own equilibrium: stable
    assert np.linalg.eigvals(linear_model(line).a).real.max() < 0.0


def test_equilibrium_holds_with_a_nonlinear_law():
    """Started at the law's operating point, the power-law line stays there as the linear
    one does: the initial stretch is F⁻¹(T_ref) and the speeds follow the strains by mass
    flow. Taking the stretch for the tension instead would start 3.7 N off (F(40 N) = 43.7 N)."""
    line = three_roller("40 N", POWER)
    run = webline.simulate(line, 0.05)
    # the rolls' radii move the equilibrium slowly: the linear web drifts 6e-4 N in 50 ms
    assert np.abs(run.tension - 40.0).max() < 2e-3
    strain = run.stretch[0] / line.ea
    expected = 0.004 * (40.0 / (line.ea * 0.004)) ** (1 / 1.6)  # ε = ε_r (T / S_r)^(1/n)
    np.testing.assert_allclose(strain, expected, rtol=1e-12)  # rounding only


def test_web_length_conserved_with_a_nonlinear_law():
    """A speed ramp on the power-law line: unwound = rewound + change stored, to 1e-7 m (the
    state is still the stretch the mass balance moves; as tests/validation/test_conservation)."""
    ramp = {"type": "ramp", "initial": "30 m/min", "final": "200 m/min", "start": 0.5,
            "duration": 2.0}
    line = three_roller("40 N", POWER).replace(speed=ramp)
    run = webline.simulate(line, 6.0)
    balance = run.web_unwound - run.web_rewound - (run.web_stored - run.web_stored[0])
    assert run.web_unwound[-1] > 10.0
    assert np.abs(balance).max() < 1e-7  # RK4 at 1 ms: ~1e-10 m; a missing term shows at mm


def _span_frequencies(line: webline.Line) -> np.ndarray:
    """|Im λ| [rad/s] of the open-loop plant's two oscillatory span modes, ascending."""
    lam = np.linalg.eigvals(linear_model(line, loop="open").a)
    return np.sort(lam.imag[lam.imag > 1.0])  # the upper one of each conjugate pair


def _hand_frequencies(line: webline.Line, tangent: float) -> np.ndarray:
    """Natural frequencies [rad/s] of the chain of masses J_i/r_i² joined by springs
    K/L_k, K = A E_t = ``tangent`` [N] the tangent stiffness (transport v/L and the (1 - ε)
    of 6.8 left out)."""
    op = webline.operating_point(line)
    from webline.sim.linear_plant import load_inertia
    from webline.sim.plan import compile_plan

    plan = compile_plan(line)
    mass = np.array([load_inertia(plan, op, i) / op.radius[i] ** 2 for i in range(3)])
    springs = [tangent / s.length for s in line.spec.spans]
    k = np.zeros((3, 3))
    for j, c in enumerate(springs):
        k[j:j + 2, j:j + 2] += c * np.array([[1, -1], [-1, 1]])
    omega2 = np.linalg.eigvals(np.diag(1 / mass) @ k).real
    return np.sqrt(np.sort(omega2)[1:])  # the rigid-body mode is 0


def test_stiffening_web_raises_the_span_frequency_as_its_tangent_modulus_says():
    """Power law σ = E ε_r (ε/ε_r)^1.6 at 20 N and 80 N: the linearized span modes sit at
    the chain frequencies with the local tangent stiffness EA·n(ε/ε_r)^(n-1); the linear web
    keeps its frequencies at both tensions (within the same neglected terms)."""
    ea = three_roller().ea
    freqs = {}
    for tension in (20.0, 80.0):
        line = three_roller(f"{tension} N", POWER)
        strain = 0.004 * (tension / (ea * 0.004)) ** (1 / 1.6)
        tangent = ea * 1.6 * (strain / 0.004) ** 0.6  # dT/dε [N]
        got, hand = _span_frequencies(line), _hand_frequencies(line, tangent)
        # neglected: the (1 - ε) of 6.8 (ε = 0.28 % and 0.67 %: ω low by ~ε/2 <= 0.34 %) and
        # transport (v/L ~ 0.1 1/s against 35-75 rad/s); the linear web's would be 14-48 % off
        np.testing.assert_allclose(got, hand, rtol=5e-3)
        freqs[tension] = got
        linear = three_roller(f"{tension} N")
        np.testing.assert_allclose(_span_frequencies(linear),
                                   _hand_frequencies(linear, ea), rtol=5e-3)
    # the stiffening is the law's: ω ~ √E_t, E_t ~ ε^(n-1), ε ~ T^(1/n), so ω rises by
    # (80/20)^((n-1)/(2n)) = 4^0.1875 = 1.297 (to the same ~ε/2 as above)
    ratio = freqs[80.0] / freqs[20.0]
    np.testing.assert_allclose(ratio, 4.0 ** (0.6 / 3.2), rtol=5e-3)


def test_strain_beyond_yield_is_a_finding_of_the_verdict():
    """A bilinear web (yield at ε = 0.4 %, 34.7 N; half the modulus beyond) whose first zone
    steps from 30 N to 45 N at 0.5 s: span1 yields after the step and stays beyond (at 45 N
    the law's strain is 0.4 % + (45 - 34.7) N / (0.5 EA) = 0.637 %); span2 (30 N) never
    yields. The same run on a web yielding at 1 % has no such finding."""
    law = {"law": "bilinear", "yield_strain": 0.004, "hardening": 0.5}
    step = {"type": "steps", "initial": "30 N", "steps": [{"time": 0.5, "value": "45 N"}]}
    line = three_roller("30 N", law).replace({"spans.span1.tension": step})
    run = webline.simulate(line, 2.0)
    found = [f for f in run.verdict.findings if f.kind == "yield"]
    assert [f.where for f in found] == ["span1"]
    assert run.verdict.status == "warning"
    yielded = found[0].details
    strain = run.stretch[:, 0] / line.ea
    first = run.time[np.argmax(strain > 0.004)]
    # the 4 rad/s tension loop covers the 31 % of the step up to the yield in ~0.4 s
    assert 0.5 < yielded["first_s"] == first < 1.2
    dt = run.time[1] - run.time[0]
    assert yielded["duration_s"] == pytest.approx(run.time[-1] - first + dt, abs=1.01 * dt)
    assert yielded["peak_strain"] == strain.max()
    # past yield the strain is the law's for the felt tension: ε = ε_y + (T - EA ε_y)/(h EA)
    # (to rounding); the zone approaches 45 N (44 N by 2 s on its 4 rad/s loop)
    tension = run.tension[-1, 0]
    hand = 0.004 + (tension - 0.004 * line.ea) / (0.5 * line.ea)
    assert strain[-1] == pytest.approx(hand, rel=1e-12)
    assert 43.0 < tension < 45.5
    assert yielded["peak_strain"] >= strain[-1]
    stiff = three_roller("30 N", law | {"yield_strain": 0.01}).replace(
        {"spans.span1.tension": step})
    assert not [f for f in webline.simulate(stiff, 2.0).verdict.findings if f.kind == "yield"]


def test_rockwell_linearization_with_a_law_matches_finite_differences(rockwell):
    """rockwell (a dancer, a belt, an idle roller) with a softening paper (n = 0.7): the
    open-loop A against central differences of the kernel, as for the three-roller line."""
    line = rockwell.replace({"web.stress_strain": {"law": "power", "exponent": 0.7,
                                                   "reference_strain": 0.005}})
    op = webline.operating_point(line)
    f, z0, _ = plant_derivative(line, op)
    sys = linear_model(line, loop="open")
    scale = np.maximum(np.abs(z0), 1.0)
    fd = jacobian(f, z0, op.torque, scale)
    # central differences of a smooth rhs at 1e-6 relative steps: ~1e-9 relative error
    np.testing.assert_allclose(sys.a, fd, rtol=1e-6, atol=1e-6 * np.abs(sys.a).max())


def test_fast_path_matches_the_adaptive_reference_with_a_law():
    """The power-law line through a speed ramp and a wound-in ripple: the compiled RK4 path
    against scipy's DOP853 at 1e-10 (which evaluates the same law in the same right-hand
    side, adaptively): any step-size or felt-tension bookkeeping error would show."""
    ramp = {"type": "ramp", "initial": "30 m/min", "final": "200 m/min", "start": 0.5,
            "duration": 2.0}
    line = three_roller("40 N", POWER).replace(speed=ramp, disturbances=[
        {"type": "wound_in_ripple", "amplitude": "2 N", "frequency": "3 Hz"}])
    fast = webline.simulate(line, 3.0)
    ref = webline.simulate_reference(line, 3.0, method="DOP853", rtol=1e-10, atol=1e-10)
    error = np.abs(fast.tension - ref.tension).max() / np.abs(ref.tension).max()
    assert np.ptp(ref.tension[:, 0]) > 0.3  # the ripple and ramp move the tension (0.64 N)
    assert error < 1e-5  # measured 5.9e-9: RK4 at the 1 ms tick (as test_reference_path)
    np.testing.assert_allclose(fast.speed, ref.speed, rtol=1e-6)


def test_a_study_case_that_yields_is_judged_as_its_run():
    """The yielding line of the test above as a sweep over its hardening: each case's status
    and headline say what its run's verdict says (warning: span1 beyond yield), and the
    case's peak strain is its run's, F⁻¹(T_max)/EA from the largest felt tension."""
    from webline.sim.sweep import sweep

    law = {"law": "bilinear", "yield_strain": 0.004, "hardening": 0.5}
    step = {"type": "steps", "initial": "30 N", "steps": [{"time": 0.5, "value": "45 N"}]}
    line = three_roller("30 N", law).replace({"spans.span1.tension": step})
    cases = sweep(line, {"web.stress_strain.hardening": [0.5, 0.8]}, duration=2.0)
    for c, hardening in enumerate((0.5, 0.8)):
        run = webline.simulate(line.replace({"web.stress_strain.hardening": hardening}), 2.0)
        assert str(cases.status.values[c]) == run.verdict.status == "warning"
        assert "span1 strained beyond the web's yield (0.4 %)" in str(cases.headline.values[c])
        peak = (run.stretch[:, 0] / line.ea).max()
        assert f"peak {100 * peak:.3g} %" in str(cases.headline.values[c])
