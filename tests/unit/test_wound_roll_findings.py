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


def test_a_branched_line_refuses_roll_stress_in_one_line() -> None:
    """Its runs do not compute the roll yet: the table is refused, not ignored."""
    import webline
    from webline.errors import LineFileError

    line = webline.load_line("laminator")
    with pytest.raises(LineFileError, match=r"rollers\[6\]\.roll_stress: .*single-path"):
        line.replace({"rollers.rewind.roll_stress": {"k1": "1 kPa", "k2": 100}})


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
