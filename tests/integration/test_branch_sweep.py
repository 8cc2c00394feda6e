"""Sweeps and Monte Carlo on a branched line (issue 26 item 2, docs/branching.md): each case
runs the branch kernel from its own operating point; its metrics per span (so per lane) and
its verdict per web; Monte Carlo reproducible from its seed; a resumed study equals an
uninterrupted one and never mixes two lines; bad input is one line, exit 2."""

from __future__ import annotations

from importlib.resources import files

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.errors import ArgumentError

MODULI = ["2.25 GPa", "4.5 GPa", "9 GPa"]  # the film's 4.5 GPa (EA 103.5 kN) halved, doubled


@pytest.fixture(scope="module")
def upset():
    # 3 s holds the step at 2 s and the dips after it (a 10 s run gives the same peaks)
    return webline.sweep("laminator", {"webs.film.web.modulus": MODULI},
                         scenario="layer-upset", duration=3)


def test_film_modulus_grid_in_the_layer_upset(upset) -> None:
    peak = upset.tension_peak_error
    assert peak.dims == ("webs.film.web.modulus", "span")
    np.testing.assert_allclose(upset["webs.film.web.modulus"].values, [2.25e9, 4.5e9, 9e9])
    # the softest film needs the most unwind torque swing for the same 30 N: its unwind
    # touches its torque limit (8 ms), a warning on the film web and so on the case
    assert list(upset.status.values) == ["warning", "ok", "ok"]
    assert upset.web_status.dims == ("webs.film.web.modulus", "web")
    assert list(upset.web_status.values[0]) == ["warning", "ok", "ok"]
    film, foil, lam = (peak.sel(span=s).values for s in ("film_zone", "foil_zone",
                                                          "laminate_zone"))
    # the film zone's peak error is its reference's own 30 N step (a tension cannot jump):
    # 1e-2 N allows the ~1e-3 N the zone sits off its reference before the step
    np.testing.assert_allclose(film, 30.0, atol=1e-2)
    # the laminate (EA_L = EA_film + EA_foil) grows stiffer with the film: L dT/dt = EA_L Δv,
    # the same nip speed error gives a larger tension response. Measured 5.91, 6.09, 6.29 N
    # (6.30, 6.45, 6.64 N with the draw held, E-B4): steps of 0.18 N and more, far above
    # the solver's 1e-9 N
    assert np.all(np.diff(lam) > 0.1)
    # the foil feels the upset only through the nip's speed, which stiffer film and laminate
    # spans on either side of the nip hold tighter: its dip shrinks, 9.12, 9.08, 8.22 N
    # (with the film drives' draw following the step, docs/errata.md E-B4; 8.69, 8.62,
    # 7.80 N when it was held): steps of 0.039 N and more, far above the solver's 1e-9 N
    assert np.all(np.diff(foil) < -0.02)
    # the baseline case is the line's own run (docs/branching.md: the foil dips 9.1 N)
    assert foil[1] == pytest.approx(9.08, abs=0.05)


def test_steady_nip_leaves_the_foil_zone_alone() -> None:
    # no upset: the nip turns at line speed and every case starts at its own equilibrium, so
    # the foil zone stays at its 60 N whatever the film's modulus. Its peak error (5.5e-3 N,
    # the rewind's radius ramp drifting the laminate zone) moves by < 5e-4 N over a 4x change
    ds = webline.sweep("laminator", {"webs.film.web.modulus": MODULI}, duration=1)
    foil = ds.tension_peak_error.sel(span="foil_zone").values
    assert np.all(foil < 1e-2)
    assert np.ptp(foil) < 5e-4


DISTS = {"webs.film.web.ea": "normal(103.5 kN, 5 %)",
         "webs.foil.spans.foil_zone.length": "uniform(1.8 m, 2.2 m)"}


@pytest.fixture(scope="module")
def monte_carlo():
    return webline.monte_carlo("laminator", DISTS, 4, seed=7, duration=0.5)


