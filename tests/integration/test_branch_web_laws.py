"""Web laws on a branched line (docs/branching.md, "Web laws"): each raw web's
``stress_strain``, a laminate's law the sum of its layers' at their shared strain, a lane its
share of its base web's; ``strength`` per web and lane; yield in the verdict; Kelvin-Voigt
spans."""

from __future__ import annotations

import numpy as np
import pytest
from branch_support import laminated_then_slit

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import linear_model
from webline.sim.branches.plan import compile_branches

EA_FILM, EA_FOIL = 103.5e3, 630e3  # N: the laminator's layers
POWER = {"law": "power", "exponent": 1.5, "reference_strain": 1e-4}


def _laminator(foil: dict | None = None, film: dict | None = None) -> dict:
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    for w, change in ((0, film), (1, foil)):
        if change is not None:
            data["webs"][w]["web"].update(change)
    return data


def _span(line, name: str) -> int:
    return next(s.index for s in line.spans if s.name == name)


def _film_by_modulus(table: bool, third: float | None = None) -> dict:
    """The film as E h w (E = 4.5 GPa, 23 um x 1 m: EA 103.5 kN), or the same as a table of
    stress; strains powers of two so that E ε and σ/ε are exact (the table's EA then has the
    modulus path's bits). ``third``: the third point's stress over E ε (1: on the line)."""
    film: dict = {"ea": None, "modulus": 4.5e9}
    if table:
        strain = [0.0, 2.0 ** -7, 2.0 ** -6]
        stress = [0.0, 4.5e9 * strain[1], 4.5e9 * strain[2] * (third or 1.0)]
        film = {"ea": None, "modulus": None,
                "stress_strain": {"law": "table", "strain": strain, "stress": stress}}
    return film


def _without_none(data: dict) -> dict:
    for web in data["webs"]:
        if "web" in web:
            web["web"] = {k: v for k, v in web["web"].items() if v is not None}
    return data


def test_a_table_equal_to_the_linear_law_gives_the_linear_run_bit_for_bit():
    """A table on T = EA ε is the linear law (its array is [LINEAR]): the layer upset's
    tensions are bit-identical to the film given by its modulus. A third point off the line
    (strain 1.6 %, far beyond the run's 0.15 %) makes the law nonlinear, so the kernel's law
    path runs (tensions F(s), the nip's F_L⁻¹ of the layers' sum, the unwind's F⁻¹ of its
    wound-in tension): it gives the same run to rounding, 1e-9 of 180 N being ~1e7 times
    the double's resolution of a piecewise-linear evaluation."""
    runs = [webline.simulate(load_branched(_without_none(_laminator(film=_film_by_modulus(t, x)))),
                             scenario="layer-upset", duration=3.0).dataset
            for t, x in ((False, None), (True, None), (True, 1.5))]
    assert np.array_equal(runs[0].tension.values, runs[1].tension.values)
    assert np.array_equal(runs[0].omega.values, runs[1].omega.values)
    assert np.max(np.abs(runs[2].tension.values - runs[0].tension.values)) < 1e-9 * 180.0


def test_the_laminate_carries_the_sum_of_its_layers_laws_at_their_own_strains():
    """A stiffening foil (power law, n = 1.5, ε_r = 1e-4): at the operating point the
    laminate zone's tension, its reference 180 N = 120 N + 60 N (no draw across the nip), is
    T_film(ε_film) + T_foil(ε_foil) at the strains the layers were bonded with, their own
    zones' (issue 35: bonded layers keep their strains), each law evaluated here from its
    formula, to 1e-9 N (the solver's XTOL 1e-13 on the scaled unknowns); the run's layer
    tensions are those laws too."""
    line = load_branched(_laminator(foil={"stress_strain": POWER}))
    plan = compile_branches(line)
    point = operating_point(plan)
    film_strain = point.x[_span(line, "film_zone")] / EA_FILM
    foil_strain = point.x[_span(line, "foil_zone")] / EA_FOIL
    film = EA_FILM * film_strain
    foil = EA_FOIL * 1e-4 * (foil_strain / 1e-4) ** 1.5
    assert film == pytest.approx(120.0, abs=1e-9) and foil == pytest.approx(60.0, abs=1e-9)
    ds = webline.simulate(line, duration=0.2).dataset
    assert ds.tension.sel(span="laminate_zone").values[0] == pytest.approx(180.0, abs=1e-9)
    layers = ds.layer_tension.isel(time=0)
    assert float(layers.sel(layer_span="laminate_zone/film")) == pytest.approx(film, abs=1e-8)
    assert float(layers.sel(layer_span="laminate_zone/foil")) == pytest.approx(foil, abs=1e-8)
    # each web's unstrained length balance (B1 in strain) still closes
    for row in webline.simulate(line, scenario="layer-upset", duration=3.0).web_summary():
        assert row["length_balance_drift_m"] < 1e-7


