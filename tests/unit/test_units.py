"""Unit conversion at the boundary: ``webline.units.to_si`` and ``display_factor``.

Expected SI values come from the exact definitions of the international foot, pound and
pound-force (NIST SP 811, App. B): 1 ft = 0.3048 m, 1 in = 0.0254 m, 1 lb = 0.45359237 kg,
1 lbf = 4.4482216152605 N (= 0.45359237 kg x 9.80665 m/s^2). pint applies the same factors
but may multiply them in another order than the expression written here, so the results may
differ in the last binary digit; ``assert_ulps`` allows 4 units in the last place (~1e-15
relative) and nothing more.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from webline.units import DIMENSIONS, IMPERIAL_UNITS, SI_UNITS, display_factor, to_si

FT = 0.3048
INCH = 0.0254
LB = 0.45359237
LBF = 4.4482216152605


def assert_ulps(actual: float, expected: float, n: int = 4) -> None:
    """``actual`` equals ``expected`` up to ``n`` units in the last place (float rounding)."""
    assert abs(actual - expected) <= n * math.ulp(expected), (actual, expected)


# --- exact conversions --------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "kind", "expected"),
    [
        ("500 ft/min", "speed", 2.54),
        ("500 fpm", "speed", 2.54),
        ("1000 ft/min", "speed", 5.08),
        ("14.35 lbf", "force", 14.35 * LBF),
        ("2000 lbf", "force", 2000 * LBF),
        ("8 lb*ft**2", "inertia", 8 * LB * FT**2),
        ("0.5 lbf*ft*s", "rot_damping", 0.5 * LBF * FT),
        ("1 lbf*ft", "torque", LBF * FT),
        ("20 ft", "length", 20 * FT),
        ("3 in", "length", 3 * INCH),
        ("12.7 um", "length", 12.7e-6),
        ("0.05 mm", "length", 5e-5),
        ("2 ms", "time", 0.002),
        ("1 min", "time", 60.0),
        ("1 kHz", "frequency", 1000.0),
        ("1 Hz", "frequency", 1.0),
        # a frequency [Hz] counts cycles: 40 rad/s is 40/(2π) Hz (pint alone would say 40)
        ("40 rad/s", "frequency", 40.0 / (2 * math.pi)),
        ("60 rpm", "frequency", 1.0),
        # an angular frequency [rad/s] counts radians: 6 Hz is 2π·6 rad/s (docs/line-file.md)
        ("6 Hz", "angular_frequency", 12 * math.pi),
        ("40 rad/s", "angular_frequency", 40.0),
        ("60 rpm", "angular_frequency", 2 * math.pi),
        ("5 %", "dimensionless", 0.05),
        ("1390 kg/m**3", "density", 1390.0),
        ("4.6 GPa", "pressure", 4.6e9),
        ("1 psi", "pressure", LBF / INCH**2),
        ("180 deg", "angle", math.pi),
        ("0.5", "dimensionless", 0.5),
    ],
)
def test_string_with_units_converts_to_si(text: str, kind: str, expected: float) -> None:
    assert_ulps(to_si(text, kind), expected)


def test_hswl_line_speed_is_2_54_m_per_s() -> None:
    # 500 ft/min = 500 * 0.3048 / 60 m/s = 2.54 m/s exactly in decimal; pint's float result
    # is the nearest double or its neighbour (2.5399999999999996).
    assert_ulps(to_si("500 ft/min", "speed"), 2.54, n=1)


@pytest.mark.parametrize("value", [0, 3, 2.5, -7.25, 1e-12, 1e12])
def test_plain_numbers_are_si(value: float) -> None:
    result = to_si(value, "length")
    assert result == float(value)
    assert type(result) is float


def test_whitespace_around_a_quantity_is_ignored() -> None:
    assert to_si("  3 m  ", "length") == 3.0


def test_plain_number_string_is_si_for_frequency() -> None:
    # A dimensionless string for a frequency is a plain SI number (Hz); this used to raise
    # pint's DimensionalityError instead of converting.
    assert to_si("1000", "frequency") == 1000.0
    assert to_si("2.5", "frequency") == 2.5


@pytest.mark.parametrize("kind", sorted(k for k, u in SI_UNITS.items() if u))
def test_one_si_unit_is_one(kind: str) -> None:
    assert_ulps(to_si(f"1 {SI_UNITS[kind]}", kind), 1.0)


def test_every_kind_has_si_and_imperial_units() -> None:
    assert set(DIMENSIONS) == set(SI_UNITS) == set(IMPERIAL_UNITS)


# --- bad input -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "kind"),
    [
        ("3 s", "length"),
        ("500 ft", "speed"),
        ("14.35 lb", "force"),  # lb is a mass; a force needs lbf
        ("8 lbf*ft", "inertia"),
        ("1 m", "frequency"),
        ("2 m", "dimensionless"),
        ("5 N", "time"),
    ],
)
def test_wrong_dimension_names_the_expected_kind(text: str, kind: str) -> None:
    article = "an" if kind[0] in "aeiou" else "a"
    with pytest.raises(ValueError, match=rf"expected {article} {kind}\b") as info:
        to_si(text, kind)
    assert repr(text) in str(info.value)


@pytest.mark.parametrize("text", ["abc", "3 furlongz", "1/0 m", "(", ""])
def test_unreadable_string_raises_value_error(text: str) -> None:
    with pytest.raises(ValueError, match="cannot read"):
        to_si(text, "length")


@pytest.mark.parametrize(
    "value", [math.nan, math.inf, -math.inf, "nan m", "inf m", "-inf m", "1e400 m", 10**400]
)
def test_non_finite_is_rejected(value: object) -> None:
    # 10**400 is an int beyond float range: it used to escape as OverflowError.
    with pytest.raises(ValueError, match="must be finite"):
        to_si(value, "length")


@pytest.mark.parametrize("value", [True, False])
def test_bool_is_not_a_number(value: bool) -> None:
    with pytest.raises(ValueError, match="expected a force"):
        to_si(value, "force")


@pytest.mark.parametrize("value", [None, [1.0], {"value": 1.0}, (1.0,), b"1 m"])
def test_other_types_are_rejected(value: object) -> None:
    with pytest.raises(ValueError, match="expected a length"):
        to_si(value, "length")


# --- display ---------------------------------------------------------------------------------


def test_display_factor_imperial_force_is_inverse_of_lbf() -> None:
    factor, unit = display_factor("force", "imperial")
    assert unit == "lbf"
    assert_ulps(factor, 1.0 / LBF)
    assert_ulps(factor * to_si("14.35 lbf", "force"), 14.35)


def test_display_factor_imperial_speed_is_inverse_of_ft_per_min() -> None:
    factor, unit = display_factor("speed", "imperial")
    assert unit == "ft/min"
    assert_ulps(factor, 60.0 / FT)
    assert_ulps(factor * to_si("500 ft/min", "speed"), 500.0)


@pytest.mark.parametrize("kind", sorted(k for k, u in IMPERIAL_UNITS.items() if u))
def test_display_factor_inverts_to_si_for_every_kind(kind: str) -> None:
    factor, unit = display_factor(kind, "imperial")
    assert unit == IMPERIAL_UNITS[kind]
    assert_ulps(factor * to_si(f"1 {unit}", kind), 1.0)


@pytest.mark.parametrize("kind", sorted(SI_UNITS))
def test_display_factor_si_is_identity(kind: str) -> None:
    assert display_factor(kind, "si") == (1.0, SI_UNITS[kind])


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_subnormal=False))
def test_round_trip_through_imperial_display(value: float) -> None:
    # SI value -> display in ft/min -> back through to_si: the same speed within rounding.
    factor, unit = display_factor("speed", "imperial")
    back = to_si(f"{value * factor!r} {unit}", "speed")
    assert back == pytest.approx(value, rel=1e-14, abs=1e-300)
