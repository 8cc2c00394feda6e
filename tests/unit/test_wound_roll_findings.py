"""The wound roll's findings from a run's records (sim.results.wound_roll), on synthetic
records: a dip in tension is a soft band at the radius and time it was wound; limits on
pressure, core and hoop name their numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from webline.sim.results.wound_roll import bands, wound_roll
from webline.spec.roll_stress import RollStressSpec

H, W, RC = 25e-6, 1.0, 0.08


def _records(dip: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A roll growing at 5 m/s from 85 mm (2πR dR/dt = h v) for 10 s; the tension is 120 N
    with a ``dip`` [N] between 4 and 5 s."""
    t = np.linspace(0.0, 10.0, 20001)
    r = np.sqrt(0.085**2 + H * 5.0 * t / math.pi)
    ten = 120.0 - dip * ((t >= 4.0) & (t < 5.0))
    return t, r, ten


def _roll(dip: float, **limits: object):
    spec = RollStressSpec(k1=1.5e3, k2=120.0, diameter=0.2, **limits)  # type: ignore[arg-type]
    t, r, ten = _records(dip)
    return (
        wound_roll(
            "rewind",
            spec,
            time=t,
            radius=r,
            tension=ten,
            core_radius=RC,
            thickness=H,
            width=W,
            modulus=4e9,
            steady_tension=lambda x: np.full(np.shape(x), 120.0),
        ),
        t,
        r,
    )


def test_bands_are_runs_of_true() -> None:
    found = bands(np.array([0, 1, 1, 0, 1, 0, 0, 1], dtype=bool))
    assert [(b.first, b.last) for b in found] == [(1, 2), (4, 4), (7, 7)]


def test_a_dip_is_a_soft_band_where_and_when_it_was_wound() -> None:
    roll, t, r = _roll(30.0)
    found = [f for f in roll.findings() if f.kind == "roll_band"]
    assert len(found) == 1
    band = found[0]
    assert "soft band" in band.message
    t0, t1 = band.details["time_s"]
    assert 4.0 <= t0 < 4.0 + 0.1 and 4.9 < t1 <= 5.0  # a layer every ~0.1 s here
    r0, r1 = band.details["radius_m"]
    assert r0 == pytest.approx(np.interp(4.0, t, r), abs=H)
    assert r1 == pytest.approx(np.interp(5.0, t, r), abs=2 * H)
    # the band's hoop stress is down by about the dip's share of the wound-on stress
    assert band.details["hoop_departure"] == pytest.approx(-30.0 / 120.0, abs=0.05)
    assert band.time == t0


def test_no_dip_no_band() -> None:
    roll, _, _ = _roll(0.0)
    assert not [f for f in roll.findings() if f.kind == "roll_band"]
    # the run's layers are exactly the steady roll's
    np.testing.assert_allclose(roll.stress.pressure, roll.steady.pressure, rtol=1e-12)


def test_limits_name_their_numbers() -> None:
    roll, _, _ = _roll(0.0, max_pressure=1e3, core_rating=1e3, min_hoop=1e9)
    kinds = {f.kind: f for f in roll.findings()}
    assert set(kinds) == {"roll_pressure", "roll_core", "roll_hoop"}
    core = kinds["roll_core"]
    assert core.details["core_pressure_Pa"] == roll.stress.core_pressure > 1e3
    assert kinds["roll_hoop"].details["layers"] == len(roll.stress.radius)  # all below 1 GPa
    assert kinds["roll_pressure"].details["max_pressure_Pa"] == roll.stress.pressure.max()


def _snapshot_roll(at_radii: list[float], **table: object):
    """The 10 s records with a 20 N dip, constant E_r = 60 MPa and a fibre core, kept at
    ``at_radii`` [m] (the records reach 87.4 mm)."""
    spec = RollStressSpec(
        model="constant",
        radial_modulus=60e6,
        core={"modulus": 3e9, "inner_radius": 0.07},  # type: ignore[arg-type]
        at_radii=at_radii,
        **table,  # type: ignore[arg-type]
    )
    t, r, ten = _records(20.0)
    return wound_roll(
        "rewind",
        spec,
        time=t,
        radius=r,
        tension=ten,
        core_radius=RC,
        thickness=H,
        width=W,
        modulus=4e9,
        steady_tension=lambda x: np.full(np.shape(x), 120.0),
    )


def test_snapshot_equals_the_closed_form_of_the_roll_truncated_there() -> None:
    """at_radii: the roll when its surface passed 85.5 and 86.5 mm (wound in the run, the
    second after the dip) is the constant-modulus closed form (Altmann-type superposition,
    ``linear_roll_stress``) of its first m layers, m = (r - r_c)/h, to 1e-6."""
    from webline.physics.roll_stress import core_modulus, linear_roll_stress

    roll = _snapshot_roll([0.0855, 0.0865], diameter=0.2)
    assert roll.missed == ()
    for snap, r in zip(roll.snapshots, (0.0855, 0.0865), strict=True):
        m = round((r - RC) / H)
        assert len(snap.stress.radius) == m
        closed = linear_roll_stress(
            roll.layers.stress[:m],
            RC,
            H,
            tangential_modulus=4e9,
            radial_modulus=60e6,
            poisson=0.01,
            core_stiffness=core_modulus(3e9, 0.3, 0.07, RC),
        )
        np.testing.assert_allclose(snap.stress.pressure, closed.pressure, rtol=1e-6)
        scale = np.abs(closed.hoop).max()
        np.testing.assert_allclose(snap.stress.hoop, closed.hoop, rtol=0, atol=1e-6 * scale)
        # when: the time its last layer (laid on r - h) was wound, on the growth law r(t)
        laid = r - H
        assert snap.time == pytest.approx(math.pi * (laid**2 - 0.085**2) / (H * 5.0), abs=1e-3)
    # the finished roll (to 100 mm) presses its core harder: the layers above press too
    assert roll.snapshots[1].stress.core_pressure < roll.stress.core_pressure
    xr_roll = roll.to_xarray()
    assert xr_roll.at_pressure.shape == (2, len(roll.stress.radius))
    assert np.isnan(xr_roll.at_pressure.values[0, m:]).all()


