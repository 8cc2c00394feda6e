"""Bonded laminates (issue 35, item 1; docs/branching.md (B2)): every layer keeps the
strain it was bonded with at the nip, so each layer's tension is its own law at its own
strain and the laminate's tension their sum.

Kinematics checked here from first principles, independent of the kernel: bonded layers
move at one speed, so the unstrained flow of layer i through a section at speed v is
v (1 - ε_i) (first order, thesis 6.8). Between the nip (speed v_a) and a roller downstream
(speed v_b) each layer's steady flow is conserved: v_b (1 - ε_i) = v_a (1 - ε_i,up), which
shifts every layer's strain by the same draw to first order, ε_i = ε_i,up + (v_b/v_a - 1)
(1 - ε_i,up); the layers keep the strain difference they were bonded with."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.model.web_graph import load_branched
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import linear_model
from webline.sim.branches.plan import compile_branches

EA_FILM, EA_FOIL = 103.5e3, 630e3  # N: the laminator's layers (its file's header)
EA_L = EA_FILM + EA_FOIL
POWER = {"law": "power", "exponent": 1.5, "reference_strain": 1e-4}


def _laminator(foil: dict | None = None, laminate_tension: float | None = None) -> dict:
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    if foil is not None:
        data["webs"][1]["web"].update(foil)
    if laminate_tension is not None:
        data["webs"][2]["spans"][0]["tension"] = laminate_tension
    return data


def _span(line, name: str) -> int:
    return next(s.index for s in line.spans if s.name == name)


def _power_foil(strain: np.ndarray | float) -> np.ndarray | float:
    """The power-law foil's tension [N] at its strain: EA ε_r (ε / ε_r)^n."""
    return EA_FOIL * 1e-4 * (np.asarray(strain) / 1e-4) ** 1.5


def test_the_laminators_layers_carry_their_own_zones_tensions():
    """The line file sets the film zone to 120 N, the foil zone to 60 N and the laminate
    zone to 180 N = 120 + 60: the laminate's reference is the sum of its layers', so there
    is no draw across the nip (v_b = v_a above) and each layer leaves the nip with the strain
    it came in with, film 120 N / EA_film and foil 60 N / EA_foil: 120 N and 60 N in the
    laminate. (A shared strain would give EA_i / EA_L x 180 N: 25.4 N and 154.6 N.)
    Tolerance 0.5 % (the brief's): the zones settle on their PI loops' references."""
    ds = webline.simulate("laminator", duration=1.0).dataset
    layers = ds.layer_tension.isel(time=-1)
    strains = ds.layer_strain.isel(time=-1)
    assert float(strains.sel(layer_span="laminate_zone/film")) == pytest.approx(
        120.0 / EA_FILM, rel=5e-3
    )
    assert float(strains.sel(layer_span="laminate_zone/foil")) == pytest.approx(
        60.0 / EA_FOIL, rel=5e-3
    )
    for span in ("laminate_zone", "laminate[1]"):
        assert float(layers.sel(layer_span=f"{span}/film")) == pytest.approx(120.0, rel=5e-3)
        assert float(layers.sel(layer_span=f"{span}/foil")) == pytest.approx(60.0, rel=5e-3)
        assert float(
            layers.sel(layer_span=f"{span}/film") + layers.sel(layer_span=f"{span}/foil")
        ) == pytest.approx(float(ds.tension.isel(time=-1).sel(span=span)), rel=1e-9)


def test_each_layers_length_is_conserved_through_the_nip_and_the_laminate():
    """Layer upset (the film zone steps 120 -> 150 N at 2 s) over 10 s: the unstrained film
    and foil that leave their own webs at the nip are what enters the laminate as that layer,
    and each layer's balance over the laminate (in - out - stored) stays constant, both to
    1e-9 of the length that passed (~25 m; the RK4 sums' rounding is ~1e-13 of it)."""
    result = webline.simulate("laminator", scenario="layer-upset", duration=10.0)
    ds = result.dataset
    for layer in ("film", "foil"):
        passed = float(ds.web_out.sel(web=layer)[-1] - ds.web_out.sel(web=layer)[0])
        assert passed > 24.0
        into = ds.layer_in.sel(layer_web=f"laminate/{layer}").values
        left = ds.web_out.sel(web=layer).values
        assert np.max(np.abs((into - into[0]) - (left - left[0]))) < 1e-9 * passed
        balance = (
            into
            - ds.layer_out.sel(layer_web=f"laminate/{layer}").values
            - ds.layer_stored.sel(layer_web=f"laminate/{layer}").values
        )
        assert np.max(np.abs(balance - balance[0])) < 1e-9 * passed


