"""Mutations of the built-in line files, shared by the fuzz test and the fuzz benchmark.

Each mutator takes a ``Chooser`` (hypothesis's ``draw`` in the test, ``random.Random`` in
the benchmark) and returns the bytes of a line file. Categories: wrong types, missing and
unknown keys, numeric edges, unit strings, topology, file-level damage.
"""

from __future__ import annotations

import contextlib
import copy
import math
import tomllib
from collections.abc import Callable, Sequence
from importlib import resources
from typing import Any, Protocol, TypeVar

import tomli_w

T = TypeVar("T")


class Chooser(Protocol):
    def pick(self, options: Sequence[T]) -> T: ...

    def integer(self, low: int, high: int) -> int: ...


BUILTIN = {name: resources.files("webline.data.lines").joinpath(f"{name}.toml").read_text("utf-8")
           for name in ("hswl", "rockwell")}
DATA = {name: tomllib.loads(text) for name, text in BUILTIN.items()}

WRONG_TYPES: list[object] = [[], [1, 2], ["a"], [{}], {}, {"a": 1}, {"type": "ramp"}, True,
                             False, "abc", "", 3, -1, 2.5, "x" * 5000]
NUMERIC_EDGES: list[object] = [0, 0.0, -0.0, math.inf, -math.inf, math.nan, 1e308, -1e308,
                               1e-308, 5e-324, 1e300, 1e-300, 10**30, -(10**30), 2**63 - 1,
                               2**63, 10**400, -1, 1e6, 1e-9, 1e9, 1e-6]
UNIT_STRINGS: list[str] = [
    "1,5 m", "1.2.3 m", "{{7*7}} m", "3 deg", "5 %", "1e400 m", "9**9**9 m", "1 m\x01",
    "6 Hz", "40 rad/s", "1 furlong", "", " ", "1 m m", "1 m**99", "1 m**999", "1e-400 s",
    "2e5 N/m", "1 lbf", "1 ft", "3 ms", "1 GHz", "1 nm", "1 km", "1e300 kg*m**2", "-1 m",
    "1 N*m", "0.5 lbf*ft*s", "500 fpm", "1 kg/m**3", "4.6 GPa", "1 ns", "1 (m)", "1 m/(s",
    "1 m\u202e", "nan Hz", "inf m", "0x10 m", "1_000 m", "１ m", "1 µm", "1 m # x", "10 kHz",
]
TYPE_NAMES = ["unwind", "rewind", "driven", "idle", "ramp", "steps", "table", "belt", "shaft",
              "direct", "adaptive", "state_feedback", "cascaded_pi", "traction", "", "UNWIND"]
UNKNOWN_KEYS = ["torque_limt", "lenght", "radious", "inertia_", "foo", "", "type2",
                "speed_bandwith", "x" * 300]


Path = tuple[str | int, ...]


def paths(node: object, prefix: Path = ()) -> list[Path]:
    """Every key path below ``node``."""
    out: list[Path] = []
    items = (node.items() if isinstance(node, dict) else
             enumerate(node) if isinstance(node, list) else ())
    for key, child in items:
        out.append((*prefix, key))
        out.extend(paths(child, (*prefix, key)))
    return out


def get(node: Any, path: Path) -> Any:
    for part in path:
        node = node[part]
    return node


def leaves(data: object) -> list[Path]:
    return [p for p in paths(data) if not isinstance(get(data, p), dict | list)]


def tables(data: object) -> list[Path]:
    return [(), *(p for p in paths(data) if isinstance(get(data, p), dict))]


def _set(data: Any, choose: Chooser, value: object) -> None:
    path = choose.pick(leaves(data))
    get(data, path[:-1])[path[-1]] = value


def types(data: Any, choose: Chooser) -> None:
    _set(data, choose, copy.deepcopy(choose.pick(WRONG_TYPES)))  # never share (cycles)


def keys(data: Any, choose: Chooser) -> None:
    what = choose.integer(0, 2)
    table = get(data, choose.pick(tables(data)))
    if what == 0 and table:
        del table[choose.pick(sorted(table))]
    elif what == 1:
        table[choose.pick(UNKNOWN_KEYS)] = copy.deepcopy(choose.pick([1, "1 m", {"a": 1}, [1]]))
    elif table:  # a typo of a key that exists
        key = choose.pick(sorted(table))
        table[key[:-1] + key[-1:] * 2 if key else "x"] = table.pop(key)


def numbers(data: Any, choose: Chooser) -> None:
    numeric = [p for p in leaves(data) if isinstance(get(data, p), int | float | str)
               and not isinstance(get(data, p), bool) and p[-1] not in ("name", "type")]
    path = choose.pick(numeric)
    value: object = choose.pick(NUMERIC_EDGES)
    if choose.integer(0, 2) == 0 and isinstance(get(data, path), str):
        unit = get(data, path).partition(" ")[2]
        value = f"{choose.pick(NUMERIC_EDGES)!r} {unit}".strip()
    get(data, path[:-1])[path[-1]] = value