def test_a_stiffening_foil_raises_the_laminate_mode_by_its_tangent_stiffness():
    """The laminate guide's span mode (1038 rad/s) is the guide's inertia on the two
    laminate spans: ω² ≈ (E_t A)(1/L_1 + 1/L_2) r²/J, both spans at one draw, so the power
    foil scales it by √(Σ dT_i/dε / EA_L), the tangent stiffness at the layers' own strains
    from first principles: EA_film + n EA_foil (ε_foil/ε_r)^(n-1), ε_foil its zone's (the
    foil is bonded at its 60 N). The neighbours' inertia terms
    (nip, rewind: ~2 % of the guide's r²/J) scale alike; the spans' strains differ by the
    guide's friction (0.05 N of 180 N); tolerance 1e-3 (measured 7e-5)."""
    def guide_mode(line) -> float:  # the line's fastest oscillation (docs: 1038 rad/s)
        return float(np.max(np.linalg.eigvals(linear_model(line, loop="open").a).imag))

    linear = load_branched("laminator")
    stiff = load_branched(_laminator(foil={"stress_strain": POWER}))
    strain = operating_point(compile_branches(stiff)).x[_span(stiff, "foil_zone")] / EA_FOIL
    tangent = EA_FILM + 1.5 * EA_FOIL * (strain / 1e-4) ** 0.5
    predicted = np.sqrt(tangent / (EA_FILM + EA_FOIL))
    ratio = guide_mode(stiff) / guide_mode(linear)
    assert predicted > 1.15  # the foil is 1.5x as stiff (tangent) at its operating strain
    assert ratio == pytest.approx(predicted, rel=1e-3)


def test_a_bilinear_foil_past_its_yield_is_a_yield_finding_naming_the_foil():
    """Yield at 0.02 % strain, 0.5 E beyond. At the laminate's 180 N the bonded foil keeps
    its zone's strain (60 N: 0.0095 %): no finding (a shared strain, 0.0245 %, gave a false
    one). The laminate zone at 300 N draws every layer by Δ with 120 + 103.5 kN Δ + F_foil
    (0.0095 % + Δ) = 300 N: Δ = 0.0208 %, the foil at 0.0303 %, beyond yield in both
    laminate spans from t = 0 while its own zone stays below. The finding names the foil
    web (a layer of the laminate) and its peak strain, which mass conservation gives from the
    nip's and the rewind's speeds (the laminate's last span: ε = 1 - v_nip/v_b (1 - ε_up))."""
    law = {"law": "bilinear", "yield_strain": 2e-4, "hardening": 0.5}
    calm = webline.simulate(load_branched(_laminator(foil={"stress_strain": law})),
                            duration=0.5)
    assert not [f for f in calm.verdict.findings if f.kind == "yield"]
    data = _laminator(foil={"stress_strain": law})
    data["webs"][2]["spans"][0]["tension"] = 300.0
    result = webline.simulate(load_branched(data), duration=0.5)
    found = [f for f in result.verdict.findings if f.kind == "yield"]
    assert [f.where for f in found] == ["foil"]
    assert "laminate laminate" in found[0].message and "laminate_zone" in found[0].message
    ds = result.dataset
    nip = 0.1 * ds.omega.sel(node="nip").values[0]
    rewind = float(ds.speed.sel(node="rewind").values[0])
    up = float(ds.strain.sel(span="foil_zone").values[0])
    assert found[0].details["peak_strain"] == pytest.approx(1 - nip / rewind * (1 - up),
                                                            rel=1e-3)
    assert found[0].details["peak_strain"] == pytest.approx(3.03e-4, rel=1e-2)
    assert found[0].details["first_s"] == 0.0
    assert result.verdict.status == "warning"
    assert float(ds.strain.sel(span="foil_zone").max()) < 2e-4
    from webline.report.plots.branch_figures import layers_caption  # says what it draws

    assert "its own law at the strain it was bonded with" in layers_caption(result)


