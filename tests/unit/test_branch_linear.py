"""Linear models of branched lines (docs/branching.md, "Linear models"): the finite-difference
Jacobian of the kernel against one derived by hand from (B1)-(B4), the lamination nip as the
only coupling between the layers, the lanes' difference on one shaft, the tension loops' poles
against their tuning, the radii's slow modes, and stability at every built-in operating point."""

from __future__ import annotations

import math

import numpy as np
import pytest

from webline.model.web_graph import load_branched
from webline.physics.roller import COULOMB_SMOOTHING
from webline.physics.web_law import law_slope
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import (
    analysis_time,
    branch_linear_model,
    kept_states,
    plant_matrices,
    sampled_closed_loop,
    sampled_unstable_modes,
)
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import node_inertia
from webline.sim.branches.plan import compile_branches
from webline.sim.linear.stability import tolerance


def _at(name: str, scenario: str | None = None, t: float = 0.0):
    line = load_branched(name)
    if scenario is not None:
        line = line.with_scenario(scenario)
    plan = compile_branches(line)
    return plan, operating_point(plan, t)


def _hand_jacobian(plan, point) -> np.ndarray:
    """A of (B1)-(B4) derived by hand, radii frozen, at a taut ``point``:
    L dx_k/dt = EA (v_b - v_a) + s_in v_a - x_k v_b (first-order transport), or exactly
    L dx_k/dt = (EA + x_k) v_b - (EA + x_k)² v_a / (EA + s_in) (docs/errata.md E-6.6),
    v = r ω, s_in per (B2)/(B3);
    J dω_i/dt = n τ - b ω - c tanh(ω/ω_s) + Σ arm x; dτ/dt = (u - τ)/lag."""
    x, o = point.x, plan.offsets
    keep = kept_states(plan)
    col = {int(m): j for j, m in enumerate(keep)}
    a = np.zeros((len(keep), len(keep)))
    off_w = o[B.O_OMEGA]

    def arm(end_roll: int, node: int) -> float:
        return x[o[B.O_RADIUS] + end_roll] if end_roll >= 0 else plan.nodes[node, B.N_RADIUS]

    for k in range(plan.si.shape[0]):
        na, nb = plan.si[k, B.S_A], plan.si[k, B.S_B]
        ra, rb = arm(plan.si[k, B.S_ARMA], na), arm(plan.si[k, B.S_ARMB], nb)
        length, ea = plan.sf[k, B.SF_LENGTH], plan.sf[k, B.SF_EA]
        va, vb = ra * x[off_w + na], rb * x[off_w + nb]
        src, frm = plan.si[k, B.S_SRC], plan.si[k, B.S_FROM]
        sources: list[tuple[int, float]] = []  # (span, d s_in / d x_span)
        if src == B.SRC_PREVIOUS:
            sources = [(frm, 1.0)]
        elif src == B.SRC_LAYERS:
            sources = [(int(plan.layers[frm + j]), 1.0) for j in range(plan.si[k, B.S_COUNT])]
        elif src == B.SRC_SLIT:
            sources = [(frm, plan.sf[k, B.SF_SHARE])]
        s_in = (plan.wound[plan.si[k, B.S_WEB]] if src == B.SRC_WOUND
                else sum(share * x[j] for j, share in sources))
        if plan.offsets[B.O_EXACT]:
            grow, carried = ea + x[k], ea + s_in
            a[k, k] = (vb - 2.0 * grow * va / carried) / length
            for j, share in sources:
                a[k, j] += share * grow**2 * va / carried**2 / length
            a[k, col[off_w + na]] -= ra * grow**2 / carried / length
            a[k, col[off_w + nb]] += rb * grow / length
        else:
            a[k, k] = -vb / length
            for j, share in sources:
                a[k, j] += share * va / length
            a[k, col[off_w + na]] += ra * (s_in - ea) / length
            a[k, col[off_w + nb]] += rb * (ea - x[k]) / length
        ja = node_inertia(na, x, o, plan.nodes, plan.rolls)
        jb = node_inertia(nb, x, o, plan.nodes, plan.rolls)
        for j, slope in _felt_slopes(plan, x, k):  # d felt / d state (a span's own: 1)
            a[col[off_w + na], col[j]] += ra * slope / ja
            a[col[off_w + nb], col[j]] -= rb * slope / jb
        _layer_rows(plan, x, k, a, col, (ra, rb, va, vb), sources)
    for i in range(plan.nodes.shape[0]):
        inertia = node_inertia(i, x, o, plan.nodes, plan.rolls)
        omega = x[off_w + i]
        sech2 = 1.0 - math.tanh(omega / COULOMB_SMOOTHING) ** 2
        coulomb = plan.nodes[i, B.N_COULOMB] / COULOMB_SMOOTHING * sech2
        damping = plan.nodes[i, B.N_VISCOUS] + coulomb
        a[col[off_w + i], col[off_w + i]] = -damping / inertia
        d = int(plan.nodes[i, B.N_DRIVE])
        if d >= 0:
            tq = col[o[B.O_TORQUE] + d]
            a[col[off_w + i], tq] = plan.nodes[i, B.N_RATIO] / inertia
            a[tq, tq] = -plan.df[d, B.D_INVLAG]
    return a