def test_monte_carlo_is_bit_identical_from_its_seed(monte_carlo) -> None:
    again = webline.monte_carlo("laminator", DISTS, 4, seed=7, duration=0.5)
    xr.testing.assert_identical(monte_carlo, again)  # values, coords and attrs, bit for bit
    other = webline.monte_carlo("laminator", DISTS, 4, seed=8, duration=0.5)
    assert not np.array_equal(other["webs.film.web.ea"].values,
                              monte_carlo["webs.film.web.ea"].values)
    # the samples are what the distributions say, in SI: 2.2 m in metres, not millimetres
    assert np.all((monte_carlo["webs.foil.spans.foil_zone.length"].values >= 1.8)
                  & (monte_carlo["webs.foil.spans.foil_zone.length"].values <= 2.2))
    assert monte_carlo.attrs["mode"] == "monte_carlo" and monte_carlo.attrs["seed"] == 7


def test_interrupted_study_resumes_to_the_same_dataset(tmp_path, monte_carlo,
                                                       monkeypatch) -> None:
    from webline.sim.sweeps import chunks

    monkeypatch.setattr(chunks, "CHUNK", 2)  # 2 chunks of 2 cases

    def killed(done: int, total: int) -> None:
        raise KeyboardInterrupt  # dies right after its first chunk is saved

    line = tmp_path / "laminator.toml"
    text = (files("webline.data") / "lines" / "laminator.toml").read_text()
    line.write_text(text)
    store = tmp_path / "store"
    with pytest.raises(KeyboardInterrupt):
        webline.monte_carlo(line, DISTS, 4, seed=7, duration=0.5, store=store,
                            progress=killed)
    assert [p.name for p in store.glob("chunk-*.nc")] == ["chunk-000000.nc"]
    # the line file edited since (the nip's inertia): its hash differs, the resume is refused
    line.write_text(text.replace('inertia = "0.5 kg*m**2"\nfriction = "0.05 N*m*s"\ndrive = '
                                 '{ ratio = 1.0, torque_limit = "100 N*m"',
                                 'inertia = "0.6 kg*m**2"\nfriction = "0.05 N*m*s"\ndrive = '
                                 '{ ratio = 1.0, torque_limit = "100 N*m"', 1))
    assert line.read_text() != text
    with pytest.raises(ArgumentError, match="rollers"):
        webline.monte_carlo(line, DISTS, 4, seed=7, duration=0.5, store=store, resume=True)
    line.write_text(text)
    ds = webline.monte_carlo(line, DISTS, 4, seed=7, duration=0.5, store=store, resume=True)
    for name in (*DISTS, "status", "web_status", "tension_peak_error", "tension_min",
                 "tension_max", "tension_final_error", "substeps"):
        np.testing.assert_array_equal(ds[name].values, monte_carlo[name].values, err_msg=name)


