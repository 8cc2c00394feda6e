"""Property tests for line files (hypothesis).

1. Random damage to the valid HSWL file (deleted keys, wrong values, unknown keys, bad
   ``type`` names, cut or grown lists, reordered lists) gives either a valid line or one
   ``LineFileError`` that names the file, a key path rooted at a real key, and a problem --
   never any other exception.
2. Valid numeric changes (lengths, inertias, ... scaled by positive factors) round-trip
   exactly through ``dump_spec`` and back.
"""

from __future__ import annotations

import copy
import re
import tomllib
from importlib import resources
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from webline.errors import LineFileError
from webline.line import Line
from webline.spec.load import dump_spec, spec_from_dict
from webline.spec.schema import LineSpec

HSWL: dict[str, Any] = tomllib.loads(
    resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8"))

Path = tuple[str | int, ...]

#: Values that are wrong for most keys (or, by chance, right for a few).
BAD_VALUES: list[object] = [
    -1, -3.5, 0, 0.0, -1e-300, 1e308, 1e300, 10**30, 10**400,
    "abc", "", " ", "3 s", "-2 m", "1 kg", "0 m", "5 lbf", "500 ft", "1000", "nan m", "nan",
    "inf m", "-inf N", "1e400 m", "1/0 m", "m", "(",
    [], [1, 2], ["a"], [{}], {}, {"a": 1}, {"type": "ramp"},
    True, False,
]

#: ``type`` names valid somewhere in the schema (so often valid in the wrong place).
TYPE_NAMES = ["unwind", "rewind", "driven", "idle", "ramp", "steps", "table", "constant",
              "wound_in_ripple", "eccentric_roller", "speed_ripple", "cascaded_pi", "",
              "state_feedback", "adaptive", "measurement_noise", "UNWIND", "missing"]

# Random strings avoid '*' and 'e' so pint never evaluates a huge power or exponent.
safe_text = st.text(alphabet="abcdfgmnstxyz 0123456789.-/", max_size=10)
bad_value = st.one_of(
    st.sampled_from(BAD_VALUES),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**6), max_value=10**6),
    safe_text,
)


def all_paths(node: object, prefix: Path = ()) -> list[Path]:
    """Every key path below ``node`` (not the root itself)."""
    out: list[Path] = []
    if isinstance(node, dict):
        for key, child in node.items():
            out.append((*prefix, key))
            out += all_paths(child, (*prefix, key))
    elif isinstance(node, list):
        for i, child in enumerate(node):
            out.append((*prefix, i))
            out += all_paths(child, (*prefix, i))
    return out


def get(data: Any, path: Path) -> Any:
    for part in path:
        data = data[part]
    return data


@st.composite
def mutated_hswl(draw: st.DrawFn) -> dict[str, Any]:
    """The HSWL file with 1-3 random mutations applied in turn."""
    data = copy.deepcopy(HSWL)
    for _ in range(draw(st.integers(1, 3), label="n_mutations")):
        paths = all_paths(data)
        kind = draw(st.sampled_from(["delete", "set", "unknown_key", "type", "resize",
                                     "swap"]), label="mutation")
        if kind in {"delete", "set"} and paths:
            path = draw(st.sampled_from(paths), label="path")
            parent = get(data, path[:-1])
            if kind == "delete":
                del parent[path[-1]]
            else:
                parent[path[-1]] = draw(bad_value, label="value")
        elif kind == "unknown_key":
            tables = [p for p in [(), *paths] if isinstance(get(data, p), dict)]
            table = get(data, draw(st.sampled_from(tables), label="table"))
            key = draw(st.text(alphabet="abcdefghijklmnopqrstuvwxyz_", min_size=1,
                               max_size=8).filter(lambda k, t=table: k not in t), label="key")
            table[key] = draw(st.one_of(bad_value, st.just(1.0)), label="value")
        elif kind == "type":
            typed = [p for p in paths if p[-1] == "type"]
            if typed:
                path = draw(st.sampled_from(typed), label="path")
                get(data, path[:-1])["type"] = draw(
                    st.one_of(st.sampled_from(TYPE_NAMES), safe_text), label="type")
        elif kind in {"resize", "swap"}:
            lists = [p for p in [("rollers",), ("spans",), *paths]
                     if isinstance(get(data, p) if _exists(data, p) else None, list)]
            if not lists:
                continue
            items = get(data, draw(st.sampled_from(lists), label="list"))
            if kind == "resize":
                new_len = draw(st.integers(0, len(items) + 3), label="length")
                while len(items) < new_len:
                    source = items[draw(st.integers(0, len(items) - 1))] if items else {}
                    items.append(copy.deepcopy(source))
                del items[new_len:]
            elif len(items) >= 2:
                i, j = draw(st.lists(st.integers(0, len(items) - 1), min_size=2, max_size=2,
                                     unique=True), label="swap")
                items[i], items[j] = items[j], items[i]
    return data


def _exists(data: Any, path: Path) -> bool:
    try:
        get(data, path)
    except (KeyError, IndexError, TypeError):
        return False
    return True


def key_parts(key: str) -> Path:
    """'rollers[2].drive.ratio' -> ('rollers', 2, 'drive', 'ratio'); for a range of spans
    ('spans[2]..spans[3]') the first end."""
    key = key.split("..")[0]
    return tuple(int(index) if index else name
                 for name, index in re.findall(r"([^.\[\]]+)|\[(\d+)\]", key))