def test_a_foil_layer_at_its_strength_stops_the_run_naming_it():
    """The laminate's reference steps 180 -> 260 N at 1 s. The bonded foil carries its own
    60 N before and 60 + 80 EA_foil / EA_L = 128.7 N after: with a strength of 100 N the run
    stops, failed, when the laminate zone's foil layer reaches 100 N, naming the foil and
    its laminate; with 170 N (a shared strain broke it at 197.9 N on the 220 N step) it
    runs on."""
    def run(strength: float, step: float):
        data = _laminator(foil={"strength": strength})
        data["webs"][2]["spans"][0]["tension"] = {
            "type": "steps", "initial": 180.0, "steps": [{"time": 1.0, "value": step}]}
        return webline.simulate(load_branched(data), duration=3.0, raise_on_failure=False)

    assert run(170.0, 220.0).failure is None
    result = run(100.0, 260.0)
    assert result.failure is not None
    assert "web foil (a layer of laminate laminate) broke" in result.failure
    assert result.verdict.status == "failed"
    assert [f.kind for f in result.verdict.findings if f.level == "failed"] == [
        "strength_exceeded"]
    foil = result.dataset.layer_tension.sel(layer_span="laminate_zone/foil").values
    # records every tick (1 ms): the last is below 100 N, within one tick's rise of it
    assert foil[-1] < 100.0 < foil[-1] + 2.0 * np.max(np.diff(foil))
    assert float(result.time[-1]) > 1.0


def test_a_lane_at_its_share_of_the_base_webs_strength_stops_the_run_naming_it():
    """Slitter, thickness profile: lane_1 (400 mm, 1 % thicker: φ = 0.3232 of the base web)
    rises towards 147 N. The base web's strength 433.17 N is 140 N for lane_1 (its area
    share, same breaking strain): the run stops there, naming lane_1."""
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    phi = 0.4 / 1.25 * 1.01
    data["web"]["strength"] = 140.0 / phi
    result = webline.simulate(load_branched(data), scenario="thickness-profile",
                              raise_on_failure=False)
    assert result.failure is not None and result.failure.startswith("lane lane_1 broke")
    lane = result.dataset.tension.sel(span="lane_1_span").values
    assert lane[-1] < 140.0 < lane[-1] + 2.0 * np.max(np.abs(np.diff(lane[-100:])))


def test_kelvin_voigt_laminate_spans_damp_the_guide_mode_by_tau_omega_over_two():
    """A damper in both laminate spans: the guide's mode (ω_n 1038 rad/s) gains
    ζ = τ ω_n / 2 (docs/winder.md's hand formula: a damper τ k on the spring k): τ = 0.1 ms
    adds 0.0519. Tolerance 3 % of the added damping (the transport term and the nip's and
    rewind's share of the mode); τ = 1 ns gives the elastic run to 1e-6 N."""
    def damped(tau: float | None) -> tuple[float, object]:
        data = _laminator()
        if tau is not None:
            for span in data["webs"][2]["spans"]:
                span.update(model="kelvin-voigt", retardation=tau)
        line = load_branched(data)
        values = np.linalg.eigvals(linear_model(line, loop="open").a)
        mode = max((v for v in values if 1000 < v.imag < 1100), key=lambda v: v.imag)
        return -mode.real / abs(mode), line

    zeta_0, elastic = damped(None)
    zeta_1, _ = damped(1e-4)
    assert zeta_1 - zeta_0 == pytest.approx(1e-4 * 1038.4 / 2, rel=0.03)
    _, tiny = damped(1e-9)
    a = webline.simulate(elastic, scenario="layer-upset", duration=2.5).dataset.tension.values
    b = webline.simulate(tiny, scenario="layer-upset", duration=2.5).dataset.tension.values
    assert np.max(np.abs(a - b)) < 1e-6


