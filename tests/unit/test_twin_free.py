"""Free parameters of a fit: bounds with units read into SI, wildcards expanded to one
parameter per element, bad bounds refused naming the path."""

from __future__ import annotations

import pytest

import webline
from webline.errors import ArgumentError
from webline.twin.fitting.free import parse_free


@pytest.fixture(scope="module")
def converter():
    return webline.load_line("converter")


def test_bounds_with_units_are_si_and_the_start_is_the_lines_value(converter):
    (p,) = parse_free(converter, {"web.modulus": "2 .. 6 GPa"})
    assert (p.low, p.high, p.unit, p.start) == (2e9, 6e9, "Pa", 4e9)
    (q,) = parse_free(converter, {"rollers.unwind.inertia": "10 .. 50 lb*ft**2"})
    # 1 lb ft² = 0.45359237 kg x 0.3048² m² = 0.0421401 kg m² (exact definitions)
    assert q.low == pytest.approx(10 * 0.45359237 * 0.3048**2, rel=1e-12)
    assert q.unit == "kg*m**2"


def test_a_wildcard_gives_one_parameter_per_element(converter):
    params = parse_free(converter, {"rollers.*.friction": "0.001 .. 0.2 N*m*s"})
    names = [converter.node_name(i) for i in range(converter.n_nodes)]
    assert [p.path for p in params] == [f"rollers.{n}.friction" for n in names]
    assert {p.start for p in params} == {0.05, 1e-3}  # the file's driven and guide rollers


@pytest.mark.parametrize(("free", "fragment"), [
    ({"rollers.nope.inertia": "1 .. 2 kg*m**2"}, "rollers.nope.inertia"),
    ({"web.modulus": "6 .. 2 GPa"}, "LOW < HIGH"),
    ({"web.modulus": "2 .. 6 m/s"}, "web.modulus"),
    ({"web.modulus": "4 GPa"}, "LOW .. HIGH"),
    ({"rollers.*.nothing": "1 .. 2"}, "matches no value"),
    ({"sensors.lc.gain": "0.9 .. 1.1"}, "declares no such sensor"),
])
def test_bad_free_parameters_name_the_path(converter, free, fragment):
    with pytest.raises(ArgumentError) as exc:
        parse_free(converter, free)
    assert fragment in str(exc.value)


def test_a_declared_sensors_gain_is_free_like_any_value(converter):
    """``sensors.NAME.gain`` of a declared loadcell (docs/line-file.md, sensors): dimensionless
    bounds, the file's gain as the start."""
    span = converter.span_name(converter.zones[0].loadcell)
    line = converter.replace({"sensors": [{"name": "lc", "type": "loadcell", "span": span,
                                           "gain": 1.01}]})
    (p,) = parse_free(line, {"sensors.lc.gain": "0.9 .. 1.1"})
    assert (p.low, p.high, p.unit, p.start) == (0.9, 1.1, "", 1.01)