def reload(spec: LineSpec) -> LineSpec:
    return spec_from_dict(tomllib.loads(dump_spec(spec)), "dumped.toml")


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_hswl())
def test_malformed_specs_raise_only_line_file_error(data: dict[str, Any]) -> None:
    try:
        spec = spec_from_dict(data, "mut.toml")
    except LineFileError as err:
        assert err.file == "mut.toml"
        assert str(err).startswith("mut.toml: ")
        # one problem a line, the first being the error's key and problem
        lines = str(err).splitlines()
        assert lines[0] == f"mut.toml: {err.key}: {err.problem}"
        assert lines == [f"mut.toml: {p.key}: {p.problem}" for p in err.problems[:20]] + (
            [f"mut.toml: and {len(err.problems) - 20} more problems"]
            if len(err.problems) > 20 else [])
        assert err.key.strip() and err.problem.strip()
        # The input is a table, so the error is never blamed on the file as a whole, and
        # the key path starts at a top-level key the file has or the schema defines.
        assert err.key != "(top level)", str(err)
        assert "function-" not in err.key, str(err)
        parts = key_parts(err.key)
        assert parts and (parts[0] in data or parts[0] in LineSpec.model_fields), str(err)
        # Every step but the last is a key or index the file really has (the last may be
        # a missing key): no pydantic union tag ('ramp', 'cascaded_pi', ...) in the path.
        assert _exists(data, parts[:-1]), str(err)
        return
    # Whatever survives is a checked line: its topology is well defined and it round-trips.
    line = Line(spec)
    assert len(line.zones) == len(line.drives) - 1
    assert all(zone.first <= zone.loadcell < zone.last for zone in line.zones)
    assert reload(spec) == spec


def format_path(path: Path) -> str:
    """('spans', 2, 'length') -> 'spans[2].length', as error messages write key paths."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else part)
    return out


#: Every plain value of the HSWL file except the ``type`` selectors (changing a type moves
#: the error to another key, which the property above covers).
LEAVES = [p for p in all_paths(HSWL)
          if not isinstance(get(HSWL, p), dict | list) and p[-1] != "type"]


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(LEAVES), st.one_of(st.sampled_from(BAD_VALUES), bad_value))
def test_one_bad_value_is_reported_at_its_exact_key(path: Path, value: object) -> None:
    data = copy.deepcopy(HSWL)
    get(data, path[:-1])[path[-1]] = value
    try:
        LineSpec.model_validate(data)
    except ValidationError:
        with pytest.raises(LineFileError) as info:
            spec_from_dict(data, "one.toml")
        # The schema rejects the value, so the error is about exactly the key we damaged
        # (or, where the bad value is itself a table or list, a key inside it).
        key, damaged = info.value.key, format_path(path)
        assert key == damaged or key.startswith((f"{damaged}.", f"{damaged}[")), str(info.value)
        return
    # The value is well-formed for its key; the only possible complaint is a cross-key
    # check, still as a LineFileError.
    try:
        spec_from_dict(data, "one.toml")
    except LineFileError as err:
        assert err.key.strip() and err.problem.strip()


# --- valid changes round-trip --------------------------------------------------------------

# each value of the HSWL file scaled by 0.1 .. 10 stays inside its physical range
factor = st.floats(min_value=0.1, max_value=10.0, allow_subnormal=False)


@st.composite
def scaled_hswl(draw: st.DrawFn) -> dict[str, Any]:
    """The HSWL spec in SI with lengths, inertias, frictions, torque limits, tension
    references, the web density and the speed each scaled by its own positive factor."""
    data = load_hswl_si()
    for span in data["spans"]:
        span["length"] *= draw(factor)
        if "tension" in span:
            span["tension"] *= draw(factor)
    for i, roller in enumerate(data["rollers"]):
        roller["inertia"] *= draw(factor)
        roller["friction"] *= draw(factor)
        if 0 < i < len(data["rollers"]) - 1:  # not the rolls: keep core < radius
            roller["radius"] *= draw(factor)
        if "drive" in roller:
            roller["drive"]["torque_limit"] *= draw(factor)
            roller["drive"]["motor_inertia"] = draw(st.sampled_from([0.0, 1e-3])) * draw(factor)
    data["web"]["density"] *= draw(factor)
    data["speed"] *= draw(factor)
    return data


def load_hswl_si() -> dict[str, Any]:
    return spec_from_dict(copy.deepcopy(HSWL)).model_dump(exclude_none=True)


@settings(max_examples=300, deadline=None)
@given(scaled_hswl())
def test_valid_specs_round_trip_exactly(data: dict[str, Any]) -> None:
    spec = spec_from_dict(data, "scaled.toml")
    # Plain numbers are SI and are kept bit for bit ...
    assert [s.length for s in spec.spans] == [s["length"] for s in data["spans"]]
    assert [r.inertia for r in spec.rollers] == [r["inertia"] for r in data["rollers"]]
    # ... through the TOML text and back.
    text = dump_spec(spec)
    again = spec_from_dict(tomllib.loads(text), "scaled.toml")
    assert again == spec
    assert dump_spec(again) == text
