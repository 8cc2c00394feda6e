"""A study case's plan patched from its base plan (issue 37 item 3, ``sim.core.plan_patch``)
equals the case's full plan to the last bit, for every kind of path hswl's Monte Carlo samples
(the web's EA) and the others the patch takes (strength, controller gains and bandwidths,
torque limits and lags), on lines with dancers, tapers, belts and decentralized drives; paths
that change the operating point's inputs or the node, span or profile tables (inertia,
friction, span length, initial radius, ratio, speed, sample rate) take a full plan; a map
that claimed a path it cannot patch is caught by the first case and the study takes full
plans; and a Monte Carlo study gives the same Dataset with patched plans as without."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.sim.core import plan_patch
from webline.sim.core.plan import _compile
from webline.sim.core.plan_patch import CasePlans, identical, patch_kind
from webline.sim.sweeps.cases import derive_line

EA = 2000 * 4.4482216152605  # hswl's EA [N]
PATCHED = [
    ("hswl", {"web.ea": 0.9 * EA}),
    ("hswl", {"web.ea": 1.1 * EA}),
    ("hswl", {"web.ea": 1.1 * EA, "rollers.process.controller.speed_kp": 3.0}),
    ("hswl", {"web.strength": 400.0}),
    ("hswl", {"rollers.process.controller.tension_bandwidth": 5.0}),
    ("hswl", {"rollers.unwind.controller.speed_bandwidth": 30.0}),
    ("hswl", {"rollers.rewind.controller.tension_ki": 0.02}),
    ("hswl", {"rollers[2].drive.torque_limit": 60.0, "rollers[2].drive.torque_lag": 0.003}),
    ("converter", {"web.modulus": 4.5e9}),
    ("converter", {"rollers.infeed.controller.speed_bandwidth": 60.0}),
    ("rockwell", {"web.modulus": 0.35e9}),
    ("rockwell", {"rollers.rewind.drive.torque_limit": 90.0}),
    ("sf", {"web.ea": 1.05 * EA}),
    ("sf", {"rollers.process.controller.speed_gain": 2.0}),
]
FULL = [
    {"rollers.unwind.inertia": 0.4},          # the operating point's inputs (inertia)
    {"rollers.process.friction": 1.0},        # the equilibrium torques and the node table
    {"spans.span2.length": 12.0},             # the span table
    {"rollers.unwind.radius": 0.3},           # initial radius: the op's inputs, the roll
    {"rollers.master.drive.ratio": 2.0},      # the node table
    {"speed": 3.0},                           # the profiles
    {"control.sample_rate": 500.0},           # the step
    {"web.ea": "9 kN"},                       # a text: only numbers patch
]


def _base(name: str) -> webline.Line:
    if name == "sf":  # decentralized state feedback on the process roller
        return webline.load_line("hswl").replace(
            {"rollers.process.controller": {"type": "state_feedback"}})
    return webline.load_line(name)


@pytest.mark.parametrize(("name", "changes"), PATCHED,
                         ids=[f"{n}:{','.join(c)}" for n, c in PATCHED])
def test_patched_plan_equals_full_plan(name, changes) -> None:
    base = _base(name)
    assert patch_kind(changes) is not None
    plans = CasePlans(base)
    plans._checked[frozenset(changes)] = True  # no first-case check: the patch itself
    patched = plans.plan_of(derive_line(base, changes), changes)
    assert plans.patched == 1
    full = _compile(derive_line(base, changes), None)
    assert identical(patched, full)
    assert not identical(patched, plans.plan)  # the case changed its plan


@pytest.mark.parametrize("changes", FULL, ids=lambda c: ",".join(c))
def test_other_paths_take_a_full_plan(changes) -> None:
    base = webline.load_line("hswl")
    assert patch_kind(changes) is None
    plans = CasePlans(base)
    plan = plans.plan_of(derive_line(base, changes), changes)
    assert plans.patched == 0
    assert identical(plan, _compile(derive_line(base, changes), None))


def test_identical_sees_one_bit() -> None:
    plan = webline.load_line("hswl")
    a = _compile(plan, None)
    b = _compile(plan, None)
    assert identical(a, b)
    b.drives[1, 3] = np.nextafter(b.drives[1, 3], np.inf)
    assert not identical(a, b)
    assert not identical(0.0, -0.0) and identical(float("nan"), float("nan"))


def test_a_wrong_claim_is_caught_by_the_first_case(monkeypatch) -> None:
    # the web's density changes the rolls' inertia (an input of the operating point) and
    # the node table: claimed patchable, the first case's check finds the difference
    monkeypatch.setitem(plan_patch._WEB_KEYS, "density", True)
    base = webline.load_line("hswl")
    plans = CasePlans(base)
    for density in (1200.0, 1300.0):
        changes = {"web.density": density}
        assert patch_kind(changes) is True
        plan = plans.plan_of(derive_line(base, changes), changes)
        assert identical(plan, _compile(derive_line(base, changes), None))
    assert plans.patched == 0


def test_monte_carlo_is_the_same_with_and_without_patches(monkeypatch) -> None:
    dists = {"web.ea": "uniform(1800 lbf, 2200 lbf)",
             "rollers.process.controller.speed_bandwidth": "uniform(30 rad/s, 50 rad/s)"}
    patched = webline.monte_carlo("hswl", dists, 6, seed=3, duration=0.5, workers=1)
    monkeypatch.setattr(plan_patch, "patch_kind", lambda changes: None)
    full = webline.monte_carlo("hswl", dists, 6, seed=3, duration=0.5, workers=1)
    assert set(patched.variables) == set(full.variables)
    for name in patched.variables:  # every variable and coordinate, NaN where NaN
        x, y = patched[name].values, full[name].values
        if x.dtype.kind == "f":
            np.testing.assert_array_equal(x, y)
        else:
            assert (x == y).all(), name
