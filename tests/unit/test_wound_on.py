"""Wound-on tension per layer from a run's radius and tension (physics.wound_on)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from webline.physics.wound_on import layers_from_run, wound_on_stress


def test_nip_adds_friction_over_thickness() -> None:
    """σ_w = T/(w h) + μ N/h: 150 N on 1.3 m of 23 µm film is 5.02 MPa; a 2 kN/m nip at
    μ = 0.3 adds 600 N/m / 23 µm = 26.1 MPa (Good, Wu & Fikes 1994)."""
    assert wound_on_stress(150.0, 1.3, 23e-6) == pytest.approx(150.0 / 1.3 / 23e-6)
    assert wound_on_stress(150.0, 1.3, 23e-6, 2000.0, 0.3) - wound_on_stress(
        150.0, 1.3, 23e-6
    ) == pytest.approx(0.3 * 2000.0 / 23e-6)


def test_step_lands_at_the_radius_wound_then() -> None:
    """A roll growing as the web arrives (2πR dR/dt = h v) with a tension step at 4 s: the
    layers below R(4 s) carry the first tension, those above the second, and each layer's
    time is the instant its radius was reached."""
    h, v, rc = 50e-6, 5.0, 0.1
    t = np.linspace(0.0, 10.0, 10001)
    r = np.sqrt(rc**2 + h * v * t / math.pi)  # integral of dR/dt = h v / (2π R)
    ten = np.where(t < 4.0, 100.0, 150.0)
    lay = layers_from_run(
        t,
        r,
        ten,
        core_radius=0.09,
        outer_radius=0.12,
        thickness=h,
        width=1.0,
        fill=lambda x: np.full_like(x, 80.0),
    )
    r_step = math.sqrt(rc**2 + h * v * 4.0 / math.pi)
    run = lay.in_run
    assert np.all(lay.tension[~run] == 80.0)  # outside the run: the fill
    assert np.all(lay.tension[run & (lay.radius < r_step - h)] == 100.0)
    assert np.all(lay.tension[run & (lay.radius > r_step + h)] == 150.0)
    expect = math.pi * (lay.radius[run] ** 2 - rc**2) / (h * v)
    np.testing.assert_allclose(lay.time[run], expect, atol=2e-3)  # record spacing 1 ms
    assert lay.radius[run][0] >= rc and lay.radius[run][-1] <= r[-1]
