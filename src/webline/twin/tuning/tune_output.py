"""The files of ``webline tune``: the tuned line, the numbers, the gain schedule, figures and
an HTML report (``report.html`` pieces)."""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from webline.spec.load import dump_spec
from webline.twin.tuning.tune import OBJECTIVE, TuneResult
from webline.twin.tuning.tune_branched import line_gain_table
from webline.version import __version__

FILES = ("tuned.toml", "tune.json", "gain_table.csv", "report.html")


def tune_json(result: TuneResult) -> dict[str, Any]:
    """Everything ``tune`` found, as plain data (SI)."""
    def evaluation(e: Any) -> dict[str, Any]:
        return {"objective": e.objective, "terms": e.terms, "values": e.values,
                "constraints": [c.as_dict() for c in e.constraints],
                "every_constraint_holds": e.feasible}

    return {"webline_version": __version__, "line": result.line.name,
            "objective": OBJECTIVE, "scenarios": list(result.scenarios),
            "free": [{"path": p.path, "low": p.low, "high": p.high} for p in result.free],
            "limits": result.limits.as_dict(),
            "objective_before": result.before.objective,
            "objective_after": result.after.objective,
            "relative_improvement": result.improvement,
            "every_constraint_holds": result.holds,
            "before": evaluation(result.before), "after": evaluation(result.after),
            "robustness": result.robust.as_dict(),
            "gains_before": result.gains_before, "gains_after": result.gains_after,
            "gain_table": line_gain_table(result.tuned),
            "evaluations": result.evaluations, "seconds": result.seconds,
            "notes": list(result.notes)}


def tuned_toml(result: TuneResult) -> str:
    """The tuned line file: a header saying what was tuned, on what and what holds, then the
    line (SI) with its gains explicit."""
    lines = [f"# Tuned by webline {__version__} (webline tune) from {result.line.name}.",
             f"# Objective: {OBJECTIVE}",
             f"#   over scenarios {', '.join(result.scenarios)}: "
             f"{result.before.objective:.5g} before, {result.after.objective:.5g} after.",
             "# Tuned values (SI; bounds in brackets):"]
    for p in result.free:
        lines.append(f"#   {p.path}: {result.before.values.get(p.path, math.nan):.5g} -> "
                     f"{result.after.values[p.path]:.5g}  [{p.low:.4g} .. {p.high:.4g}]")
    lines.append("# Gains written explicitly so they stay as tuned when a parameter changes "
                 "(a roll's speed gains follow its diameter: gain_table.csv):")
    for path, value in result.gains_after.items():
        was = result.gains_before.get(path, math.nan)
        lines.append(f"#   {path} = {value:.6g} (was {was:.6g})")
    lines.append("# Constraints (worst over scenarios and roll points):")
    for c in result.after.constraints:
        lines.append(f"#   {c.name}: {c.value:.4g} {c.sense} {c.limit:g} "
                     f"({'holds' if c.holds else 'FAILS'}) {c.where}")
    lines += [f"# {text}" for text in result.robust.lines()]
    return "\n".join(lines) + "\n\n" + dump_spec(result.tuned.spec)


def write_tune(result: TuneResult, out: Path,
               claim: Callable[[str], Path] | None = None) -> list[Path]:
    """Write ``FILES`` and the figures into ``out``; ``claim(relative)`` gives each file's
    path (an output folder's bookkeeping), default ``out / relative``."""
    place = claim or (lambda relative: out / relative)
    written = []
    path = place("tuned.toml")
    path.write_text(tuned_toml(result), encoding="utf-8")
    written.append(path)
    data = tune_json(result)
    path = place("tune.json")
    path.write_text(json.dumps(data, indent=2, allow_nan=True), encoding="utf-8")
    written.append(path)
    path = place("gain_table.csv")
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, ["drive", "diameter_m", "speed_kp", "speed_ki"])
        writer.writeheader()
        writer.writerows(data["gain_table"])
    written.append(path)
    from webline.twin.tuning.tune_figures import figures, report_html

    images = figures(result)
    for image in images:
        path = place(f"{image.key}.png")
        path.write_bytes(image.png)
        written.append(path)
    path = place("report.html")
    path.write_text(report_html(result, data, images), encoding="utf-8")
    written.append(path)
    return written


def csv_text(rows: list[dict[str, Any]]) -> str:
    """``rows`` as CSV text (for the report's folded tables)."""
    buffer = io.StringIO()
    if rows:
        writer = csv.DictWriter(buffer, list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return buffer.getvalue()