def test_a_laminate_zone_below_its_layers_sum_compresses_the_foil():
    """The laminate zone at 40 N, the layers' zones at 120 N and 60 N: the laminate is 140 N
    below its layers' sum, which every layer's strain shares (a draw of -140 N / EA_L), so
    the foil carries 60 - 140 EA_foil / EA_L = -60.25 N (a wrinkle risk) and the film
    120 - 140 EA_film / EA_L = 100.25 N. The verdict names the compressed layer, its span,
    when and how far below zero."""
    result = webline.simulate(load_branched(_laminator(laminate_tension=40.0)), duration=3.0)
    layers = result.dataset.layer_tension.isel(time=-1)
    foil = 60.0 - 140.0 * EA_FOIL / EA_L
    assert float(layers.sel(layer_span="laminate_zone/foil")) == pytest.approx(foil, rel=5e-3)
    assert float(layers.sel(layer_span="laminate_zone/film")) == pytest.approx(
        120.0 - 140.0 * EA_FILM / EA_L, rel=5e-3
    )
    found = [f for f in result.verdict.findings if f.kind == "layer_compressed"]
    assert [f.where for f in found] == ["foil"]
    assert found[0].level == "warning"
    assert "laminate_zone" in found[0].message and "laminate laminate" in found[0].message
    assert found[0].time == 0.0  # from the start: the operating point is at 40 N
    assert found[0].details["duration_s"] == pytest.approx(3.0, abs=2e-3)
    assert found[0].details["min_tension_N"] == pytest.approx(foil, rel=5e-3)
    assert not [
        f
        for f in webline.simulate("laminator", duration=1.0).verdict.findings
        if f.kind == "layer_compressed"
    ]


def test_a_power_law_laminate_under_a_draw_is_the_sum_of_its_layers_at_their_strains():
    """A stiffening foil (power law, n = 1.5, ε_r = 1e-4) and the laminate zone at 220 N, a
    draw over the layers' 180 N. Each layer's strain from the operating point's speeds alone
    (module docstring: ε_i = 1 - (v_a / v_b)(1 - ε_i,up), v_a the nip's, v_b the laminate
    guide's, ε_i,up the layer's own zone strain) and its law give the laminate zone's
    tension within 0.5 % (measured: rounding). The guide's mode scales with the root of the
    tangent stiffness at the layers' own strains, EA_film + n EA_foil (ε_foil/ε_r)^(n-1),
    against the linear laminator's: within 0.5 % (the neighbours' terms, ~2 %, scale alike)."""
    line = load_branched(_laminator(foil={"stress_strain": POWER}, laminate_tension=220.0))
    plan = compile_branches(line)
    point = operating_point(plan)
    x = point.x
    off_w = plan.offsets[0]
    names = [r.name for r in line.spec.rollers]
    v_a = 0.1 * x[off_w + names.index("nip")]
    v_b = 0.05 * x[off_w + names.index("guide_laminate")]
    film_up = x[_span(line, "film_zone")] / EA_FILM
    foil_up = x[_span(line, "foil_zone")] / EA_FOIL
    assert EA_FILM * film_up == pytest.approx(120.0, rel=1e-9)
    assert _power_foil(foil_up) == pytest.approx(60.0, rel=1e-9)
    film, foil = (1.0 - v_a / v_b * (1.0 - e) for e in (film_up, foil_up))
    assert film - film_up > 3e-5  # a real draw (40 N over the laminate's ~1.3 MN tangent)
    assert EA_FILM * film + _power_foil(foil) == pytest.approx(220.0, rel=5e-3)
    ds = webline.simulate(line, duration=0.2).dataset
    assert float(
        ds.layer_tension.isel(time=0).sel(layer_span="laminate_zone/foil")
    ) == pytest.approx(float(_power_foil(foil)), rel=5e-3)

    def guide_mode(line) -> float:  # the line's fastest oscillation (docs: 1038 rad/s)
        return float(np.max(np.linalg.eigvals(linear_model(line, loop="open").a).imag))

    at_180 = load_branched(_laminator(foil={"stress_strain": POWER}))
    tangent = EA_FILM + 1.5 * EA_FOIL * (foil_up / 1e-4) ** 0.5
    predicted = np.sqrt(tangent / EA_L)
    ratio = guide_mode(at_180) / guide_mode(load_branched("laminator"))
    assert ratio == pytest.approx(predicted, rel=5e-3)


