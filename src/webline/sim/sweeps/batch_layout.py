"""Where each accumulator of a batch case sits in its row (``webline.sim.sweeps.batch``): the span
metrics, the events, the time and number of records, the winder-state slots and the web
breaks' rollers after the stop (``webline.sim.sweeps.batch_states``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from webline.sim.sweeps.batch_states import SLOT_COLS, n_slots, stop_stride

# accumulator layout per case: blocks of per-element columns (``Accumulators``)
(A_SUMSQ, A_PEAK, A_TMIN, A_TMAX, A_SETTLE, A_LASTOUT) = range(6)  # per span
SPAN_BLOCKS = 6
# events: each element has total time, first time, the start of an open interval, the count
# of intervals and the longest (what a verdict's finding states: ``events.EventSummary``)
EV_TOTAL, EV_FIRST, EV_OPEN, EV_COUNT, EV_LONGEST = range(5)
EV_BLOCKS = 5


@dataclass(frozen=True)
class Layout:
    """Where each accumulator sits in a case's row (all counts per line structure)."""

    n_spans: int
    n_drives: int
    n_nodes: int
    n_breaks: int = 0

    @property
    def n_events(self) -> int:
        """Event elements: slack and tension limit per span, torque limit and backlash per
        drive, slip per node."""
        return 2 * self.n_spans + 2 * self.n_drives + self.n_nodes

    @property
    def event_base(self) -> int:
        return SPAN_BLOCKS * self.n_spans

    @property
    def end_column(self) -> int:
        """The time of the last record [s] (then the number of records, the last column)."""
        return self.event_base + EV_BLOCKS * self.n_events

    @property
    def state_base(self) -> int:
        """The first column of the winder-state slots (``batch_states``), after the time of
        the last record and the number of records."""
        return self.end_column + 2

    @property
    def n_slots(self) -> int:
        return n_slots(self.n_nodes, self.n_drives)

    @property
    def stop_base(self) -> int:
        """The first column of the web breaks' rollers after the stop (``batch_states``)."""
        return self.state_base + SLOT_COLS * self.n_slots

    @property
    def stop_stride(self) -> int:
        """Columns per web break after the stop: each driven roller's largest speed, the
        time all settled, then each span's tension at the stop and its least after it."""
        return stop_stride(self.n_drives, self.n_spans)

    @property
    def width(self) -> int:
        return self.stop_base + self.n_breaks * self.stop_stride

    def stop_columns(self, acc: np.ndarray) -> None:
        """Start values of every break's columns in ``acc`` (cases x columns): speeds 0, the
        settled time NaN (not yet), the tension at the stop NaN (none yet), its least +inf."""
        d, s = self.n_drives, self.n_spans
        for j in range(self.n_breaks):
            b = self.stop_base + j * self.stop_stride
            acc[:, b + d:b + d + 1 + s] = math.nan
            acc[:, b + d + 1 + s:b + d + 1 + 2 * s] = math.inf

    def event_slices(self) -> dict[str, tuple[int, int]]:
        """(first element, count) of each kind of event among the event elements."""
        s, d, n = self.n_spans, self.n_drives, self.n_nodes
        return {"slack": (0, s), "tension_limit": (s, s), "torque_limit": (2 * s, d),
                "backlash_open": (2 * s + d, d), "slip": (2 * s + 2 * d, n)}