def test_a_case_that_fails_is_one_row_and_the_rest_go_on(tmp_path) -> None:
    # an unwind 0.01 mm above its core runs out of web in ms: that case fails, alone
    result = CliRunner().invoke(app, [
        "sweep", "laminator", "--set", "rollers.unwind_film.radius=76.21 mm,0.3 m", "-d",
        "0.5", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    ds = xr.open_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    assert list(ds.status.values) == ["failed", "ok"]
    assert "unwind roll ran out" in str(ds.headline.values[0])
    assert list(ds.web_status.values[1]) == ["ok", "ok", "ok"]
    assert np.isfinite(ds.tension_peak_error.sel(span="foil_zone").values[1])
    assert 'id="sweep-status"' in (tmp_path / "report.html").read_text()
    assert "tension_final_error [foil_zone]" in result.output  # the summary's metric table


def test_a_path_that_does_not_exist_is_one_line_exit_2(tmp_path) -> None:
    result = CliRunner().invoke(app, [
        "sweep", "laminator", "--set", "webs.flim.web.ea=50 kN,60 kN", "--out",
        str(tmp_path)])
    assert result.exit_code == 2
    assert result.output.strip().count("\n") == 0
    assert "webs.flim" in result.output and "'film'" in result.output
    assert not (tmp_path / "sweep.nc").exists()


def test_work_is_bounded_before_any_case_runs(tmp_path) -> None:
    # 1000 cases of 1e6 s at 1 kHz and 3 sub-steps: 3e12 RK4 steps, beyond the 1e12 limit;
    # refused in the time of its probes (seconds), not the 83 core-hours it asks for
    result = CliRunner().invoke(app, [
        "sweep", "laminator", "--set", "webs.film.web.ea=normal(103.5 kN, 5 %)", "--samples",
        "1000", "-d", "1e6", "--out", str(tmp_path)])
    assert result.exit_code == 2
    assert "3e+12 steps" in result.output and "study limit" in result.output
    assert not (tmp_path / "sweep.nc").exists()


def test_per_width_units_are_refused_for_a_branched_line(tmp_path) -> None:
    result = CliRunner().invoke(app, [
        "sweep", "laminator", "--set", "webs.film.web.ea=50 kN", "--units", "si-per-width",
        "--out", str(tmp_path)])
    assert result.exit_code == 2 and result.output.strip().count("\n") == 0
    assert "own widths" in result.output


@pytest.mark.dask
def test_dask_local_cluster_equals_the_local_study(monte_carlo) -> None:
    # the cases run in two worker processes, chunk by chunk: the same numbers, bit for bit
    pytest.importorskip("distributed")
    ds = webline.monte_carlo("laminator", DISTS, 4, seed=7, duration=0.5, scheduler="local",
                             workers=2)
    for name in (*DISTS, "status", "web_status", "tension_peak_error", "tension_max"):
        np.testing.assert_array_equal(ds[name].values, monte_carlo[name].values, err_msg=name)


def test_lane_thickness_grid_splits_the_shaft_lanes_in_proportion() -> None:
    # lanes on one shaft (docs/branching.md, thickness profile): their rolls grow apart at a
    # rate ∝ h_1 - h_2, so to first order d(T_1 - T_2)/dt ≈ EA v (h_1 - h_2) / (2π r²) and the
    # split after the same time doubles with the thickness difference; the sum is the drive's
    ds = webline.sweep("slitter", {"webs.lane_1.thickness": ["50 um", "50.5 um", "51 um"]},
                       scenario="thickness-profile", duration=3)
    final = ds.tension_final_error
    split = (final.sel(span="lane_1_span") - final.sel(span="lane_2_span")).values
    # equal lanes: no split (1e-3 N: the solver's tolerance at the operating point, 1e-4 N)
    assert abs(split[0]) < 1e-3
    # 2 % allows the second-order terms: (h_1 - h_2)/h (2 %) on the radii ratio, measured 0.4 %
    assert split[2] / split[1] == pytest.approx(2.0, rel=0.02)
    assert split[1] > 5.0  # ~5.3 N/s for 1 %, over 3 s less the span's 0.4 s lag
    # lane_3 winds on its own shaft: untouched by lane_1's thickness
    assert np.all(np.abs(final.sel(span="lane_3_span").values) < 1e-3)
    assert final.span_web.sel(span="lane_1_span").item() == "lane_1"


def test_a_case_that_cannot_run_is_one_failed_row() -> None:
    # a 1 mm span of a 100 MN web, a spring so stiff that its fastest mode needs 709 RK4 steps per
    # controller period, beyond simulate_branches' 200; that case is refused, alone
    ds = webline.sweep("laminator", {"webs.foil.spans.0.length": ["1 mm", "1.5 m"],
                                     "webs.foil.web.ea": ["100 MN", "630 kN"]},
                       mode="zip", duration=0.2)
    assert list(ds.status.values) == ["failed", "ok"]
    assert "RK4 steps per controller period" in str(ds.headline.values[0])
    assert list(ds.web_status.values[0]) == ["failed"] * 3
    assert np.all(np.isnan(ds.tension_max.values[0])) and np.all(
        np.isfinite(ds.tension_max.values[1]))
    np.testing.assert_allclose(ds["webs.foil.spans.0.length"].values, [1e-3, 1.5])
