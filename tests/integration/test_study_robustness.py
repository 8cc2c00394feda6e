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
        p, n, k = float(row["p_unstable_or_failed"]), int(row["cases"]), int(
            row["unstable_or_failed"])
        assert 0 <= k <= n and p == k / n
        assert f"{row['controller']}: P(unstable or failed) = {p:.1%} ({k} of {n}; 95 % " \
            in result.summary
        # the exact interval: at k = 0 its top is 1 - 0.025^(1/n) (37 % for 8 lines), never
        # the zero a standard error would claim
        low, high = float(row["p_95_low"]), float(row["p_95_high"])
        assert low <= p <= high
        if k == 0:
            assert low == 0.0 and math.isclose(high, 1 - 0.025 ** (1 / n), rel_tol=1e-9)
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
