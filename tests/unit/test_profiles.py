"""Reference profiles: breakpoints of constant/ramp/steps/table and their piecewise-linear
evaluation (``webline.profiles``). Profiles are built through the schema, as a line file
would give them, so units are parsed on the way in."""

from __future__ import annotations

import numpy as np
import pytest
from pydantic import TypeAdapter

from webline.profiles import breakpoints, pwl_slope, pwl_value
from webline.spec.schema import SpeedProfile

speed_profile = TypeAdapter(SpeedProfile)


def profile(value: object) -> object:
    return speed_profile.validate_python(value)


# --- constant ------------------------------------------------------------------------------


def test_constant_is_one_point_at_time_zero() -> None:
    times, values = breakpoints(profile(2.0))
    np.testing.assert_array_equal(times, [0.0])
    np.testing.assert_array_equal(values, [2.0])


def test_constant_with_units_is_si() -> None:
    _, values = breakpoints(profile("600 ft/min"))
    assert values[0] == pytest.approx(3.048, rel=1e-15)


def test_integer_constant_is_accepted() -> None:
    times, values = breakpoints(3)
    np.testing.assert_array_equal(times, [0.0])
    np.testing.assert_array_equal(values, [3.0])


@pytest.mark.parametrize("t", [-1.0, 0.0, 5.0, 1e6])
def test_constant_value_everywhere_and_no_slope(t: float) -> None:
    times, values = breakpoints(profile(2.0))
    assert pwl_value(times, values, t) == 2.0
    assert pwl_slope(times, values, t) == 0.0


# --- ramp ------------------------------------------------------------------------------------

RAMP = {"type": "ramp", "initial": 1.0, "final": 3.0, "start": 2.0, "duration": 4.0}


def test_ramp_breakpoints_are_start_and_end() -> None:
    times, values = breakpoints(profile(RAMP))
    np.testing.assert_array_equal(times, [2.0, 6.0])
    np.testing.assert_array_equal(values, [1.0, 3.0])


def test_ramp_start_defaults_to_zero() -> None:
    times, _ = breakpoints(profile({"type": "ramp", "initial": 0, "final": 1, "duration": 2}))
    np.testing.assert_array_equal(times, [0.0, 2.0])


def test_ramp_with_units() -> None:
    times, values = breakpoints(profile({
        "type": "ramp", "initial": "200 ft/min", "final": "1000 ft/min",
        "start": "2 s", "duration": "5000 ms",
    }))
    np.testing.assert_allclose(times, [2.0, 7.0], rtol=1e-15)
    np.testing.assert_allclose(values, [1.016, 5.08], rtol=1e-15)


@pytest.mark.parametrize(
    ("t", "value", "slope"),
    [
        (0.0, 1.0, 0.0),  # before the ramp: initial value, flat
        (1.999, 1.0, 0.0),
        (2.0, 1.0, 0.5),  # at its start the ramp is rising
        (3.0, 1.5, 0.5),
        (4.0, 2.0, 0.5),
        (5.5, 2.75, 0.5),
        (6.0, 3.0, 0.0),  # at and after its end: final value, flat
        (100.0, 3.0, 0.0),
    ],
)
def test_ramp_value_and_slope(t: float, value: float, slope: float) -> None:
    times, values = breakpoints(profile(RAMP))
    assert pwl_value(times, values, t) == value
    assert pwl_slope(times, values, t) == slope


def test_falling_ramp_has_negative_slope() -> None:
    times, values = breakpoints(profile({"type": "ramp", "initial": 4, "final": 0,
                                         "duration": 2}))
    assert pwl_value(times, values, 0.5) == 3.0
    assert pwl_slope(times, values, 0.5) == -2.0


# --- steps -----------------------------------------------------------------------------------

STEPS = {"type": "steps", "initial": 1.0,
         "steps": [{"time": 2.0, "value": 5.0}, {"time": 4.0, "value": 0.5}]}


