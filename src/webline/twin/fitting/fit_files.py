"""A fit's files: ``fit.json`` (the numbers, for ``webline tune`` and scripts) and
``fitted.toml`` (the line with the fitted values, each annotated with its interval and the
data it came from)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

from webline.files import atomic_write_text
from webline.spec.load import dump_spec
from webline.spec.paths import split_path

if TYPE_CHECKING:
    from webline.twin.fitting.fit import FitResult


def _number(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


def fit_json(result: FitResult) -> dict[str, Any]:
    """The ``fit.json`` object: ``{"line", "data", "verdict" ("good"/"poor"/"failed"),
    "reasons" [text], "residual_scale", "parameters": {PATH: {"value", "unit", "stderr",
    "ci95": [lo, hi], "interval" ("two-sided"/"one-sided"/"bounds"), "at_bound"
    ("low"/"high"/null), "bounds": [low, high], "identifiable"}}, "correlation",
    "simulations", "cost", "converged", "starts": {"count", "reached_best"} (null: one
    start), "effective_points", "correlation_time", "checks": [{"signal", "rms" (noise
    levels), "correlation_time" [s], "p_white", "worst_window" [s, s], "worst_rms"}],
    "findings": [text]}``, values in SI."""
    kinds, at = result.interval_kind, result.at_bound
    parameters = {
        p.path: {"value": float(result.value[i]), "unit": p.unit,
                 "stderr": float(result.stderr[i]),
                 "ci95": [float(result.ci95[i, 0]), float(result.ci95[i, 1])],
                 "interval": kinds[i], "at_bound": at[i] or None,
                 "bounds": [float(p.low), float(p.high)],
                 "identifiable": bool(result.identifiable[i])}
        for i, p in enumerate(result.parameters)}
    found = result.global_stage
    return {"line": result.line.name, "data": str(result.data.source),
            "verdict": result.verdict.status, "reasons": list(result.verdict.reasons),
            "residual_scale": _number(result.residual_scale),
            "parameters": parameters,
            "correlation": [[float(c) if math.isfinite(c) else 0.0 for c in row]
                            for row in result.correlation],
            "simulations": int(result.simulations), "cost": _number(result.cost),
            "converged": bool(result.converged),
            "starts": ({"count": found.count, "reached_best": found.reached}
                       if found is not None else None),
            "effective_points": int(result.effective_points),
            "correlation_time": _number(result.correlation_time),
            "checks": [{"signal": c.signal, "rms": _number(c.rms),
                        "correlation_time": _number(c.correlation_time),
                        "p_white": _number(c.p_white), "worst_window": list(c.window),
                        "worst_rms": _number(c.window_rms)} for c in result.checks.signals],
            "findings": list(result.checks.findings)}


def annotation(result: FitResult, i: int) -> str:
    """The comment of parameter ``i``: interval and data file, or why it was not fitted."""
    p, data = result.parameters[i], Path(result.data.source).name
    if not result.identifiable[i]:
        return (f"not identifiable from {data} ({result.identifiability.reasons[i]}): "
                f"kept the line's value")
    lo, hi = result.ci95[i]
    side = result.at_bound[i]
    where = f" at its {'lower' if side == 'low' else 'upper'} bound" if side else ""
    if not result.verdict.good:
        # a poor fit's numbers are not an estimate with an interval: say so on each line
        return (f"{result.verdict.status.upper()} FIT to {data}, not to be trusted: "
                f"{result.value[i]:.6g} {p.unit}{where} (the interval "
                f"{lo:.6g} .. {hi:.6g} assumes a model the data contradict)")
    one = " (one-sided)" if side else ""
    return (f"fitted to {data}: {result.value[i]:.6g} {p.unit}{where}, 95 % interval{one} "
            f"{lo:.6g} .. {hi:.6g}, stderr {result.stderr[i]:.3g}")


def fitted_toml(result: FitResult) -> str:
    """The fitted line as TOML (SI, ``dump_spec``), a header listing every parameter and a
    comment on each fitted value's line (where the value has a line of its own)."""
    text = dump_spec(result.fitted_line.spec)
    lines = text.splitlines()
    for i, p in enumerate(result.parameters):
        row = _value_row(lines, p.path)
        if row is not None:
            lines[row] = f"{lines[row]}  # {annotation(result, i)}"
    verdict = result.verdict
    header = [f"# Line {result.line.name!r} fitted by webline to {result.data.source}",
              f"# VERDICT: {verdict.status.upper()}" + (
                  " - " + "; ".join(verdict.reasons) if verdict.reasons else ""),
              f"# {result.simulations} simulations, cost {result.cost:.6g}, "
              f"{'converged' if result.converged else 'NOT converged'}; values in SI",
              *(f"# {p.path}: {annotation(result, i)}"
                for i, p in enumerate(result.parameters)),
              *(f"# model check: {f}" for f in result.checks.findings), ""]
    return "\n".join(header + lines) + "\n"


def _value_row(lines: list[str], path: str) -> int | None:
    """Index of the ``key = value`` line of ``path`` in ``dump_spec``'s text: under the
    table ``[SECTION.SUB...]`` (or ``[[SECTION]]`` for the element itself) whose element is
    named ``name = "ELEMENT"``; None where the value sits in an inline table."""
    parts = [str(x) for x in split_path(path)]
    if len(parts) < 2:
        return None
    section, key = parts[0], parts[-1]
    arrays = {"rollers", "spans", "disturbances", "webs"}  # (webs: a branched line's)
    element = parts[1] if section in arrays else None
    inner = parts[2:-1] if section in arrays else parts[1:-1]
    want = ".".join([section, *inner])
    header, current = "", None
    for row, text in enumerate(lines):
        match = re.match(r"^\[\[?([^\]]+)\]\]?\s*$", text)
        if match:
            header = match[1]
            if text.startswith("[[") and header == section:
                current = None
            continue
        name = re.match(r'^name = "(.*)"$', text)
        if name and header == section:
            current = name[1]
        if header == want and (element is None or current == element) and \
                text.startswith(f"{key} = "):
            return row
    return None


def write_fit_files(result: FitResult, out: Path) -> tuple[Path, Path]:
    """Write ``out/fitted.toml`` and ``out/fit.json`` (atomically); their paths."""
    out.mkdir(parents=True, exist_ok=True)
    toml_path, json_path = out / "fitted.toml", out / "fit.json"
    atomic_write_text(toml_path, fitted_toml(result))
    atomic_write_text(json_path, json.dumps(fit_json(result), indent=2) + "\n")
    return toml_path, json_path