def test_a_snapshot_the_roll_never_reached_is_a_finding() -> None:
    """Without a diameter the roll ends where the records end (87.4 mm): a snapshot asked
    at 90 mm is not taken, and the verdict says so with both radii."""
    roll = _snapshot_roll([0.0855, 0.09])
    assert roll.missed == (0.09,)
    assert [s.radius for s in roll.snapshots] == [0.0855]
    (found,) = [f for f in roll.findings() if f.kind == "roll_snapshot"]
    assert "no snapshot at r = 90 mm" in found.message
    assert found.details["outer_radius_m"] == pytest.approx(roll.stress.outer_radius)


def test_a_snapshot_outside_the_chain_roll_is_refused() -> None:
    import webline
    from webline.errors import LineFileError

    line = webline.load_line("converter")
    table = {"k1": "1 kPa", "k2": 100, "diameter": "0.5 m"}
    with pytest.raises(LineFileError, match=r"roll_stress\.at_radii\[0\]: .* inside the core"):
        line.replace({"rollers.rewind.roll_stress": {**table, "at_radii": ["1 mm"]}})
    with pytest.raises(LineFileError, match=r"at_radii\[0\]: 0\.3 m is beyond the finished"):
        line.replace({"rollers.rewind.roll_stress": {**table, "at_radii": ["0.3 m"]}})


def test_a_model_missing_its_keys_is_one_clear_line() -> None:
    import webline
    from webline.errors import LineFileError

    line = webline.load_line("converter")
    with pytest.raises(LineFileError, match=r"roll_stress\.k2: the pfeiffer model needs it"):
        line.replace({"rollers.rewind.roll_stress": {"k1": "1 kPa"}})
    with pytest.raises(LineFileError, match=r"roll_stress\.core\.inner_radius: must be below"):
        line.replace(
            {
                "rollers.rewind.roll_stress": {
                    "model": "constant",
                    "radial_modulus": "50 MPa",
                    "core": {"modulus": "3 GPa", "inner_radius": "0.1 m"},
                }
            }
        )


def test_a_lay_on_nip_adds_mu_n_over_h_to_every_layer() -> None:
    """nip_load [N over the width] and nip_friction μ: each layer's wound-on stress rises by
    μ (N/w)/h, in the run's layers and the steady ones alike (Good, Wu & Fikes 1994)."""
    plain, _, _ = _roll(0.0)
    spec = RollStressSpec(k1=1.5e3, k2=120.0, diameter=0.2, nip_load=2000.0, nip_friction=0.3)
    t, r, ten = _records(0.0)
    nip = wound_roll(
        "rewind",
        spec,
        time=t,
        radius=r,
        tension=ten,
        core_radius=RC,
        thickness=H,
        width=W,
        modulus=4e9,
        steady_tension=lambda x: np.full(np.shape(x), 120.0),
    )
    np.testing.assert_allclose(nip.layers.stress - plain.layers.stress, 0.3 * 2000.0 / W / H)
    assert nip.stress.core_pressure > plain.stress.core_pressure


def test_a_snapshot_at_the_finished_surface_is_the_finished_roll() -> None:
    """A diameter of 200.01 mm is 800.2 layers of 25 um over the 80 mm core: the roll has
    800, and a snapshot at its stated surface (100.005 mm) is the finished roll, not missed."""
    roll = _snapshot_roll([0.100005], diameter=0.20001)
    assert roll.missed == () and len(roll.stress.radius) == 800
    (snap,) = roll.snapshots
    np.testing.assert_array_equal(snap.stress.pressure, roll.stress.pressure)
    np.testing.assert_array_equal(snap.stress.hoop, roll.stress.hoop)


def test_a_run_that_ran_away_winds_its_roll_up_to_its_last_finite_record() -> None:
    """Records non-finite from 8 s on (a diverged run): the roll takes the records before,
    the rest of it the steady tension, and no NaN reaches the stresses."""
    from webline.sim.results.wound_roll import recorded_roll

    t, r, ten = _records(0.0)
    late = t >= 8.0
    r, ten = np.where(late, np.nan, r), np.where(late, np.inf, ten)
    roll = recorded_roll(
        "rewind",
        RollStressSpec(k1=1.5e3, k2=120.0, diameter=0.2),
        time=t,
        radius=r,
        tension=ten,
        core_radius=RC,
        thickness=H,
        width=W,
        modulus=4e9,
        set_tension=120.0,
        taper=None,
    )
    assert np.isfinite(roll.stress.pressure).all() and np.isfinite(roll.stress.hoop).all()
    assert np.nanmax(roll.layers.time) < 8.0
    np.testing.assert_allclose(roll.layers.tension, 120.0, rtol=1e-12)