def test_a_lane_of_a_laminate_carries_each_layers_strain_and_length_through_the_knife():
    """The laminate slit into two lanes on one shaft (``branch_support``): a lane leaves the
    knife with the laminate's strains, layer by layer, so each layer's unstrained length out
    of the laminate is what enters each lane as that layer (a lane is a strip of the same
    length), and each lane's layer balance closes, to 1e-9 of the length that passed. The
    lanes' layers carry their area share (φ = 0.5) of the layers' tensions: with no draw
    after the nip (the lanes at 90 N each) 60 N and 30 N per lane."""
    from branch_support import laminated_then_slit

    result = webline.simulate(laminated_then_slit(), duration=3.0)
    ds = result.dataset
    for layer in ("film", "foil"):
        left = ds.layer_out.sel(layer_web=f"laminate/{layer}").values
        passed = float(left[-1] - left[0])
        assert passed > 7.0
        for lane in ("lane_a", "lane_b"):
            into = ds.layer_in.sel(layer_web=f"{lane}/{layer}").values
            assert np.max(np.abs((into - into[0]) - (left - left[0]))) < 1e-9 * passed
            balance = (
                into
                - ds.layer_out.sel(layer_web=f"{lane}/{layer}").values
                - ds.layer_stored.sel(layer_web=f"{lane}/{layer}").values
            )
            assert np.max(np.abs(balance - balance[0])) < 1e-9 * passed
    plan = result.plan
    line = plan.line
    from webline.sim.branches.laminates import layer_rows, layer_stretch, mirrored_tension

    k = _span(line, "lane_a_span")
    tensions = {
        line.spec.webs[r].name: 0.5
        * float(mirrored_tension(line, r, layer_stretch(plan, t, result.states[-1:]))[0])
        for t, r in layer_rows(plan, k)
    }
    assert tensions["film"] == pytest.approx(60.0, rel=5e-3)
    assert tensions["foil"] == pytest.approx(30.0, rel=5e-3)


def test_a_laminate_of_a_laminate_keeps_each_raw_layers_strain_and_length():
    """A second, idle nip laminates a paper web (EA 200 kN, its zone at 50 N) onto the
    film-foil laminate: the outer laminate's layers are the inner laminate's film and foil
    (each with its own offset carried through the second nip) and the paper. The outer zone
    at 230 N = 120 + 60 + 50 leaves no draw anywhere (the idle nip's bearing drag aside), so
    each raw layer carries its own zone's tension in the outer laminate (film 120 N, foil
    60 N, paper 50 N, 0.5 %), and each raw layer's length passes the second nip unchanged
    (1e-9 of the length that passed)."""
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    rollers = {r["name"]: r for r in data["rollers"]}
    rewind = data["rollers"].pop()
    data["rollers"] += [
        {**rollers["unwind_film"], "name": "unwind_paper", "wound_in_tension": 40.0},
        {**rollers["guide_film"], "name": "guide_paper"},
        {**rollers["guide_film"], "name": "nip_2"},
        {**rollers["guide_film"], "name": "guide_outer"},
        rewind,
    ]
    data["webs"][2]["path"] = ["nip", "guide_laminate", "nip_2"]
    data["webs"][2]["spans"][0].pop("tension")  # (an idle second nip: the rewind's zone)
    data["webs"] += [
        {
            "name": "paper",
            "web": {"ea": 200e3, "thickness": 1e-4, "width": 1.0, "density": 800.0},
            "path": ["unwind_paper", "guide_paper", "nip_2"],
            "spans": [{"length": 1.5}, {"name": "paper_zone", "length": 2.0, "tension": 50.0}],
        },
        {
            "name": "outer",
            "layers": ["laminate", "paper"],
            "path": ["nip_2", "guide_outer", "rewind"],
            "spans": [{"name": "outer_zone", "length": 2.0, "tension": 230.0}, {"length": 1.5}],
        },
    ]
    data["scenarios"] = {}
    result = webline.simulate(load_branched(data), duration=2.0)
    ds = result.dataset
    layers = ds.layer_tension.isel(time=-1)
    assert float(layers.sel(layer_span="outer_zone/paper")) == pytest.approx(50.0, rel=5e-3)
    assert float(layers.sel(layer_span="outer_zone/laminate")) == pytest.approx(180.0, rel=5e-3)
    plan = result.plan
    from webline.sim.branches.laminates import layer_rows, layer_stretch, mirrored_tension

    k = _span(plan.line, "outer_zone")
    own = {
        plan.line.spec.webs[r].name: float(
            mirrored_tension(plan.line, r, layer_stretch(plan, t, result.states[-1:]))[0]
        )
        for t, r in layer_rows(plan, k)
    }
    assert own["film"] == pytest.approx(120.0, rel=5e-3)
    assert own["foil"] == pytest.approx(60.0, rel=5e-3)
    for layer in ("film", "foil"):
        left = ds.layer_out.sel(layer_web=f"laminate/{layer}").values
        into = ds.layer_in.sel(layer_web=f"outer/{layer}").values
        passed = float(left[-1] - left[0])
        assert passed > 4.5
        assert np.max(np.abs((into - into[0]) - (left - left[0]))) < 1e-9 * passed
