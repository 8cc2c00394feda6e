"""Profile-likelihood intervals (issue 36 item 5, ``fit(..., profile=True)``,
``webline fit --intervals profile``): where the confidence region is an ellipsoid they are
the honest Wald intervals, where it is not they follow the cost."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from webline.cli import app
from webline.line import load_line
from webline.twin.fitting.fit import fit
from webline.twin.traces.synthetic import synthetic_csv
from webline.twin.tuning.experiment import plan_experiment

HSWL = load_line("hswl")


def test_on_an_ellipsoidal_region_profile_is_wald(tmp_path):
    """hswl's tension step with EA 5 % and the process inertia 30 % off: the cost is
    quadratic in both over their intervals (±0.02 %, ±0.2 %), so the profile's ends, where
    the refitted cost rises by ½ t² (stderr / stderr_noise)², are the Wald ends to 1 % of
    the width (the bisection's last step, interpolated)."""
    plan = plan_experiment(HSWL, "tension-step")
    truth = {"web.ea": 1.05 * float(HSWL.spec.web.ea), "rollers.process.inertia": 0.11}
    path = synthetic_csv(tmp_path / "step.csv", plan.line, changes=truth,
                         duration=plan.duration, rate=plan.logging_rate, seed=1)
    free = {"web.ea": "5000 .. 20000 N", "rollers.process.inertia": "0.01 .. 0.5 kg*m**2"}
    wald = fit(plan.line, path, free, starts=1)
    profile = fit(plan.line, path, free, starts=1, profile=True)
    assert profile.interval_kind == ("profile", "profile")
    for i in range(2):
        width = wald.ci95[i, 1] - wald.ci95[i, 0]
        assert profile.ci95[i] == pytest.approx(wald.ci95[i], abs=0.01 * width)


def test_a_one_sided_region_gets_a_one_sided_profile(tmp_path):
    """The span between master and process from accel-ramps with 5 x the tension noise: a
    short span makes the tension follow a speed difference fast (EA/L), which the record
    sees; a long one only slows it, which the ramps barely excite. The Wald interval is
    wider than the bounds (named not identifiable); the profile bounds the length from
    below, holds the truth (the file's 10.06 m) and stays open to the upper bound."""
    plan = plan_experiment(HSWL, "accel-ramps")
    path = synthetic_csv(tmp_path / "ramps.csv", plan.line, changes={}, duration=plan.duration,
                         rate=200.0, seed=1, noise={"tension": 2.5, "speed": 0.01,
                                                    "torque": 0.1})
    free = {"spans.span2.length": "1 .. 40 m", "web.ea": "2000 .. 40000 N"}
    wald = fit(plan.line, path, free, starts=1)
    assert wald.interval_kind[0] == "bounds"
    profile = fit(plan.line, path, free, starts=1, profile=True)
    low, high = profile.ci95[0]
    assert profile.interval_kind[0] == "profile, one-sided"
    assert 2.0 < low < 10.06 and high == pytest.approx(40.0)
    assert profile.interval_kind[1] == "profile"
    assert profile.ci95[1, 0] < float(HSWL.spec.web.ea) < profile.ci95[1, 1]


def test_cli_refuses_an_unknown_interval_method(tmp_path):
    result = CliRunner().invoke(app, ["fit", "hswl", str(tmp_path / "none.csv"), "--free",
                                      "web.ea=5000..20000 N", "--intervals", "bootstrap"])
    assert result.exit_code == 2
    assert "--intervals: 'wald' or 'profile'" in result.stderr