def _terms(plan, k: int) -> list[int]:
    """Law terms of span ``k`` with an offset state (a bonded laminate's layers)."""
    first = plan.si[k, B.S_LAW0]
    return [t for t in range(first, first + plan.si[k, B.S_NLAW])
            if plan.si[k, B.S_NLAW] > 1 and plan.lawi[t, B.LI_STATE] >= 0]


def _felt_slopes(plan, x, k: int) -> list[tuple[int, float]]:
    """(state, d felt_k / d state): 1 on the span's own stretch, or for bonded layers
    T = Σ c F_r(u), u = a s + o: dT/ds = Σ c a F_r'(u), dT/do = c F_r'(u)."""
    terms = _terms(plan, k)
    if not terms:
        return [(k, 1.0)]
    out, ds = [], 0.0
    for t in terms:
        state = plan.lawi[t, B.LI_STATE]
        scale, factor = plan.lawf[t, B.LF_SCALE], plan.lawf[t, B.LF_FACTOR]
        slope = factor * law_slope(scale * x[k] + x[state],
                                   plan.laws[plan.lawi[t, B.LI_START]:])
        ds += scale * slope
        out.append((int(state), slope))
    return [(k, ds), *out]


def _layer_rows(plan, x, k: int, a, col, ends, sources) -> None:
    """Rows of span ``k``'s layer offsets o = u - a s, each layer's stretch u advected as a
    span's is (same form as (B1), the layer's own EA, its stretch in u_in = a_up s_up +
    o_up): exactly L du/dt = (EA + u) v_b - (EA + u)² v_a / (EA + u_in), first-order
    L do/dt = v_a o_in - v_b o with o_in = u_in - a s_in; do/dt = du/dt - a ds/dt."""
    ra, rb, va, vb = ends
    o, length = plan.offsets, plan.sf[k, B.SF_LENGTH]
    na, nb, off_w = plan.si[k, B.S_A], plan.si[k, B.S_B], o[B.O_OMEGA]
    for t in _terms(plan, k):
        row, scale = col[plan.lawi[t, B.LI_STATE]], plan.lawf[t, B.LF_SCALE]
        up, upscale = plan.lawi[t, B.LI_UP], plan.lawf[t, B.LF_UPSCALE]
        ins = [(up, upscale)] + ([(plan.lawi[t, B.LI_UPSTATE], 1.0)]
                                 if plan.lawi[t, B.LI_UPSTATE] >= 0 else [])
        own = [(k, scale), (plan.lawi[t, B.LI_STATE], 1.0)]
        if o[B.O_EXACT]:
            ea = plan.lawf[t, B.LF_EA]
            grow = ea + scale * x[k] + x[plan.lawi[t, B.LI_STATE]]
            carried = ea + sum(d * x[j] for j, d in ins)
            for j, d in own:
                a[row, col[j]] += d * (vb - 2.0 * grow * va / carried) / length
            for j, d in ins:
                a[row, col[j]] += d * grow**2 * va / carried**2 / length
            a[row, col[off_w + na]] -= ra * grow**2 / carried / length
            a[row, col[off_w + nb]] += rb * grow / length
            a[row, :] -= scale * a[k, :]  # less the laminate's a ds/dt (its row is done)
        else:  # o_in = u_in - a s_in, s_in = Σ share x_j over the span's sources (B2)
            offset = x[plan.lawi[t, B.LI_STATE]]
            o_in = sum(d * x[j] for j, d in ins) - scale * sum(d * x[j] for j, d in sources)
            for j, d in ins:
                a[row, col[j]] += d * va / length
            for j, d in sources:
                a[row, col[j]] -= scale * d * va / length
            a[row, row] -= vb / length
            a[row, col[off_w + na]] += ra * o_in / length
            a[row, col[off_w + nb]] -= rb * offset / length