@pytest.mark.parametrize(("change", "key", "problem"), [
    (lambda d: d["webs"][1]["web"].update(stress_strain={"law": "power", "exponent": 1.5}),
     r"webs\[1\]\.web\.stress_strain\.reference_strain", "needs its reference_strain"),
    (lambda d: d["webs"][0]["web"].update(stress_strain={
        "law": "table", "strain": [0.0, 0.01], "stress": [0.0, 4.5e7]}),
     r"webs\[0\]\.web\.modulus", "gives the web's stiffness itself"),
    (lambda d: d["webs"][1]["web"].update(stress_strain={
        "law": "bilinear", "yield_strain": 0.003, "hardening": 0.0}),
     r"webs\[1\]\.web\.stress_strain\.hardening", "must be > 0"),
    (lambda d: d["webs"][2]["spans"][0].update(model="kelvin-voigt"),
     r"webs\[2\]\.spans\[0\]\.retardation", "needs its retardation time"),
    (lambda d: d["webs"][2]["spans"][0].update(retardation=1e-3),
     r"webs\[2\]\.spans\[0\]\.retardation", "only a span with model = 'kelvin-voigt'"),
    (lambda d: d["webs"][1]["web"].update(strength=-5.0), r"webs\[1\]\.web\.strength", ""),
])
def test_bad_web_laws_are_one_line_naming_the_key(change, key, problem):
    data = _laminator()
    change(data)
    with pytest.raises(LineFileError, match=key) as error:
        load_branched(data)
    assert problem in str(error.value) and "\n" not in str(error.value)


@pytest.mark.parametrize("damper", [None, 5e-4])
def test_the_closed_loop_model_with_web_laws_is_the_runs(damper):
    """A 2 N step of the laminate zone's reference at 1 s on the laminator with the power-law
    foil (and, second case, dampers of τ = 0.5 ms in both laminate spans): the run minus the
    same run without the step against the closed-loop linear model's step response, whose
    loadcell rows and tension outputs are the felt tension's, F'(s) (+ τ ds/dt). As in
    test_branch_linear_response (same tolerance, same reasons: the 1 kHz sampling's held
    torque, second-order terms), 5 % of each response's peak; a loadcell reading the stretch
    instead of F(s) (F' = 1.9 here) moves the responses by tens of %."""
    from scipy.linalg import expm

    from webline.sim.branches.linear import branch_linear_model

    def line(step: float):
        data = _laminator(foil={"stress_strain": POWER})
        data.pop("scenarios")
        data["webs"][2]["spans"][0]["tension"] = {
            "type": "steps", "initial": 180.0, "steps": [{"time": 1.0, "value": 180.0 + step}]}
        if damper is not None:
            for span in data["webs"][2]["spans"]:
                span.update(model="kelvin-voigt", retardation=damper)
        return load_branched(data)

    runs = [webline.simulate(line(step), duration=3.0).dataset for step in (0.0, 2.0)]
    plan = compile_branches(line(2.0))
    model = branch_linear_model(plan, operating_point(plan), "closed")
    n = model.a.shape[0]
    augmented = np.zeros((n + 1, n + 1))
    augmented[:n, :n] = model.a
    augmented[:n, n] = model.b[:, model.inputs.index("laminate_zone_tension_ref")] * 2.0
    time = runs[1].time.values
    after = time >= 1.0
    steps = [expm(augmented * (t - 1.0))[:n, n] for t in time[after][::10]]
    for zone in ("laminate_zone", "foil_zone", "film_zone"):
        simulated = (runs[1].tension.sel(span=zone) - runs[0].tension.sel(span=zone)).values
        row = model.c[model.outputs.index(f"{zone}_tension")]
        linear = np.array([row @ x for x in steps])
        peak = np.max(np.abs(linear))
        assert peak > 0.05  # N: each zone feels the step (the layers through the nip)
        assert np.max(np.abs(simulated[after][::10] - linear)) < 0.05 * peak, zone


