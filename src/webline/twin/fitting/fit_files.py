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


def _parameter(result: FitResult, i: int) -> dict[str, Any]:
    p, kinds, at = result.parameters[i], result.interval_kind, result.at_bound
    return {"value": float(result.value[i]), "unit": p.unit,
            "stderr": float(result.stderr[i]),
            "ci95": [float(result.ci95[i, 0]), float(result.ci95[i, 1])],
            "interval": kinds[i], "at_bound": at[i] or None,
            "bounds": [float(p.low), float(p.high)],
            "identifiable": bool(result.identifiable[i])}


def fit_json(result: FitResult) -> dict[str, Any]:
    """The ``fit.json`` object: ``{"line", "data" [each record's file], "verdict"
    ("good"/"poor"/"failed"), "reasons" [text], "residual_scale" (joint), "parameters"
    (the shared ones, what ``webline tune --fit`` reads): {PATH: {"value", "unit",
    "stderr", "ci95": [lo, hi], "interval" ("two-sided"/"one-sided"/"bounds"), "at_bound"
    ("low"/"high"/null), "bounds": [low, high], "identifiable"}}, "records": [{"label",
    "data", "scenario", "points", "residual_scale", "correlation_time" [s], "parameters"
    (the record's own, as above)}], "correlation" (every coordinate, in
    "correlation_order": PATH or PATH@RECORD), "simulations", "cost", "converged",
    "starts": {"count", "reached_best"} (null: one start), "effective_points",
    "correlation_time", "checks": [{"signal" ("RECORD: SIGNAL" for several records),
    "rms" (noise levels), "correlation_time" [s], "p_white", "worst_window" [s, s],
    "worst_rms"}], "findings": [text]}``, values in SI."""
    found = result.global_stage
    records = [{"label": r.label, "data": str(r.data.source), "scenario": r.record.scenario,
                "points": r.record.points, "residual_scale": _number(r.residual_scale),
                "correlation_time": _number(r.correlation_time),
                "parameters": {p.path: _parameter(result, i)
                               for i, p in enumerate(result.parameters)
                               if result.owner[i] == k}}
               for k, r in enumerate(result.records)]
    return {"line": result.line.name, "data": [str(r.data.source) for r in result.records],
            "verdict": result.verdict.status, "reasons": list(result.verdict.reasons),
            "residual_scale": _number(result.residual_scale),
            "parameters": {p.path: _parameter(result, i)
                           for i, p in enumerate(result.parameters)
                           if result.owner[i] is None},
            "records": records,
            "correlation": [[float(c) if math.isfinite(c) else 0.0 for c in row]
                            for row in result.correlation],
            "correlation_order": list(result.labels),
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
    """The comment of parameter ``i``: interval and data file(s), or why it was not fitted."""
    p, owner = result.parameters[i], result.owner[i]
    data = result.sources if owner is None else result.records[owner].label
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
    """The fitted line as TOML (SI, ``dump_spec``), a header listing every parameter (each
    record's own too: their values belong to the record, not to the line) and each record's
    residual scale, and a comment on each shared value's line (where it has a line of its
    own)."""
    text = dump_spec(result.fitted_line.spec)
    lines = text.splitlines()
    for i, p in enumerate(result.parameters):
        row = _value_row(lines, p.path) if result.owner[i] is None else None
        if row is not None:
            lines[row] = f"{lines[row]}  # {annotation(result, i)}"
    verdict = result.verdict
    sources = ", ".join(str(r.data.source) for r in result.records)
    header = [f"# Line {result.line.name!r} fitted by webline to {sources}",
              f"# VERDICT: {verdict.status.upper()}" + (
                  " - " + "; ".join(verdict.reasons) if verdict.reasons else ""),
              f"# {result.simulations} simulations, cost {result.cost:.6g}, "
              f"{'converged' if result.converged else 'NOT converged'}; values in SI",
              *(f"# record {r.label}: residuals {r.residual_scale:.3g} x the noise"
                + (f" (scenario {r.record.scenario})" if r.record.scenario else "")
                for r in result.records if len(result.records) > 1),
              *(f"# {result.labels[i]}: {annotation(result, i)}"
                for i in range(len(result.parameters))),
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