@pytest.mark.parametrize("name", ["laminator", "slitter"])
def test_finite_difference_jacobian_matches_the_hand_derived_one(name):
    plan, point = _at(name)
    a, b, _ = plant_matrices(plan, point)
    hand = _hand_jacobian(plan, point)
    # entries span EA v/L^2-ish scales (1e-1 .. 1e6); the central difference is exact for the
    # affine and bilinear terms, so what is left is rounding, eps |f| / h with h = 1e-5 of
    # the state's scale: ~1e-9 of the largest entry. 1e-7 of it leaves room and still catches
    # any missing term (the smallest physical entry, -v/L ~ 1, is 1e-6 of 1e6)
    scale = np.max(np.abs(hand))
    assert np.max(np.abs(a - hand)) < 1e-7 * scale
    # and each entry to 1e-6 relative where it is not tiny
    big = np.abs(hand) > 1e-6 * scale
    assert np.allclose(a[big], hand[big], rtol=1e-6)
    kept = kept_states(plan)
    torques = (kept >= plan.offsets[B.O_TORQUE]) & (kept < plan.offsets[B.O_WEB])
    assert np.allclose(b[torques],
                       np.diag(plan.df[:, B.D_INVLAG]), rtol=1e-9)


def _block(model, prefixes):
    return [j for j, s in enumerate(model.states) if s.startswith(prefixes)]


@pytest.mark.parametrize("loop", ["open", "closed"])
def test_the_nip_couples_the_layer_zones_only_through_its_speed(loop):
    plan, point = _at("laminator")
    model = branch_linear_model(plan, point, loop)
    film = _block(model, ("film", "unwind_film", "guide_film"))
    foil = _block(model, ("foil", "unwind_foil", "guide_foil"))
    nip = model.states.index("nip_omega")
    assert len(film) >= 5 and len(foil) >= 5
    a = model.a
    # no state of one layer's zone acts on the other's directly: exact zeros (the rhs and
    # the controllers of one layer never read the other layer's states)
    assert not np.any(a[np.ix_(foil, film)]) and not np.any(a[np.ix_(film, foil)])
    # which outside states each layer's zone reads: only the nip's speed
    outside_foil = set(np.flatnonzero(np.any(a[foil] != 0.0, axis=0))) - set(foil)
    outside_film = set(np.flatnonzero(np.any(a[film] != 0.0, axis=0))) - set(film)
    assert outside_foil == outside_film == {nip}
    # and the nip's speed reads both layers' tensions (r T of each span ending on it)
    for zone in ("film_zone_tension", "foil_zone_tension"):
        assert a[nip, model.states.index(zone)] < 0.0


def test_lanes_difference_on_one_shaft_is_the_span_transport_pole():
    plan, point = _at("slitter")
    model = branch_linear_model(plan, point, "closed")
    values, vectors = np.linalg.eig(model.a)
    one, two = model.states.index("lane_1_span_tension"), model.states.index("lane_2_span_tension")
    # lane spans: v (1 - ε) at both ends with the shaft's surface speed v; the difference of
    # two equal lanes' strains obeys L dΔε/dt = -v Δε exactly (the shaft's ω, the knife's
    # strain and the controlled sum drop out): λ = -v/L, with v the lane's surface speed
    shaft = model.states.index("rewind_shaft_omega")
    v = point.x[plan.offsets[B.O_RADIUS] + plan.di[2, B.DI_ROLL]] * point.x[shaft]
    expected = -v / plan.line.spans[one].length
    j = int(np.argmin(np.abs(values - expected)))
    # a simple real eigenvalue of a 23x23 matrix of norm ~1e6 is exact to ~1e-10 of it
    assert abs(values[j] - expected) < 1e-6 * abs(expected)
    mode = vectors[:, j] / vectors[one, j]
    assert abs(mode[two] + 1.0) < 1e-9  # antisymmetric: one lane up, the other down
    assert np.max(np.abs(np.delete(mode, [one, two]))) < 1e-9  # nothing else moves


