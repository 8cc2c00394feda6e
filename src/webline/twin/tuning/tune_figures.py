"""Figures and the HTML report of ``webline tune``: each scenario's loadcell tensions before
and after, the gain schedule against diameter, the tables of constraints and gains."""

from __future__ import annotations

import io
import math
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from webline.report.text.html import Image, Section, Text, render
from webline.report.text.tables import make_table
from webline.twin.tuning.tune import OBJECTIVE, TuneResult
from webline.twin.tuning.tune_branched import line_gain_table
from webline.version import __version__


def _png(fig: Any) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110, bbox_inches="tight")
    plt.close(fig)
    return buffer.getvalue()


def scenario_figure(result: TuneResult, scenario: str) -> Image:
    """Tension error of every loadcell span [N] over time, before and after."""
    from webline.sim.simulate import simulate

    runs = {"before": _errors(simulate(result.line, scenario=scenario,
                                       raise_on_failure=False)),
            "after": _errors(simulate(result.tuned, scenario=scenario,
                                      raise_on_failure=False))}
    names = [name for name, _ in runs["before"][1]]
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 1.9 * len(names) + 0.6), sharex=True,
                             squeeze=False)
    for k, (ax, name) in enumerate(zip(axes[:, 0], names, strict=True)):
        for label, (time, errors) in runs.items():
            error = errors[k][1]
            rms = math.sqrt(float(np.mean(error**2)))
            ax.plot(time, error, lw=0.9, label=f"{label}: RMS {rms:.3g} N",
                    ls="-" if label == "after" else "--")
        ax.set_ylabel(f"{name}\nerror [N]", fontsize=8)
        ax.legend(fontsize=7, loc="upper right")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(f"{scenario}: tension minus reference, before and after tuning", fontsize=10)
    caption = (f"Scenario {scenario}: each loadcell span's tension error before (dashed) and "
               "after (solid) tuning, with its RMS over the run.")
    return Image(f"tension_{scenario}", caption, _png(fig))


def _errors(run: Any) -> tuple[np.ndarray, list[tuple[str, np.ndarray]]]:
    """(time [s], [(loadcell span, tension minus reference [N])]) of a run of either kind."""
    from webline.sim.results.result import Result

    if not isinstance(run, Result):  # a branched line's BranchResult
        from webline.twin.tuning.tune_branched import loadcell_errors

        return loadcell_errors(run)
    ref = run.tension_ref
    return run.time, [(run.plan.line.span_name(k), run.tension[:, k] - ref[:, k])
                      for k in range(ref.shape[1]) if np.all(np.isfinite(ref[:, k]))]


def schedule_figure(table: list[dict[str, Any]]) -> Image | None:
    """The speed gains of the scheduled rolls against diameter."""
    drives = sorted({str(r["drive"]) for r in table})
    if not drives:
        return None
    fig, ax = plt.subplots(figsize=(7, 3.2))
    for drive in drives:
        rows = [r for r in table if r["drive"] == drive]
        ax.plot([r["diameter_m"] for r in rows], [r["speed_kp"] for r in rows], marker="o",
                label=f"{drive} speed_kp")
    ax.set_xlabel("roll diameter [m]")
    ax.set_ylabel("speed kp [N·m·s/m]")
    ax.set_yscale("log")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    caption = ("Tuned speed-loop proportional gain of each roll against its diameter, as the "
               "drive schedules it (J/(n r)); ki follows the same factor (gain_table.csv).")
    return Image("gain_schedule", caption, _png(fig))


def figures(result: TuneResult) -> list[Image]:
    """Every figure of the tune report."""
    out = [scenario_figure(result, s) for s in result.scenarios]
    schedule = schedule_figure(line_gain_table(result.tuned))
    return out + ([schedule] if schedule is not None else [])


def report_html(result: TuneResult, data: dict[str, Any], images: list[Image]) -> str:
    """The self-contained HTML report of a tune."""
    constraints = make_table(
        "constraints", "Constraints of the tuned line (worst over scenarios and roll points)",
        ("constraint", "before", "after", "limit", "holds after", "where (after)"),
        [(a.name, f"{b.value:.4g}", f"{a.value:.4g}", f"{a.sense} {a.limit:g}",
          "yes" if a.holds else "NO", a.where)
         for b, a in zip(result.before.constraints, result.after.constraints, strict=True)])
    free = make_table("free", "Tuned values (SI)", ("path", "before", "after", "low", "high"),
                      [(p.path, f"{result.before.values.get(p.path, math.nan):.4g}",
                        f"{result.after.values[p.path]:.4g}", f"{p.low:.4g}", f"{p.high:.4g}")
                       for p in result.free])
    gains = make_table("gains", "Gains written into tuned.toml (SI)", ("path", "before", "after"),
                       [(p, f"{result.gains_before.get(p, math.nan):.5g}", f"{v:.5g}")
                        for p, v in result.gains_after.items()])
    terms = make_table("terms", "Objective terms: RMS tension error / set tension",
                       ("scenario/span", "before", "after"),
                       [(k, f"{result.before.terms.get(k, math.nan):.4g}", f"{v:.4g}")
                        for k, v in result.after.terms.items()])
    r = result.robust
    over_draws = make_table(
        "robust", f"The same constraints on the {r.n} robustness draws (worst over the draws)",
        ("constraint", "worst", "limit", "draws missing it", "where"),
        [(c.name, f"{c.value:.4g}", f"{c.sense} {c.limit:g}",
          f"{r.missing.get(c.name, 0)} of {r.n}", c.where) for c in r.worst])
    robust = Text(f"Robustness: {r.passed} of {r.n} Monte Carlo draws met every constraint "
                  f"(required {r.required:.0%}): {'holds' if r.holds else 'FAILS'}. "
                  "Distributions: " + "; ".join(f"{p}: {d}" for p, d in r.distributions.items())
                  + ("" if not r.reasons else ". First failures: " + "; ".join(r.reasons)))
    sections = [Section("Objective", (Text(f"{OBJECTIVE}, over {', '.join(result.scenarios)}: "
                                           f"{result.before.objective:.4g} before, "
                                           f"{result.after.objective:.4g} after "
                                           f"({result.evaluations} candidates evaluated, "
                                           f"{result.seconds:.0f} s)."), terms)),
                Section("Constraints", (constraints, robust, over_draws)),
                Section("Tuned values", (free, gains)),
                Section("Figures", tuple(images)),
                *([Section("Notes", tuple(Text(n) for n in result.notes))] if result.notes
                  else [])]
    status = "ok" if result.holds else "failed"
    return render(f"webline tune: {result.line.name}", "controllers tuned on the line's "
                  "scenarios", result.summary(), status, sections,
                  f"webline {__version__}", headline="tuned" if result.holds else
                  "tuned, but not every constraint holds")
