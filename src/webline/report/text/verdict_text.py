"""The verdict in words and tables: terminal lines, the report's events table and headline."""

from __future__ import annotations

from collections.abc import Sequence

from webline.report.text.html import Text
from webline.report.text.tables import Table, make_table
from webline.sim.results.events import EventStats
from webline.verdict import Verdict

#: CSS class of the report's headline box for each status
STATUS_CLASS = {"ok": "ok", "warning": "warning", "unstable": "failed", "failed": "failed",
                "interrupted": "interrupted"}


def verdict_lines(verdict: Verdict, quiet: bool = False) -> list[str]:
    """The headline, then one indented line per finding when there are several; with
    ``quiet`` only the headline, and nothing for ok."""
    if quiet:
        return [] if verdict.ok else [f"verdict: {verdict.headline}"]
    lines = [f"verdict: {verdict.headline}"]
    if len(verdict.findings) > 1:
        lines += [f"  {f.level} {f.kind} [{f.where}]: {f.message}" for f in verdict.findings]
    return lines


def events_table(events: Sequence[EventStats]) -> Table:
    """One row per kind of event and element: count, first time, total and longest time [s],
    share of the run."""
    rows = [[e.kind, e.where, str(e.count), f"{e.first:.4g}", f"{e.total:.4g}",
             f"{e.longest:.4g}", f"{e.fraction:.1%}"] for e in events]
    return make_table("events", "Events (per span and drive)",
                      ["event", "where", "count", "first [s]", "total [s]", "longest [s]",
                       "share of run"], rows)


def events_parts(events: Sequence[EventStats]) -> list[Table | Text]:
    """The events table of any run, or a line saying there were none."""
    if events:
        return [events_table(events)]
    return [Text("No events: the web never went slack, no drive sat at its torque limit, no "
                 "web slipped, no backlash gap opened.")]
