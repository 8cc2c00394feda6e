"""Tidy study tables (issue 37): ``StudyDataset.metrics()`` is one row per case, metric and
element, ``to_dataframe()`` one row per case (no cross product of spans, drives and nodes)."""

from __future__ import annotations

import numpy as np
import pytest

import webline


@pytest.fixture(scope="module")
def grid():
    return webline.sweep(
        "hswl",
        {"web.ea": ["8 kN", "9 kN"], "rollers.process.controller.tension_bandwidth": [4, 8]},
        duration=0.2,
    )


@pytest.fixture(scope="module")
def monte_carlo():
    return webline.monte_carlo("hswl", {"web.ea": "normal(9 kN, 5 %)"}, 3, seed=1, duration=0.2)


def test_metrics_is_one_row_per_case_metric_and_element(grid) -> None:
    table = grid.metrics()
    n_cases = 4
    # hswl: 4 spans, 4 drives, 5 nodes; per span six metrics, per drive one, per node one,
    # per case two numbers (failure_time, substeps)
    assert len(table) == n_cases * (6 * 4 + 1 * 4 + 1 * 5 + 2)
    assert not table.duplicated(
        ["web.ea", "rollers.process.controller.tension_bandwidth", "metric", "element"]
    ).any()
    row = table[
        (table.metric == "tension_rms_error")
        & (table.element == "span2")
        & (table["web.ea"] == grid["web.ea"].values[1])
        & (table["rollers.process.controller.tension_bandwidth"] == 8.0)
    ]
    assert len(row) == 1
    assert (
        row.value.item()
        == grid.tension_rms_error.sel(
            {
                "span": "span2",
                "web.ea": grid["web.ea"].values[1],
                "rollers.process.controller.tension_bandwidth": 8.0,
            }
        ).item()
    )
    assert set(table.loc[table.metric == "substeps", "element"]) == {""}


def test_to_dataframe_is_one_row_per_case_without_the_cross_product(grid, monte_carlo) -> None:
    df = grid.to_dataframe()
    assert len(df) == 4  # xarray's own: 4 cases x 4 spans x 4 drives x 5 nodes = 320 rows
    assert len(webline.sim.sweeps.study_view.xr.Dataset.to_dataframe(grid)) == 320
    assert df.index.names == ["web.ea", "rollers.process.controller.tension_bandwidth"]
    # the case number, six metrics per span, one per drive and node, four per case
    assert df.shape[1] == 1 + 6 * 4 + 4 + 5 + 4
    assert {f"tension_rms_error[{s}]" for s in grid.span.values} <= set(df.columns)
    assert {f"slip_time[{n}]" for n in grid.node.values} <= set(df.columns)
    np.testing.assert_array_equal(
        df["tension_max[span1]"].to_numpy(), grid.tension_max.sel(span="span1").values.reshape(-1)
    )
    assert set(df["status"]) <= {"ok", "warning"}
    mc = monte_carlo.to_dataframe()
    assert len(mc) == 3 and mc.index.name == "case"
    np.testing.assert_array_equal(mc["web.ea"].to_numpy(), monte_carlo["web.ea"].values)
    assert len(monte_carlo.metrics()) == 3 * (6 * 4 + 4 + 5 + 2)


def test_a_slice_without_status_keeps_xarrays_table(grid) -> None:
    part = grid[["tension_max"]]
    assert len(part.to_dataframe()) == 4 * 4
    with pytest.raises(ValueError, match="status"):
        part.metrics()
