"""The verdict of a run: its failure, its events and the linear stability of its line."""

from __future__ import annotations

from typing import TYPE_CHECKING

from webline.sim.stability import stability_findings
from webline.verdict import Finding, Level, Verdict

if TYPE_CHECKING:
    from webline.sim.result import Result


def run_verdict(result: Result) -> Verdict:
    """``failed`` (or ``interrupted``) for a run that stopped early, ``unstable`` for a line
    with a growing closed-loop mode at ``analysis_time``, ``warning`` for each kind of event
    on each element (``webline.sim.events``), else ``ok``."""
    findings = []
    failure = result.failure
    if failure is not None:
        level: Level = "interrupted" if failure.kind == "interrupted" else "failed"
        findings.append(Finding(level, failure.kind, failure.where, failure.message,
                                failure.time, dict(failure.details)))
    findings += [Finding("warning", e.kind, e.where, e.sentence(), e.first, e.as_dict())
                 for e in result.events]
    findings += stability_findings(result.line)
    return Verdict.of(findings)
