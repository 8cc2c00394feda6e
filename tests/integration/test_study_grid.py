"""A grid sweep comes back on its grid (issue 23 items 2 and 3): one dimension per swept path
with its values as coordinates, each cell the same numbers as the flat case it came from; a
Monte Carlo keeps ``case`` with the drawn values as coordinates; a study prints in a few
lines."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.sim.study_grid import as_cases

LBF = 4.4482216152605  # [N]
EA = "web.ea"
BW = "rollers.process.controller.tension_bandwidth"


@pytest.fixture(scope="module")
def grid():
    return webline.sweep("hswl", {EA: ["1800 lbf", "2000 lbf", "2200 lbf"],
                                  BW: [3.0, 4.0, 6.0, 8.0]}, duration=0.3, workers=1)


def test_a_3_by_4_grid_has_its_two_parameters_as_dimensions(grid) -> None:
    assert grid.tension_rms_error.dims == (EA, BW, "span")
    assert grid.status.dims == (EA, BW)
    assert (grid.sizes[EA], grid.sizes[BW]) == (3, 4)
    # the coordinates are each path's values once, in SI (lbf -> N, exactly the factor)
    np.testing.assert_allclose(grid[EA].values, np.array([1800, 2000, 2200]) * LBF, rtol=1e-12)
    np.testing.assert_array_equal(grid[BW].values, [3.0, 4.0, 6.0, 8.0])
    assert grid[EA].attrs["units"] == "N"
    # the case numbers over the grid: the last path varied fastest, as the cases ran
    np.testing.assert_array_equal(grid.case.values, np.arange(12).reshape(3, 4))


def test_each_grid_cell_holds_the_run_of_its_own_values(grid) -> None:
    # a cell picked by its values equals simulate of that case to rounding of the batch's
    # compiled reductions (far below 1e-12 relative; test_sweep's tolerance)
    cell = grid.sel({EA: 2000 * LBF, BW: 6.0}, method="nearest")
    line = webline.load_line("hswl").replace({EA: "2000 lbf", BW: 6.0})
    expected = webline.simulate(line, 0.3).metric_arrays()
    np.testing.assert_allclose(cell.tension_rms_error.values, expected["tension_rms_error"],
                               rtol=1e-12, equal_nan=True)
    assert str(cell.status.values) == expected["status"]


def test_as_cases_gives_back_the_flat_study(grid) -> None:
    flat = as_cases(grid)
    assert flat.status.dims == ("case",) and flat.sizes["case"] == 12
    np.testing.assert_array_equal(flat[BW].values, [3.0, 4.0, 6.0, 8.0] * 3)
    np.testing.assert_array_equal(flat.tension_rms_error.values,
                                  grid.tension_rms_error.values.reshape(12, -1))


def test_monte_carlo_keeps_case_with_the_drawn_values_as_coordinates() -> None:
    mc = webline.monte_carlo("hswl", {EA: "normal(2000 lbf, 5 %)"}, 5, seed=3, duration=0.2,
                             workers=1)
    assert mc.status.dims == ("case",)
    assert mc[EA].dims == ("case",) and len(set(mc[EA].values.tolist())) == 5


def test_a_study_prints_in_a_few_lines(grid) -> None:
    text = repr(grid)
    lines = text.splitlines()
    assert len(lines) <= 8, text  # "a few lines" (issue 23 item 2); xarray's own is ~30
    assert "3 × 4" in lines[0] and EA in lines[0] and BW in lines[0]
    assert "12 cases" in text and "ok" in text
