"""Fuzzing the front door (issue 11): mutated built-in line files either load cleanly or
raise ``LineFileError`` -- never another exception -- and a file that loads has every
quantity inside its documented hard range (``webline.spec.ranges``).

The mutations (wrong types, missing and unknown keys, numeric edges, unit strings, topology,
file-level damage) are those of ``benchmarks/fuzz_mutations.py``, drawn by hypothesis here
and by ``random`` in ``benchmarks/fuzz_line_files.py`` (>= 10 000 files).
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from webline.errors import LineFileError
from webline.line import load_line
from webline.spec.ranges import walk

_FILE = Path(__file__).resolve().parents[2] / "benchmarks" / "fuzz_mutations.py"
_SPEC = importlib.util.spec_from_file_location("fuzz_mutations", _FILE)
assert _SPEC and _SPEC.loader
fuzz = importlib.util.module_from_spec(_SPEC)
sys.modules["fuzz_mutations"] = fuzz
_SPEC.loader.exec_module(fuzz)

CATEGORIES = [*fuzz.CATEGORIES, "file"]


class DrawChooser:
    """The ``Chooser`` of ``fuzz_mutations`` over hypothesis's ``draw`` (so it shrinks)."""

    def __init__(self, draw: st.DrawFn) -> None:
        self.draw = draw

    def pick(self, options: Any) -> Any:
        return self.draw(st.sampled_from(list(options)))

    def integer(self, low: int, high: int) -> int:
        return self.draw(st.integers(low, high))


@st.composite
def mutated_file(draw: st.DrawFn, category: str) -> bytes:
    return fuzz.mutate(category, DrawChooser(draw))


def _check(raw: bytes, tmp_path: Path) -> None:
    path = tmp_path / "fuzz.toml"
    path.write_bytes(raw)
    try:
        line = load_line(path)
        for name in line.spec.scenarios:
            line.with_scenario(name)
    except LineFileError as err:
        assert err.file == str(path)
        assert err.problems and all(p.key.strip() and p.problem.strip() for p in err.problems)
        assert len(str(err).splitlines()) <= 21  # at most 20 problems, then "and N more"
        return
    for key, found, value in walk(line.spec):
        assert math.isfinite(value) and found.hard_problem(value) is None, (key, value)


# 60 examples per category: the six categories take ~10-20 s together on this machine.
@pytest.mark.parametrize("category", CATEGORIES)
@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture,
                                 HealthCheck.data_too_large])
@given(data=st.data())
def test_mutated_file_loads_or_raises_line_file_error(category: str, data: st.DataObject,
                                                      tmp_path: Path) -> None:
    _check(data.draw(mutated_file(category)), tmp_path)


@pytest.mark.parametrize(("name", "raw"), [
    ("deep nesting", b"x = " + b"[" * 100_000 + b"]" * 100_000),
    ("binary", bytes(range(256)) * 4),
    ("NUL byte", b'name = "a\x00"'),
    ("huge integer", b"x = " + b"9" * 5000),
    ("huge file", b"# x\n" * 600_000),
    ("long string", b'name = "' + b"y" * 1_000_000 + b'"'),
])
def test_file_level_damage_is_one_clean_error(name: str, raw: bytes, tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_bytes(raw)
    with pytest.raises(LineFileError) as info:
        load_line(path)
    assert len(str(info.value)) < 2000, name  # the message never echoes the whole input


def test_a_bom_is_accepted(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + fuzz.BUILTIN["hswl"].encode())
    assert load_line(path).spec == load_line("hswl").spec
