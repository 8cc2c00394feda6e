"""Plans of a study's cases, patched from their base line's plan where a case allows it.

Most of a plan (``compile_plan``) does not depend on the values a Monte Carlo study samples:
the state names, the node and span tables, the reference profiles, the ripples, the offsets
and the structure columns follow from the line's topology and from values the case leaves as
they are. ``CasePlans`` compiles the base line once and makes each case's plan from it with
``plan.patch_plan``, which computes again only the drive table (gains, designs, limits) and
the web's row, at the case's operating point, with the same functions a full plan uses: the
patched plan equals the case's full plan to the last bit.

Which changes take a patch (``patch_kind``), and why each may:

- ``web.ea`` (or ``web.modulus``, of which EA follows): read by the operating point's
  equilibrium (the draw, 6.22), the drive table (PI tuning, designs, observers) and the
  web's row; not by the operating point's inputs
  (``model.operating_point.OperatingInputs``: references, radii, inertias, drags), which are
  the base's, so only the equilibrium is solved again (``solve_operating_point``);
- ``web.strength``: the web's row only (the operating point is the base's);
- ``rollers.<roller>.controller.<key>``: the drive table only (gains, bandwidths, designs,
  observers, estimates); the operating point never reads a controller;
- ``rollers.<roller>.drive.torque_limit`` and ``torque_lag``: the drive table only.

Each with a number as its value. Every other change (an inertia, a friction, a ratio, a span
length, a roll radius, a tension reference, the speed, disturbances, the sample rate, a
choice or a table) changes the operating point's inputs, the node or span tables or the
profiles, and takes a full plan, as does a patched plan whose flags or structure columns
would differ from the base's (``patch_plan`` returns None). The first case of each set of
patched paths is also compiled in full and compared with its patch (``identical``): a
difference, which the tests rule out for the paths above, makes the rest of the study take
full plans too.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from webline.line import Line
from webline.model.operating_point import (
    OperatingInputs,
    operating_inputs,
    solve_operating_point,
)
from webline.sim.core.plan import Plan, _compile, compile_plan, patch_plan
from webline.spec.paths import split_path

#: keys of ``rollers.<roller>.drive`` whose change only the drive table reads
_DRIVE_KEYS = frozenset({"torque_limit", "torque_lag"})
#: keys of ``web`` whose change only the operating point's equilibrium, the drive table and
#: the web's row read (True: the equilibrium is solved again)
_WEB_KEYS = {"ea": True, "modulus": True, "strength": False}


def patch_kind(changes: Mapping[str, object]) -> bool | None:
    """How a case with ``changes`` (``Line.replace`` paths) makes its plan: None for a full
    plan, else whether its operating point must be solved again (True) or is its base's
    (False); module docstring."""
    if not changes:
        return None
    solve = False
    for path, value in changes.items():
        if type(value) not in (float, int):
            return None
        parts = split_path(path)
        if len(parts) == 2 and parts[0] == "web" and parts[1] in _WEB_KEYS:
            solve = solve or _WEB_KEYS[str(parts[1])]
        elif len(parts) == 4 and parts[0] == "rollers" and (
                parts[2] == "controller" or (parts[2] == "drive" and parts[3] in _DRIVE_KEYS)):
            continue
        else:
            return None
    return solve


class CasePlans:
    """The plans of the cases of a study of ``base``: its plan compiled once, each case's
    patched from it where ``patch_kind`` allows, else compiled in full."""

    def __init__(self, base: Line) -> None:
        self.base = base
        self.plan = compile_plan(base)
        self._inputs: OperatingInputs | None = None
        self._checked: dict[frozenset[str], bool] = {}
        self.patched = 0  #: cases whose plan was patched

    def plan_of(self, line: Line, changes: Mapping[str, object]) -> Plan:
        """The plan of ``line``, ``base`` with ``changes`` (``cases.derive_line``)."""
        kind = patch_kind(changes)
        paths = frozenset(changes)
        if kind is None or not self._checked.get(paths, True) or ("plan", None) in line.memo:
            return compile_plan(line)
        if kind:
            if self._inputs is None:  # the base plan's: t = 0, initial radii
                self._inputs = operating_inputs(self.base, 0.0)
            op = solve_operating_point(line, self._inputs)
        else:
            op = self.plan.op
        plan = patch_plan(self.plan, line, op)
        if plan is None:
            return compile_plan(line)
        if paths not in self._checked:  # the first of these paths: against its full plan
            full = _compile(line, None)
            self._checked[paths] = identical(plan, full)
            if not self._checked[paths]:
                line.memo[("plan", None)] = full
                return full
        self.patched += 1
        return plan


def identical(a: Any, b: Any) -> bool:
    """Whether ``a`` and ``b`` hold the same values to the last bit: arrays by shape, type
    and bytes, floats by bits (NaN equal to NaN), dataclasses and tuples field by field; a
    plan's line and memo are left out."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.shape == b.shape
                and a.dtype == b.dtype and a.tobytes() == b.tobytes())
    if isinstance(a, float) and isinstance(b, float):
        return (math.isnan(a) and math.isnan(b)) or (a == b and math.copysign(1, a)
                                                     == math.copysign(1, b))
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        if type(a) is not type(b):
            return False
        return all(identical(getattr(a, f.name), getattr(b, f.name))
                   for f in dataclasses.fields(a) if f.name not in ("line", "memo"))
    if isinstance(a, tuple | list):
        return (type(a) is type(b) and len(a) == len(b)
                and all(identical(x, y) for x, y in zip(a, b, strict=True)))
    return type(a) is type(b) and bool(a == b)
