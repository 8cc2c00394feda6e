"""What ``webline.tune`` may change and how a tuned line keeps its gains.

A tuning variable is a line path with bounds [SI]; the optimiser moves on the logarithm of
each (gains and bandwidths are scale parameters: a factor of two matters as much at 2 rad/s
as at 40). The default set is every cascaded-PI drive's ``speed_bandwidth`` and, on
tension-controlling drives, ``tension_bandwidth`` (for a zone held by a dancer in position
control that is the dancer loop: its gains follow from it, docs/winder.md Z2), each from a
third to three times its value.

A tuned line must not re-tune itself when a parameter changes (a drive's gains stay what was
commissioned), so the tuned line carries its gains explicitly (``frozen_gains``): the speed
PIs of driven rollers and the tension (or dancer position) PIs. A roll's speed PI is
scheduled with its diameter (``inertia_adaptive``: J(r)/(n r)) and a plan normalises that
schedule at the run's initial roll, so an explicit value would mean another gain in a run
that starts from another roll (a splice scenario): it stays defined by its
``speed_bandwidth``, and its gains over the diameter are tabulated (``gain_table``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from webline.errors import ArgumentError, LineFileError
from webline.line import Line
from webline.sim.core.plan import compile_plan
from webline.sim.elements import layout as L
from webline.sim.sweeps.cases import case_value, derive_line
from webline.spec.schema import CascadedPISpec

#: default bounds of a free bandwidth: its value divided and multiplied by this [1]
DEFAULT_SPAN = 3.0


@dataclass(frozen=True)
class LineOps:
    """What ``webline.tune`` does with one kind of line (a single-path line: ``tune.CHAIN``;
    a branched one: ``tune_branched.BRANCHED``): load it, its default ``FreeParameter``s,
    ``derive(line, {path: value})``, its ``frozen_gains``, ``run_cases(line, cases, *,
    scenario, workers)`` (a Dataset with ``tension_rms_error`` (case, span), ``status``,
    ``torque_limit_time`` (case, drive)), ``set_tension(line)`` [N] per span, its
    ``stability(line, limits)`` constraints (the nominal's and each robustness draw's) and
    ``default_uncertain(line)``."""

    load: Callable[[Any], Any]
    default_free: Callable[[Any], list[FreeParameter]]
    derive: Callable[[Any, Mapping[str, Any]], Any]
    frozen_gains: Callable[[Any], dict[str, float]]
    run_cases: Callable[..., Any]
    set_tension: Callable[[Any], np.ndarray]
    stability: Callable[[Any, Any], list[Any]]
    default_uncertain: Callable[[Any], dict[str, str]]


@dataclass(frozen=True)
class FreeParameter:
    """A tuned value: line ``path``, bounds ``low`` < ``high`` [SI, > 0]."""

    path: str
    low: float
    high: float


def default_free(line: Line) -> list[FreeParameter]:
    """The default tuning variables of ``line`` (module docstring)."""
    return pi_bandwidths(line, lambda i: line.controlled_zone(i) is not None)


def pi_bandwidths(line: Any, holds_tension: Callable[[int], bool]) -> list[FreeParameter]:
    """Each cascaded-PI drive's ``speed_bandwidth`` and, where ``holds_tension(node)``, its
    ``tension_bandwidth`` [rad/s], from a third to three times their values (``line``: a
    single-path or branched line, its ``drives`` and ``spec.rollers``)."""
    out = []
    for i in line.drives:
        roller = line.spec.rollers[i]
        c = getattr(roller, "controller", None)
        if not isinstance(c, CascadedPISpec):
            continue
        base = f"rollers.{roller.name}.controller"
        out.append(_around(f"{base}.speed_bandwidth", c.speed_bandwidth))
        if holds_tension(i):
            out.append(_around(f"{base}.tension_bandwidth", c.tension_bandwidth))
    return out


def _around(path: str, value: float) -> FreeParameter:
    return FreeParameter(path, value / DEFAULT_SPAN, value * DEFAULT_SPAN)


def parse_free(line: Any, text: str) -> FreeParameter:
    """``"PATH=LOW..HIGH"`` (units as the line file takes them; a unit written once, after
    HIGH, applies to both) as a ``FreeParameter`` in SI. Raises ``ArgumentError``."""
    path, sep, bounds = text.partition("=")
    low_text, dots, high_text = bounds.partition("..")
    if not sep or not dots or not path.strip() or not low_text.strip() or not high_text.strip():
        raise ArgumentError(f"--free {text!r}: expected PATH=LOW..HIGH, e.g. "
                            "rollers.infeed.controller.tension_bandwidth=1..20")
    path, low_text, high_text = path.strip(), low_text.strip(), high_text.strip()
    unit = high_text.split(maxsplit=1)[1] if len(high_text.split(maxsplit=1)) == 2 else ""
    if unit and _is_number(low_text):
        low_text = f"{low_text} {unit}"
    # a plain number is SI, as a line file's numbers are
    low, high = (path_value(line, path, float(t) if _is_number(t) else t)
                 for t in (low_text, high_text))
    if not 0.0 < low < high:
        raise ArgumentError(f"--free {text!r}: needs 0 < LOW < HIGH (tuning moves on log "
                            f"values), got {low:g} .. {high:g} [SI]")
    return FreeParameter(path, low, high)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def path_value(line: Any, path: str, text: object) -> float:
    """The SI number ``line`` (single-path or branched) reads at ``path`` for ``text``;
    ``ArgumentError`` naming the path where the line refuses it or the path is not a
    number."""
    from webline.model.web_graph import BranchedLine

    derive: Callable[[Any, dict[str, object]], Any] = derive_line
    if isinstance(line, BranchedLine):
        from webline.sim.sweeps.branch_study import derive_branched

        derive = derive_branched
    try:
        value = case_value(derive(line, {path: text}), path)
    except LineFileError as exc:
        raise ArgumentError(f"{path}: {exc}") from None
    if not isinstance(value, float | int) or isinstance(value, bool):
        raise ArgumentError(f"{path}: not a number the tuning can move (got {value!r})")
    return float(value)


def frozen_gains(line: Line) -> dict[str, float]:
    """Every cascaded-PI drive's gains as ``line`` compiles them [SI], as line paths (module
    docstring): ``speed_kp``/``speed_ki`` of drives that do not schedule them with a roll,
    ``tension_kp``/``tension_ki``, or the dancer's ``position_kp``/``position_ki`` where the
    zone's loop holds a dancer."""
    plan = compile_plan(line)
    out: dict[str, float] = {}
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        if not isinstance(getattr(roller, "controller", None), CascadedPISpec):
            continue
        row = plan.drives[d]
        base = f"rollers.{roller.name}.controller"
        if row[L.D_ADAPTIVE] <= 0:
            out[f"{base}.speed_kp"] = float(row[L.D_KPS])
            out[f"{base}.speed_ki"] = float(row[L.D_KIS])
        if row[L.D_ROLE] != L.ROLE_TENSION:
            continue
        if row[L.D_DANCER] >= 0 and row[L.D_DUSE] == L.DANCER_POSITION:
            dancer = f"rollers.{line.node_name(int(row[L.D_DANCER]))}.dancer"
            out[f"{dancer}.position_kp"] = float(row[L.D_KPT])
            out[f"{dancer}.position_ki"] = float(row[L.D_KIT])
        else:
            out[f"{base}.tension_kp"] = float(row[L.D_KPT])
            out[f"{base}.tension_ki"] = float(row[L.D_KIT])
    return out


