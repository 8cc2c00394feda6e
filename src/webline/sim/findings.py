"""The verdict of a run: its failure, its events and the linear stability of its line."""

from __future__ import annotations

from collections.abc import Sequence

from webline.line import Line
from webline.sim.events import EventStats
from webline.sim.failure import Failure
from webline.sim.plan import Plan
from webline.sim.stability import stability_findings
from webline.verdict import Finding, Level, Verdict


def run_verdict(failure: Failure | None, events: Sequence[EventStats], line: Line,
                plan: Plan, extra: Sequence[Finding] = ()) -> Verdict:
    """``failed`` (or ``interrupted``) for a run that stopped early, ``unstable`` for a line
    with a growing closed-loop mode at ``analysis_time``, ``warning`` for each kind of event
    on each element (``webline.sim.events``), else ``ok``."""
    findings = []
    if failure is not None:
        level: Level = "interrupted" if failure.kind == "interrupted" else "failed"
        findings.append(Finding(level, failure.kind, failure.where, failure.message,
                                failure.time, dict(failure.details)))
    findings += [Finding("warning", e.kind, e.where, e.sentence(), e.first, e.as_dict())
                 for e in events]
    findings += stability_findings(line, plan=plan)
    findings += extra  # e.g. a web break and its detection (``sim.winder_findings``)
    return Verdict.of(findings)