def test_with_radii_the_lanes_radius_difference_is_a_marginal_mode():
    plan, point = _at("slitter")
    model = branch_linear_model(plan, point, "closed", radii=True)
    values, vectors = np.linalg.eig(model.a)
    r1 = model.states.index("rewind_shaft/lane_1_radius")
    r2 = model.states.index("rewind_shaft/lane_2_radius")
    # dr_j/dt = h ω / 2π for both lanes of one shaft: r_1 - r_2 has no dynamics at all
    # (λ = 0; round-off of a matrix of norm ~1e6 leaves |λ| ~ 1e-10), nothing pulls it back
    zero = [j for j in range(len(values)) if abs(values[j]) < 1e-8]
    assert len(zero) == 1
    mode = vectors[:, zero[0]] / vectors[r1, zero[0]]
    assert abs(mode[r2] + 1.0) < 1e-6
    # the unwind's radius: with its surface speed held, dr/dt = -h v / (2π r) gives
    # λ = +h v / (2π r²): a smaller roll shrinks faster (slow, 1/λ ~ an hour); a rewind's
    # is -h v / (2π r²)
    h, v = 50e-6, 5.0
    for roll, sign in (("unwind/base_radius", 1.0), ("rewind_3/lane_3_radius", -1.0)):
        r = point.x[plan.offsets[B.O_RADIUS] + model.states.index(roll)
                    - len(plan.line.spans) - plan.nodes.shape[0]]
        expected = sign * h * v / (2 * math.pi * r * r)
        # v is the lane speed to the draw's ~1e-3 (strain), hence 1e-2 relative
        assert np.min(np.abs(values - expected)) < 1e-2 * abs(expected)


def _tension_pole(model, integral: str) -> complex:
    """The closed-loop eigenvalue (Im >= 0) in which ``integral`` participates most."""
    values, right = np.linalg.eig(model.a)
    part = np.abs(right * np.linalg.inv(right).T)
    j = model.states.index(integral)
    order = [m for m in np.argsort(-part[j]) if values[m].imag >= 0.0]
    return complex(values[order[0]])


def test_film_zone_pole_near_the_bandwidth_its_pi_was_tuned_for():
    plan, point = _at("laminator")
    model = branch_linear_model(plan, point, "closed")
    pole = _tension_pole(model, "unwind_film_tension_integral")
    # control.pi.tune places the zone's loop (plant EA/L / s, ideal speed loop) at a double
    # pole at -8 rad/s. The one-zone cascade with the speed loop as tuned (ζ = 1 at 40 rad/s)
    # and the span's transport v/L already splits it to -6.2 and -8.7 rad/s (±22 %): the
    # tolerance is 25 % on |λ|, and the mode must be well damped (ζ > 0.7, design 1)
    assert abs(abs(pole) - 8.0) < 0.25 * 8.0
    assert -pole.real / abs(pole) > 0.7


@pytest.mark.parametrize(("name", "scenario"), [
    ("laminator", None), ("laminator", "start-up"), ("laminator", "roll-change"),
    ("laminator", "layer-upset"), ("laminator", "flying-splice"), ("slitter", None),
    ("slitter", "start-up"),
    ("slitter", "thickness-profile")])
def test_every_mode_is_stable_at_every_operating_point(name, scenario):
    line = load_branched(name)
    line = line if scenario is None else line.with_scenario(scenario)
    end = 0.0 if scenario is None else line.spec.scenarios[scenario].duration
    plan = compile_branches(line)
    for t in {analysis_time(line), end}:  # a start from rest: at the end of its ramp
        point = operating_point(plan, t)
        values = np.linalg.eigvals(branch_linear_model(plan, point).a)
        # stability's own tolerance (sim.linear.stability: round-off of exact zeros)
        assert np.max(values.real) < -tolerance(values), (t, np.max(values.real))
        assert sampled_unstable_modes(plan, point) == []  # and the loop as sampled


def test_sampled_loop_keeps_the_slow_modes_of_the_continuous_one():
    plan, point = _at("laminator")
    mu = np.linalg.eigvals(sampled_closed_loop(plan, point)).astype(complex)
    sampled = np.log(mu) / plan.dt
    values = np.linalg.eigvals(branch_linear_model(plan, point).a)
    # the hold's half-period delay shifts a mode by ~|λ| dt/2 relative (5e-3 at 10 1/s):
    # the tension modes (|λ| < 10 1/s) agree to 1 % of |λ|
    for value in values[np.abs(values) < 10.0]:
        assert np.min(np.abs(sampled - value)) < 0.01 * abs(value)


