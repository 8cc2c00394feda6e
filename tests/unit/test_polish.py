"""Polish found on the way (issue 23, item 7): a Monte Carlo spread without a unit is refused,
parse hints suggest a unit of the kind asked for, a range without its count shows the
``start:stop:n`` form."""

from __future__ import annotations

import pytest

from webline.sim.sweeps.distributions import parse_distribution
from webline.units import to_si


@pytest.mark.parametrize("text", ["normal(2000 lbf, 5)", "uniform(9 kN, 10000)"])
def test_a_spread_without_unit_beside_a_value_with_one_is_refused(text: str) -> None:
    """``normal(2000 lbf, 5)`` read 5 as 5 N, a spread of 0.06 %: the user meant 5 lbf or
    5 %. Refused, naming both ways to write it."""
    with pytest.raises(ValueError, match=r"has no unit.*'5 %'|has no unit.*%"):
        parse_distribution(text)


def test_spreads_with_units_or_percent_or_zero_still_read() -> None:
    """A unit, a percentage, a plain pair (SI both) and a zero spread stay as they were."""
    assert parse_distribution("normal(2000 lbf, 5 lbf)")[2] == pytest.approx(5 * 4.4482216152605)
    assert parse_distribution("normal(2000 lbf, 5 %)")[2] == pytest.approx(
        0.05 * 2000 * 4.4482216152605)
    assert parse_distribution("normal(9000, 500)") == ("normal", 9000.0, 500.0)
    assert parse_distribution("normal(2000 lbf, 0)")[2] == 0.0


@pytest.mark.parametrize(("kind", "example", "wrong"), [
    ("time", "'1.5 s'", "'1.5 m'"),
    ("angular_frequency", "'1.5 rad/s'", "'1.5 m'"),
    ("dimensionless", "'0.5'", "'1.5 m'"),
    ("force", "'1.5 N'", "'1.5 m'"),
])
def test_parse_hint_gives_an_example_of_the_kind_asked_for(kind, example, wrong) -> None:
    """'2,5 s' as a time suggested '1.5 m' (metres) whatever the kind; the example is of the
    kind asked for (a plain number for a ratio), and the kind is in words."""
    with pytest.raises(ValueError) as caught:
        to_si("2,5 s" if kind != "dimensionless" else "0,5", kind)
    message = str(caught.value)
    assert f"e.g. {example}" in message and wrong not in message
    assert "_" not in message.split(" as ")[1].split(":")[0]  # "an angular frequency"


def test_a_range_without_its_count_shows_the_start_stop_n_form() -> None:
    """``1800 lbf:2200 lbf`` (a sweep's range without n) is not a force: the message shows
    how a range is written, ``start:stop:n``."""
    with pytest.raises(ValueError, match=r"start:stop:n.*'1800 lbf:2200 lbf:5'"):
        to_si("1800 lbf:2200 lbf", "force")
