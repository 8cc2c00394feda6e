"""One verdict for every run and analysis: ``ok``, ``warning``, ``unstable``, ``failed`` or
``interrupted``, with the findings it rests on.

This module is the bottom layer (it imports nothing of webline): the simulation, the analyses,
the CLI and the report build ``Finding``s from their numbers and share the ``Verdict``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Literal

Level = Literal["warning", "unstable", "failed", "interrupted"]
Status = Literal["ok", "warning", "unstable", "failed", "interrupted"]

#: severity of each level (``interrupted`` ranks like ``failed`` but keeps its own status)
RANK: dict[str, int] = {"ok": 0, "warning": 1, "unstable": 2, "failed": 3, "interrupted": 3}
#: failure kinds where the state ran away from the physical envelope: a dynamic instability,
#: so the exit status is 3 like ``unstable`` (README "Exit status")
RUNAWAY_KINDS = frozenset({"diverged", "nonfinite"})
#: findings named in full in a headline; the rest are counted
HEADLINE_FINDINGS = 2


@dataclass(frozen=True)
class Finding:
    """One fact behind a verdict.

    ``level``: how bad; ``kind``: what (``slack``, ``torque_limit``, ``slip``,
    ``backlash_open``, ``tension_limit``, ``yield``, ``layer_compressed``, ``unstable_mode``,
    ``diverged``, ``unwind_empty``, ``strength_exceeded``, ``nonfinite``, ``interrupted``);
    ``where``: the span, drive, roller or mode it concerns; ``message``: one sentence
    computed from the numbers; ``time`` [s]: when it first happened (None for a property of
    the line such as a mode); ``details``: the numbers themselves (SI), for JSON.
    """

    level: Level
    kind: str
    where: str
    message: str
    time: float | None = None
    details: dict[str, object] = field(default_factory=dict, compare=False, hash=False)

    def as_dict(self) -> dict[str, object]:
        """Plain data for JSON (non-finite floats become None)."""
        return {"level": self.level, "kind": self.kind, "where": self.where,
                "message": self.message, "time_s": _plain(self.time),
                "details": {k: _plain(v) for k, v in self.details.items()}}


@dataclass(frozen=True)
class Verdict:
    """The verdict of a run or analysis: ``status`` (the worst level among ``findings``, else
    ``ok``) and the findings, worst first, then in time order."""

    status: Status
    findings: tuple[Finding, ...] = ()

    @classmethod
    def of(cls, findings: Iterable[Finding]) -> Verdict:
        """The verdict that ``findings`` imply."""
        ordered = tuple(sorted(findings, key=_order))
        return cls(_worst(ordered), ordered)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def headline(self) -> str:
        """One line: the status and the most important findings."""
        if not self.findings:
            return "ok: no instability, failure or warning found"
        shown = [f.message for f in self.findings[:HEADLINE_FINDINGS]]
        rest = len(self.findings) - len(shown)
        more = f" (and {rest} more finding{'s' if rest > 1 else ''})" if rest else ""
        return f"{self.status}: " + "; ".join(m.rstrip(".") for m in shown) + more

    @property
    def exit_code(self) -> int:
        """0 ok or warning, 1 failed, 3 unstable or a runaway, 130 interrupted."""
        if self.status == "interrupted":
            return 130
        if self.status == "failed":
            runaway = any(f.kind in RUNAWAY_KINDS for f in self.findings if f.level == "failed")
            return 3 if runaway else 1
        return 3 if self.status == "unstable" else 0

    def of_level(self, level: str) -> tuple[Finding, ...]:
        """The findings of one level."""
        return tuple(f for f in self.findings if f.level == level)

    def as_dict(self) -> dict[str, object]:
        """Plain data for JSON: status, headline, exit code and every finding."""
        return {"status": self.status, "headline": self.headline, "exit_code": self.exit_code,
                "findings": [f.as_dict() for f in self.findings]}


def combine(*verdicts: Verdict) -> Verdict:
    """One verdict from several (a run and its linear analysis, the runs of a study)."""
    return Verdict.of(f for v in verdicts for f in v.findings)


def _worst(findings: Iterable[Finding]) -> Status:
    levels = {f.level for f in findings}
    if "failed" in levels:  # the failure says more than the interruption that may follow it
        return "failed"
    if "interrupted" in levels:
        return "interrupted"
    if "unstable" in levels:
        return "unstable"
    return "warning" if "warning" in levels else "ok"


def _order(finding: Finding) -> tuple[int, float, str]:
    time = math.inf if finding.time is None else finding.time
    return (-RANK[finding.level], time, finding.where)


def _plain(value: object) -> object:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value
