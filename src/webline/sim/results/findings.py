"""The verdict of a run: its failure, its events, its web breaks and the linear stability of
its line. One function (``run_verdict``) for a single run (``Result.verdict``) and for each
case of a study (``sweep_dataset.case_verdict``), so a case is never judged otherwise than
its run."""

from __future__ import annotations

from collections.abc import Sequence

from webline.sim.core.plan import Plan
from webline.sim.linear.stability import stability_findings
from webline.sim.results.events import EventSummary
from webline.sim.results.failure import Failure
from webline.sim.results.winder_findings import AfterStopReader, break_findings
from webline.verdict import Finding, Level, Verdict


def run_verdict(plan: Plan, failure: Failure | None, events: Sequence[EventSummary],
                end: float, monitor: tuple[float, int],
                after_stop: AfterStopReader | None = None,
                extra: Sequence[Finding] = ()) -> Verdict:
    """The verdict of a run of ``plan`` whose last record is at ``end`` [s]: ``failed`` (or
    ``interrupted``) for a run that stopped early and for a web break nothing detected,
    ``unstable`` for a line with a growing closed-loop mode at ``analysis_time``,
    ``warning`` for each kind of event on each element (``webline.sim.results.events``) and each
    detected web break, else ``ok``. ``monitor``: the break monitor's detection time [s]
    (-1: none) and method; ``after_stop``: the driven rollers' speeds after a break's stop
    (``winder_findings.AfterStopReader``; None where they were not kept); ``extra``: findings
    that need the run's records (a splice that slackens the web, the winder states)."""
    findings = []
    if failure is not None:
        level: Level = "interrupted" if failure.kind == "interrupted" else "failed"
        findings.append(Finding(level, failure.kind, failure.where, failure.message,
                                failure.time, dict(failure.details)))
    findings += [Finding("warning", e.kind, e.where, e.sentence(), e.first, e.as_dict())
                 for e in events]
    findings += stability_findings(plan.line, plan=plan)
    findings += break_findings(plan.line, end, monitor, after_stop)
    findings += extra
    return Verdict.of(findings)
