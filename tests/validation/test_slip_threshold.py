"""Study ``slip-threshold`` on the HSWL (issue 6), shortened: wrap and friction needs from the
capstan relation with the centrifugal term (5.12-5.13), the (5.45) check along a no-slip run,
and an idler that starts slipping. Contact values: ``webline/data/slip/hswl_contact.toml``
(assumed)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import webline
from webline.studies import slip_threshold as st


def test_slip_threshold_study_runs_end_to_end(tmp_path):
    result = st.run(tmp_path, quick=True)
    assert result.name == "slip-threshold"
    assert len(result.figures) == 3 and all(p.stat().st_size > 10_000 for p in result.figures)
    tables = json.loads((tmp_path / "slip_threshold.json").read_text())["tables"]
    line = webline.load_line("hswl")
    c = st.load_contact()

    # bearing failure on the closed-loop line: at equilibrium the idler's torque balance makes
    # the tension step across it drag/R, slipping or not; only the small wrap slips; slip
    # dissipates power; web length is conserved
    idler = line.spec.rollers[3]
    for row in tables["bearing_failure_line"]:
        assert row["step_end_N"] == pytest.approx(c.drag / idler.radius, rel=0.02)
        assert row["min_slip_power_W"] >= 0.0
        assert row["max_web_balance_m"] < 1e-7
    slipping = {row["case"]: row["slip_fraction"] for row in tables["bearing_failure_line"]}
    assert slipping["line, adhered"] == 0.0
    assert slipping["line, small wrap"] > 0.1

    # steady: the idler needs (bearing drag + inertia torque)/R over the tension, i.e.
    # mu*alpha = ln((T + ΔT - t_c)/(T - t_c)); every row is consistent with its tensions
    for row in tables["steady"]:
        need = math.log((row["t_out_N"] - row["t_c_N"]) / (row["t_in_N"] - row["t_c_N"]))
        assert row["mu_wrap_rad"] == pytest.approx(abs(need), rel=1e-9, abs=1e-15)
    worst = {row["roller"]: row for row in result.table}
    assert worst["master"]["mu_wrap_rad"] == pytest.approx(0.0, abs=1e-12)  # equal zones
    assert 0.0 < worst["idler"]["mu_wrap_rad"] < 0.1
    # a draw of 2 between zones needs ln 2 on the master roller (t_c << T)
    draw = {(r["zone2_over_zone1"], r["roller"]): r for r in tables["draw"]}
    assert draw[(2.0, "master")]["mu_wrap_rad"] == pytest.approx(math.log(2.0), rel=1e-3)
    assert draw[(3.0, "master")]["margin"] < 0 < draw[(2.0, "master")]["margin"]

    # transient: the speed change needs little and keeps (5.45) far from its limit
    for row in tables["transient"]:
        assert 0.0 < row["max_mu_wrap"] < 0.05
        assert row["max_5_45_ratio"] < 0.1

    # bearing failure: the 10 deg idler slips, the others do not; the slip power is never
    # negative and web is conserved; the slipping idler's tension difference has settled to
    # (drag + bearing viscous)/R, its torque balance, and it turns slower than the web
    failure = {row["case"]: row for row in tables["bearing_failure"]}
    assert failure["adhered"]["slip_fraction"] == 0.0
    assert failure["wrap 90°"]["slip_fraction"] == 0.0
    slipping = failure["wrap 10°"]
    assert slipping["slip_fraction"] > 0.3
    for row in failure.values():
        assert row["min_slip_power_W"] >= 0.0
        assert row["max_web_balance_m"] < 1e-10
    op = webline.operating_point(line)
    idler = line.spec.rollers[3]
    drag = (c.drag + idler.friction * op.omega[3]) / idler.radius
    # 1 %: the idler's speed (hence its viscous drag) still creeps with the span tensions
    assert slipping["difference_end_N"] == pytest.approx(drag, rel=0.01)
    assert slipping["idler_speed_deficit_fpm"] > 0.0
    assert slipping["difference_peak_N"] < failure["adhered"]["difference_peak_N"]


def test_needs_along_a_run_match_the_recorded_tensions():
    """The a-posteriori check on a short no-slip run equals the capstan need computed by hand
    from the recorded tensions and speeds."""
    from webline.analysis import slip as an

    line = webline.load_line("hswl")
    result = webline.simulate(line, 0.2)
    needs = an.needs_along(result, {"idler": math.pi / 2})["idler"]
    rho_a = an.mass_per_length(line)
    t_c = rho_a * result.speed[:, 3] ** 2
    hand = np.abs(np.log((result.tension[:, 3] - t_c) / (result.tension[:, 2] - t_c)))
    assert np.allclose(needs, hand, rtol=1e-12, atol=1e-15)