def units(data: Any, choose: Chooser) -> None:
    numeric = [p for p in leaves(data) if p[-1] not in ("name", "type", "role", "feedback")]
    path = choose.pick(numeric)
    get(data, path[:-1])[path[-1]] = choose.pick(UNIT_STRINGS)


def topology(data: Any, choose: Chooser) -> None:
    rollers, spans = data["rollers"], data["spans"]
    what = choose.integer(0, 6)
    i = choose.integer(0, len(rollers) - 1)
    j = choose.integer(0, len(rollers) - 1)
    if what == 0:
        del rollers[i]
    elif what == 1:
        del spans[min(i, len(spans) - 1)]
    elif what == 2:
        rollers[i], rollers[j] = rollers[j], rollers[i]
    elif what == 3:
        rollers.insert(i, copy.deepcopy(rollers[j]))
    elif what == 4:
        rollers[i]["type"] = choose.pick(TYPE_NAMES)
    elif what == 5:
        spans.reverse()
        spans.append(copy.deepcopy(spans[0]))
    else:
        for roller in rollers:
            if roller.get("role") == "master":
                roller["role"] = "tension"
        rollers[i]["role"] = "master"


def file_damage(data: Any, choose: Chooser) -> bytes:
    """Damage at the level of bytes."""
    raw = tomli_w.dumps(data).encode()
    what = choose.integer(0, 9)
    at = choose.integer(0, len(raw))
    if what == 0:
        return raw[:at]
    if what == 1:
        out = bytearray(raw)
        for _ in range(choose.integer(1, 8)):
            k = choose.integer(0, len(out) - 1)
            out[k] ^= 1 << choose.integer(0, 7)
        return bytes(out)
    if what == 2:
        return b"\xef\xbb\xbf" + raw
    if what == 3:
        return raw[:at] + b"\x00" + raw[at:]
    if what == 4:
        depth = choose.pick([10, 100, 500, 999, 1000, 5000, 100_000])
        return raw + b"\nnested = " + b"[" * depth + b"]" * depth + b"\n"
    if what == 5:
        return raw + b'\nlong = "' + b"x" * choose.pick([10**4, 10**6]) + b'"\n'
    if what == 6:
        return raw.replace(b'name = "', b'name = "' + b"y" * choose.pick([200, 10**6]), 1)
    if what == 7:
        return raw + b"\nbig = " + b"9" * choose.pick([19, 100, 4300, 5000, 100_000]) + b"\n"
    if what == 8:
        return bytes(choose.integer(0, 255) for _ in range(choose.integer(1, 2000)))
    return raw + b"\n# padding\n" * choose.pick([10, 300_000])


CATEGORIES: dict[str, Callable[[Any, Chooser], None]] = {
    "types": types, "keys": keys, "numbers": numbers, "units": units, "topology": topology,
}


def mutate(category: str, choose: Chooser) -> bytes:
    """The bytes of one mutated built-in line file of ``category`` ("file" or a key of
    ``CATEGORIES``), after 1 to 3 mutations."""
    data = copy.deepcopy(DATA[choose.pick(sorted(DATA))])
    if category == "file":
        return file_damage(data, choose)
    for _ in range(choose.integer(1, 3)):
        # a mutation that does not fit this (already mutated) file leaves it as it is
        with contextlib.suppress(IndexError, KeyError, TypeError, ValueError):
            CATEGORIES[category](data, choose)
    try:
        return tomli_w.dumps(data).encode()
    except (TypeError, ValueError):  # a value TOML cannot hold: damage the file instead
        return file_damage(DATA["hswl"], choose)


def check(raw: bytes, path: str) -> tuple[str, str]:
    """Run a line file through what ``webline validate`` does (load, every scenario) plus
    building the line's plan: ('clean', message) for a ``LineFileError``, ('accepted', '')
    or ('absurd', what) for a loaded line, any other exception propagates."""
    from webline.errors import LineFileError
    from webline.line import load_line
    from webline.sim.core.plan import compile_plan
    from webline.spec.ranges import walk

    with open(path, "wb") as handle:
        handle.write(raw)
    try:
        line = load_line(path)
        for name in line.spec.scenarios:
            line.with_scenario(name)
        compile_plan(line)
    except LineFileError as exc:
        return "clean", exc.problems[0].key
    for key, found, value in walk(line.spec):
        if not math.isfinite(value) or found.hard_problem(value):
            return "absurd", f"{key} = {value!r}"
    return "accepted", ""