def test_at_rest_the_slitter_idler_and_the_lanes_lose_their_transport_damping():
    line = load_branched("slitter").with_scenario("start-up")
    assert analysis_time(line) == pytest.approx(11.0)  # the ramp ends at 1 + 10 s
    plan = compile_branches(line)
    model = branch_linear_model(plan, operating_point(plan, 0.0))
    values = np.linalg.eigvals(model.a)
    # standing still, the lanes' difference has no -v/L to decay with: λ = 0 (round-off of a
    # matrix of norm ~1e6), and the knife idler's 101 Hz mode, damped at speed by transport
    # (Re λ -2.2), is left with bearing friction against the drives' torque lag: |ζ| < 1e-3
    assert np.min(np.abs(values)) < 1e-8
    idler = values[np.argmin(np.abs(np.abs(values) - 637.5))]
    assert abs(idler.real) < 1e-3 * abs(idler)


def test_webline_linearize_takes_a_branched_line():
    import webline
    from webline.analysis.modes import modes

    system = webline.linearize("laminator", "0 s")
    model = branch_linear_model(*_at("laminator"))
    assert system.nstates == len(model.states) and "film_zone_tension_ref" in system.input_labels
    # the same matrix, so the same modes (modes: slowest first; the film zone's at |λ| 6.8)
    assert np.allclose(system.A, model.a, rtol=0, atol=1e-9 * np.max(np.abs(model.a)))
    # slowest are the bonded layers' strain differences, which no loadcell feels (T = Σ c u):
    # each is carried out of its span at -v_b/L (the layers' offset rows); then the loops
    found = modes(system)
    plan, point = _at("laminator")
    for m, span in zip(found[:4], ["laminate_zone"] * 2 + ["laminate[1]"] * 2, strict=True):
        k = next(s.index for s in plan.line.spans if s.name == span)
        node, end = plan.si[k, B.S_B], plan.si[k, B.S_ARMB]
        radius = point.x[plan.offsets[B.O_RADIUS] + end] if end >= 0 else plan.nodes[
            node, B.N_RADIUS]
        v_b = radius * point.x[plan.offsets[B.O_OMEGA] + node]
        assert m.dominant.startswith(f"{span}/") and m.dominant.endswith("_offset")
        assert m.eigenvalue == pytest.approx(-v_b / plan.sf[k, B.SF_LENGTH], rel=1e-6)
    assert [m.dominant for m in found][4:7] == [
        "rewind_tension_integral", "unwind_foil_tension_integral",
        "unwind_film_tension_integral"]
    with pytest.raises(webline.ArgumentError, match=r"unwind_radius: 0\.05 m must be above"):
        webline.linearize("laminator", unwind_radius=0.05)  # inside the 76.2 mm cores
    assert webline.linearize("hswl").nstates > 0  # a single-path line as before


def test_closed_loop_modes_takes_a_branched_line():
    from webline.analysis.modes import closed_loop_modes

    found = closed_loop_modes("slitter")
    # slowest first: the lanes' difference (-v/L = -2.5 1/s) is the slowest mode at speed;
    # v is the lane's own speed, the line's 5 m/s to the strains' draw (~1e-3)
    assert found[0].eigenvalue == pytest.approx(-2.5, rel=1e-3)
    assert found[0].dominant in ("lane_1_span_tension", "lane_2_span_tension")
    assert all(m.damping > 0 for m in found)


@pytest.mark.parametrize("name", ["slitter", "laminator"])
def test_the_first_order_jacobian_matches_the_hand_derived_one(name):
    """The same check with the thesis's first-order transport (``web.transport``), the
    laminator's bonded layers' first-order rows too."""
    data = load_branched(name).spec.model_dump(exclude_none=True)
    for web in [data.get("web")] + [w.get("web") for w in data["webs"]]:
        if web is not None:
            web["transport"] = "first-order"
    plan = compile_branches(load_branched(data))
    assert plan.offsets[B.O_EXACT] == 0
    point = operating_point(plan, 0.0)
    a, _, _ = plant_matrices(plan, point)
    hand = _hand_jacobian(plan, point)
    assert np.max(np.abs(a - hand)) < 1e-7 * np.max(np.abs(hand))