def test_a_lane_of_a_laminate_carries_its_share_of_the_layers_laws():
    """The laminator's laminate slit at a knife into two 0.5 m lanes (φ = 0.5 each: the
    laminate is 1 m wide) on one shaft, the foil on its power law: at the operating point
    each lane's tension, the 90 N its loadcell holds, is φ (T_film(ε_film) + T_foil(ε_foil))
    at the layers' own strains, which exact mass conservation of each layer (the line's
    default transport, docs/errata.md E-6.6) gives from the nip's and the lane's roll's speeds
    alone: v_nip / (1 + ε_up) = v_lane / (1 + ε), ε = (1 + ε_up) v_lane / v_nip - 1 (ε_up the
    layer's zone strain; 1e-6 N, measured 7e-11 N); the knife span carries the lanes' layers
    at their strains (measured 2e-11 N; the first-order form, ε = 1 - v_nip / v_b (1 - ε_up),
    is 4e-5 N off there)."""
    line = laminated_then_slit(
        lambda data: data["webs"][1]["web"].__setitem__("stress_strain", POWER))
    assert line.exact
    plan = compile_branches(line)
    x = operating_point(plan).x
    names = [r.name for r in line.spec.rollers]
    v_nip = 0.1 * x[plan.offsets[0] + names.index("nip")]
    film_up = x[_span(line, "film_zone")] / EA_FILM
    foil_up = x[_span(line, "foil_zone")] / EA_FOIL

    def laminate(v_b: float) -> float:
        film, foil = ((1.0 + e) * v_b / v_nip - 1.0 for e in (film_up, foil_up))
        return EA_FILM * film + EA_FOIL * 1e-4 * (foil / 1e-4) ** 1.5

    omega = x[plan.offsets[0] + names.index("rewind")]
    for j, roll in enumerate(line.rolls):
        if line.spec.webs[roll.web].name.startswith("lane"):
            v_lane = x[plan.offsets[1] + j] * omega
            assert 0.5 * laminate(v_lane) == pytest.approx(90.0, abs=1e-6)
    ds = webline.simulate(line, duration=0.1).dataset
    knife = _span(line, "laminate[1]")
    v_knife = 0.05 * float(ds.omega.isel(time=0).sel(node="knife"))
    assert float(ds.tension.isel(time=0, span=knife)) == pytest.approx(laminate(v_knife),
                                                                       abs=1e-6)


def test_a_study_judges_each_case_on_its_foils_yield():
    """A sweep of the bilinear foil's yield strain, the laminate zone at 300 N: at 0.02 % the
    bonded foil (0.0303 %) is past it, a warning on the foil web (``web_status``); at 0.05 %
    nothing yields."""
    law = {"law": "bilinear", "yield_strain": 2e-4, "hardening": 0.5}
    data = _laminator(foil={"stress_strain": law})
    data["webs"][2]["spans"][0]["tension"] = 300.0
    ds = webline.sweep(load_branched(data),
                       {"webs.foil.web.stress_strain.yield_strain": [2e-4, 5e-4]}, duration=0.2)
    assert list(ds.status.values) == ["warning", "ok"]
    assert list(ds.web_status.sel(web="foil").values) == ["warning", "ok"]
    assert list(ds.web_status.sel(web="laminate").values) == ["ok", "ok"]


def test_a_damped_first_span_feels_the_wound_in_tension_through_its_rate():
    """A Kelvin-Voigt first span (the film unwind's, τ = 5 ms) with the film's loadcell on it:
    T = s + τ ds/dt and (B1) in the laminator's exact transport (docs/errata.md E-6.6),
    L ds/dt = (EA + s)² [v_b/(EA + s) - v_a/(EA + T0)] with T0 the wound-in tension, so
    ∂T/∂T0 = τ v_a / L ((EA + s)/(EA + T0))² (v_a the unwind's surface speed 2.5 m/s, L 1.5 m,
    s = 120 N, T0 = 100 N): 8.33e-3 (first order, thesis 6.8: τ v_a / L), which the closed
    loop's loadcell reads (Kw, Gw) and no elastic span has. Central differences of 1 N on a
    rate whose second derivative in T0 is 2/(EA + T0) of its first: 1e-10 relative (1e-9)."""
    from webline.sim.branches.findings.web_findings import felt_wound_rows
    from webline.sim.branches.linear import wound_gains, wound_webs

    data = _laminator()
    spans = data["webs"][0]["spans"]
    spans[0].update(model="kelvin-voigt", retardation=5e-3, tension=spans[1].pop("tension"))
    line = load_branched(data)
    plan = compile_branches(line)
    point = operating_point(plan)
    felt = felt_wound_rows(plan, point.x, wound_webs(plan))
    film = wound_webs(plan).index(0)
    from webline.sim.branches.loop import layout as B

    assert line.exact
    v_a = point.x[plan.offsets[B.O_OMEGA] + 0] * line.rolls[0].radius  # unwind ω x radius
    s, wound_in = point.x[0], 100.0  # the first span's stretch; laminator.toml's film roll
    assert s == pytest.approx(120.0, abs=1e-6)  # the loadcell's, steady (T = s)
    strain = ((EA_FILM + s) / (EA_FILM + wound_in)) ** 2
    assert felt[0, film] == pytest.approx(5e-3 * v_a / 1.5 * strain, rel=1e-9)
    assert np.count_nonzero(felt) == 1  # no other span feels it directly
    kw, gw = wound_gains(plan, point)
    assert kw[0, film] != 0.0 and gw[len(line.drives), film] != 0.0  # the unwind's PI
