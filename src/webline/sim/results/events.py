"""Events of a run, summarised per span and per drive (never one row per event).

An event is an interval of records in which a condition holds: a span is slack, a drive's
torque command sits at its limit, the web slips over a roller, a backlash gap is open, a
tension exceeds the line file's ``web.tension_limit``. An interval starts at the first record
where the condition holds and ends at the first record where it no longer does (or at the
last record), so durations are resolved to the record interval.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: a command within this fraction of its limit is at the limit: the controllers clip the
#: command to the limit exactly, so only rounding of the limit itself has to be absorbed
TORQUE_LIMIT_RTOL = 1e-6

#: what each kind of event is called in sentences, and the element it belongs to
KIND_TEXT = {
    "slack": "went slack",
    "torque_limit": "sat at its torque limit",
    "slip": "let the web slip",
    "backlash_open": "had its backlash gap open",
    "tension_limit": "exceeded the tension limit",
}


@dataclass(frozen=True)
class EventSummary:
    """The numbers of one kind of event on one element that a verdict's finding states:
    ``count`` intervals, the ``first`` start, ``total`` and ``longest`` time in the condition
    [s] over a run of ``duration`` [s]. A run's (``EventStats.summary``) and a study case's
    (its batch accumulators) give the same sentence for the same numbers."""

    kind: str
    where: str
    count: int
    first: float  #: [s]
    total: float  #: [s]
    longest: float  #: [s]
    duration: float  #: [s] of the run

    @property
    def fraction(self) -> float:
        """Share of the run spent in the condition (0..1)."""
        return self.total / self.duration if self.duration > 0 else 1.0

    def sentence(self) -> str:
        """One sentence, computed from the statistics."""
        times = "once" if self.count == 1 else f"{self.count} times"
        return (f"{self.where} {KIND_TEXT[self.kind]} {times}, first at t = {self.first:.4g} s, "
                f"{self.total:.3g} s in all ({self.fraction:.1%} of the run), longest "
                f"{self.longest:.3g} s")

    def as_dict(self) -> dict[str, object]:
        """Statistics [s] for JSON (the intervals themselves are left to the results file)."""
        return {"kind": self.kind, "where": self.where, "count": self.count,
                "first_s": self.first, "total_s": self.total, "longest_s": self.longest,
                "fraction": self.fraction}


@dataclass(frozen=True)
class EventStats:
    """Every interval of one kind of event on one element (span, drive or roller).

    ``intervals`` [s] is an (n, 2) array of start and end times; ``fraction`` is the total
    time over the run's duration.
    """

    kind: str
    where: str
    intervals: np.ndarray
    duration: float  #: [s] of the run

    @property
    def count(self) -> int:
        return int(self.intervals.shape[0])

    @property
    def first(self) -> float:
        """Start of the first interval [s]."""
        return float(self.intervals[0, 0])

    @property
    def total(self) -> float:
        """Time spent in the condition [s]."""
        return float(np.sum(self.intervals[:, 1] - self.intervals[:, 0]))

    @property
    def longest(self) -> float:
        """Longest interval [s]."""
        return float(np.max(self.intervals[:, 1] - self.intervals[:, 0]))

    @property
    def fraction(self) -> float:
        """Share of the run spent in the condition (0..1)."""
        return self.summary().fraction

    def summary(self) -> EventSummary:
        """The numbers a verdict states (``EventSummary``)."""
        return EventSummary(self.kind, self.where, self.count, self.first, self.total,
                            self.longest, self.duration)

    def sentence(self) -> str:
        """One sentence, computed from the statistics (``EventSummary.sentence``)."""
        return self.summary().sentence()

    def as_dict(self) -> dict[str, object]:
        """Statistics [s] for JSON (``EventSummary.as_dict``)."""
        return self.summary().as_dict()


def intervals(time: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Start and end times [s] of each run of True in ``mask`` over ``time`` [s], shape (n, 2);
    a run still open at the last record ends there."""
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return np.empty((0, 2))
    padded = np.concatenate(([False], mask, [False])).astype(np.int8)
    change = np.diff(padded)
    starts = np.flatnonzero(change == 1)
    ends = np.minimum(np.flatnonzero(change == -1), len(time) - 1)
    return np.column_stack((time[starts], time[ends]))


def event_stats(time: np.ndarray,
                conditions: list[tuple[str, list[str], np.ndarray]]) -> list[EventStats]:
    """Statistics of every (kind, element names, mask over time x elements) condition of a
    run recorded at ``time`` [s], for each element where the mask holds at least once, in the
    order given (vectorised over the records). ``Result.events`` lists the conditions."""
    duration = float(time[-1] - time[0]) if len(time) > 1 else 0.0
    out: list[EventStats] = []
    if len(time) == 0:
        return out
    for kind, names, masks in conditions:
        for j in np.flatnonzero(masks.any(axis=0)):
            out.append(EventStats(kind, names[j], intervals(time, masks[:, j]), duration))
    return out


@dataclass(frozen=True)
class SlackEvent:
    """A span went slack (no tension) from ``start`` to ``end`` [s] (``end`` None: still slack)."""

    span: str
    start: float
    end: float | None


def slack_intervals(time: np.ndarray, slack: np.ndarray, spans: list[str]) -> list[SlackEvent]:
    """Every interval in which a span carried no tension: ``slack`` (records x spans) true
    where it was slack, ``time`` [s] of the records, ``spans`` their names."""
    events = []
    for k, name in enumerate(spans):
        column = slack[:, k]
        edges = np.flatnonzero(np.diff(column.astype(np.int8)))
        starts = list(time[edges[column[edges + 1]] + 1])
        ends = list(time[edges[~column[edges + 1]] + 1])
        if column[0]:
            starts.insert(0, time[0])
        for j, start in enumerate(starts):
            events.append(SlackEvent(name, float(start),
                                     float(ends[j]) if j < len(ends) else None))
    return events