def test_steps_are_pairs_of_points_at_the_same_time() -> None:
    times, values = breakpoints(profile(STEPS))
    np.testing.assert_array_equal(times, [0.0, 2.0, 2.0, 4.0, 4.0])
    np.testing.assert_array_equal(values, [1.0, 1.0, 5.0, 5.0, 0.5])


@pytest.mark.parametrize(
    ("t", "value"),
    [
        (-1.0, 1.0),  # before time zero: the initial value
        (0.0, 1.0),
        (1.999, 1.0),
        (2.0, 5.0),  # at a step's time the later value holds
        (3.0, 5.0),
        (4.0, 0.5),
        (10.0, 0.5),
    ],
)
def test_steps_value(t: float, value: float) -> None:
    times, values = breakpoints(profile(STEPS))
    assert pwl_value(times, values, t) == value


@pytest.mark.parametrize("t", [-1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 10.0])
def test_steps_slope_is_zero_everywhere(t: float) -> None:
    times, values = breakpoints(profile(STEPS))
    assert pwl_slope(times, values, t) == 0.0


def test_step_at_time_zero_applies_from_the_start() -> None:
    times, values = breakpoints(profile({"type": "steps", "initial": 1.0,
                                         "steps": [{"time": 0.0, "value": 7.0}]}))
    assert pwl_value(times, values, 0.0) == 7.0
    assert pwl_value(times, values, 3.0) == 7.0


def test_two_steps_at_the_same_time_take_the_last() -> None:
    times, values = breakpoints(profile({
        "type": "steps", "initial": 1.0,
        "steps": [{"time": 1.0, "value": 2.0}, {"time": 1.0, "value": 3.0},
                  {"time": 2.0, "value": 4.0}],
    }))
    assert pwl_value(times, values, 0.5) == 1.0
    assert pwl_value(times, values, 1.0) == 3.0
    assert pwl_value(times, values, 1.5) == 3.0
    assert pwl_value(times, values, 2.0) == 4.0
    assert pwl_slope(times, values, 1.0) == 0.0


# --- table -----------------------------------------------------------------------------------

TABLE = {"type": "table", "time": [1.0, 2.0, 4.0], "value": [0.0, 10.0, 10.0]}


def test_table_breakpoints_are_its_points() -> None:
    times, values = breakpoints(profile(TABLE))
    np.testing.assert_array_equal(times, [1.0, 2.0, 4.0])
    np.testing.assert_array_equal(values, [0.0, 10.0, 10.0])
    assert times.dtype == np.float64


@pytest.mark.parametrize(
    ("t", "value", "slope"),
    [
        (0.0, 0.0, 0.0),  # before the first point: its value, flat
        (1.0, 0.0, 10.0),
        (1.5, 5.0, 10.0),
        (1.75, 7.5, 10.0),
        (2.0, 10.0, 0.0),
        (3.0, 10.0, 0.0),
        (4.0, 10.0, 0.0),  # after the last point: its value, flat
        (9.0, 10.0, 0.0),
    ],
)
def test_table_value_and_slope(t: float, value: float, slope: float) -> None:
    times, values = breakpoints(profile(TABLE))
    assert pwl_value(times, values, t) == value
    assert pwl_slope(times, values, t) == slope


def test_single_point_table_is_constant() -> None:
    times, values = breakpoints(profile({"type": "table", "time": [3.0], "value": [2.0]}))
    assert pwl_value(times, values, 0.0) == 2.0
    assert pwl_value(times, values, 5.0) == 2.0
    assert pwl_slope(times, values, 3.0) == 0.0


def test_table_with_a_vertical_jump_takes_the_later_value() -> None:
    times, values = breakpoints(profile({"type": "table", "time": [0, 1, 1, 2],
                                         "value": [0, 0, 4, 4]}))
    assert pwl_value(times, values, 1.0) == 4.0
    assert pwl_slope(times, values, 1.0) == 0.0


def test_not_a_profile_raises_type_error() -> None:
    with pytest.raises(TypeError, match="not a profile"):
        breakpoints("500 ft/min")
