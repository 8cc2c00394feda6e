"""A run's wound roll (docs/wound-roll.md): a tension step during winding leaves a band at
the radius the roll had during the step, and the verdict, summary and dataset carry it."""

from __future__ import annotations

import numpy as np
import pytest

import webline

# PET film stack: Pfeiffer K1, K2 assumed (docs/wound-roll.md, "Assumed values"); a fibre core
ROLL = {
    "k1": "1.5 kPa",
    "k2": 120,
    "core": {"modulus": "3 GPa", "inner_radius": "76 mm"},
    "max_pressure": "5 MPa",
    "core_rating": "8 MPa",
    "band": 0.05,
}


@pytest.fixture(scope="module")
def stepped() -> webline.Result:
    """converter at 300 m/min from the start; the rewind zone's set tension steps from 150 N
    to 200 N at 4 s and back at 6 s."""
    line = webline.load_line("converter").replace(
        {
            "rollers.rewind.roll_stress": ROLL,
            "spans.rewind_span.tension": {
                "type": "steps",
                "initial": "150 N",
                "steps": [{"time": "4 s", "value": "200 N"}, {"time": "6 s", "value": "150 N"}],
            },
        }
    )
    return webline.simulate(line, duration=10.0)


def test_step_leaves_a_band_at_its_radius(stepped: webline.Result) -> None:
    roll = stepped.wound_roll
    assert roll is not None
    bands = [
        f
        for f in stepped.verdict.findings
        if f.kind == "roll_band" and f.details["hoop_departure"] > 0
    ]
    assert len(bands) == 1, [f.message for f in stepped.verdict.findings]
    band = bands[0]
    t0, t1 = band.details["time_s"]
    r0, r1 = band.details["radius_m"]
    # the band was wound during the step (plus the tension loop's settling, ~1 s at 4 rad/s)
    assert 3.9 <= t0 <= 4.5 and 5.8 <= t1 <= 7.5, (t0, t1)
    # and lies where the simulated roll was then: its radius at 4.5 s and 5.5 s are inside
    radius = stepped.radius[:, -1]
    for t in (4.5, 5.5):
        assert r0 <= np.interp(t, stepped.time, radius) <= r1
    assert r0 >= np.interp(3.8, stepped.time, radius)
    assert r1 <= np.interp(8.0, stepped.time, radius)
    # 200 N (and the loop's overshoot) for 150 N x taper (0.99 here): the band's hoop stress
    # departs as its wound-on stress does, within what the layers' pressures change
    inside = (roll.layers.radius >= r0) & (roll.layers.radius < r1)
    wound = (roll.layers.stress[inside] / roll.steady.wound_on[inside]).max() - 1.0
    assert wound > 200.0 / 148.5 - 1.0 - 0.02
    assert band.details["hoop_departure"] == pytest.approx(wound, abs=0.1)
    assert band.details["pressure_departure"] > 0  # and it presses the layers below harder
    assert "hard band" in band.message


def test_roll_signals_and_summary(stepped: webline.Result) -> None:
    roll = stepped.wound_roll
    ds = roll.to_xarray()
    assert set(ds.data_vars) >= {"wound_on_tension", "pressure", "hoop", "wound_time"}
    run = np.isfinite(ds.wound_time.values)
    # the run's layers took the simulated tension: its peak (the step's overshoot) at most
    tension = stepped.tension[:, -1]
    assert ds.wound_on_tension.values[run].max() <= tension.max() + 1e-9
    assert ds.wound_on_tension.values[run].max() >= 0.99 * tension[stepped.time > 1.0].max()
    # outer layer: pressure = wound-on stress x thickness / radius
    s = roll.stress
    assert s.pressure[-1] == pytest.approx(s.wound_on[-1] * s.thickness / s.radius[-1])
    summary = roll.summary()
    assert summary["layers"] == len(s.radius) and summary["layers_in_run"] == int(run.sum())
    # the finished roll is the taper's max diameter, 0.8 m: (0.4 - 0.089) / 23 µm layers
    assert summary["outer_radius_m"] == pytest.approx(0.4, abs=23e-6)


def test_results_file_keeps_the_roll_per_layer(stepped: webline.Result, tmp_path) -> None:
    """results.nc: the run's signals at its root as before, the roll in group wound_roll."""
    import xarray as xr

    path = stepped.to_netcdf(tmp_path / "results.nc")
    with xr.open_dataset(path, group="wound_roll", engine="h5netcdf") as roll:
        np.testing.assert_array_equal(roll.pressure.values, stepped.wound_roll.stress.pressure)
        np.testing.assert_array_equal(roll.radius.values, stepped.wound_roll.layers.radius)
        assert roll.wound_time.attrs["units"] == "s"
    with xr.open_dataset(path, engine="h5netcdf") as root:
        assert "tension" in root.data_vars and "layer" not in root.dims