def roll_radii(line: Line, n: int) -> list[tuple[float, float]]:
    """``n`` (unwind, rewind) radius pairs [m] across one roll: the web that leaves the
    unwind arrives on the rewind (equal wound areas, the same width and thickness), from the
    initial radii until the unwind reaches its core or the rewind the unwind's initial
    radius."""
    unwind, rewind = line.unwind, line.rewind
    area = min(unwind.radius**2 - unwind.core_radius**2,
               max(unwind.radius, rewind.radius)**2 - rewind.radius**2)
    out = []
    for s in np.linspace(0.0, 0.95, n):  # stop short of the bare core
        moved = s * area
        out.append((math.sqrt(unwind.radius**2 - moved), math.sqrt(rewind.radius**2 + moved)))
    return out


def line_at_roll(line: Line, unwind_radius: float, rewind_radius: float) -> Line:
    """``line`` starting at these roll radii [m] (its rolls' speed gains designed there, as
    the drives schedule them)."""
    return derive_line(line, {"rollers[0].radius": unwind_radius,
                              f"rollers[{line.n_nodes - 1}].radius": rewind_radius})


def gain_table(line: Line, points: int = 9) -> list[dict[str, float | str]]:
    """Rows (drive, diameter [m], speed_kp [N·m·s/m], speed_ki [N·m/m]) of every roll whose
    speed gains follow its diameter, at ``points`` diameters from just above its core to
    the larger of the two rolls' initial diameters."""
    rows: list[dict[str, float | str]] = []
    top = max(line.unwind.radius, line.rewind.radius)
    for i in (0, line.n_nodes - 1):
        d = line.drives.index(i) if i in line.drives else -1
        if d < 0 or compile_plan(line).drives[d, L.D_ADAPTIVE] <= 0:
            continue
        core = line.spec.rollers[i].core_radius  # type: ignore[union-attr]
        for r in np.linspace(core * 1.02, top, points):
            row = compile_plan(derive_line(line, {f"rollers[{i}].radius": float(r)})).drives[d]
            rows.append({"drive": line.node_name(i), "diameter_m": 2.0 * float(r),
                         "speed_kp": float(row[L.D_KPS]), "speed_ki": float(row[L.D_KIS])})
    return rows


def with_values(line: Line, values: Mapping[str, float]) -> Line:
    """``line`` with ``values`` [SI] at their paths."""
    return derive_line(line, dict(values))
