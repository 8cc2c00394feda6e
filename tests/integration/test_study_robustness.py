"""``webline study robustness --quick`` (issue 14): one row per controller family, the
probability of instability a share of the drawn cases, and the summary computed from it."""

from __future__ import annotations

import math

import webline
from webline.control.select import FAMILIES
from webline.studies import STUDIES
from webline.studies.robustness import uncertainty


def test_robustness_rows_and_summary(tmp_path) -> None:
    result = STUDIES["robustness"](tmp_path, quick=True)
    assert [row["controller"] for row in result.table] == list(FAMILIES)
    for row in result.table:
        p, n = float(row["p_unstable_or_failed"]), int(row["cases"])
        assert 0.0 <= p <= 1.0 and math.isclose(p * n, round(p * n), abs_tol=1e-9)
        assert f"{row['controller']}: P(unstable or failed) = {p:.1%}" in result.summary
        # the drawn HSWL lines stay stable under +-10 % EA: a regulated run, errors of N
        assert 0.0 < float(row["rms_error_median_N"]) < 5.0
    assert (tmp_path / "rms_error_histogram.png").stat().st_size > 1000


def test_uncertainty_covers_every_roller_and_the_noise() -> None:
    line = webline.load_line("hswl").replace(disturbances=[
        {"type": "measurement_noise", "tension": 0.0, "seed": 1}])
    dists = uncertainty(line)
    assert dists["web.ea"].endswith("10 %)")
    assert sum(k.endswith(".friction") for k in dists) == 5
    assert sum(k.endswith(".inertia") for k in dists) == 5
    assert "disturbances[0].tension" in dists
