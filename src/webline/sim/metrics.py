"""Per-run metrics of a study: one number per span, drive or node, as a sweep stores them.

The definitions are those of a single run's summary and verdict: tension error against the
loadcell reference (``Result.tension_ref``, NaN on spans without a loadcell), event times
from ``Result.events`` (``webline.sim.events``: intervals of records) and the verdict status
(``Result.verdict``). ``Result.metric_arrays`` computes them from a run; the batched kernel
(``webline.sim.batch``) reduces the same records to the same numbers inside compiled code.
"""

from __future__ import annotations

#: A tension is settled within this fraction of its reference [1]; ``settling_time`` is the
#: last recorded time [s] it was outside (0 if never; inf if still outside at the end).
SETTLE_BAND = 0.02

#: metric name -> (element dimension, units, description)
METRICS: dict[str, tuple[str, str, str]] = {
    "tension_rms_error": ("span", "N", "RMS of tension minus loadcell reference"),
    "tension_peak_error": ("span", "N", "largest |tension - loadcell reference|"),
    "tension_min": ("span", "N", "smallest tension"),
    "tension_max": ("span", "N", "largest tension"),
    "settling_time": ("span", "s",
                      f"last time |tension error| > {SETTLE_BAND:.0%} of the reference"),
    "slack_time": ("span", "s", "time the span was slack"),
    "torque_limit_time": ("drive", "s", "time the torque command sat at its limit"),
    "slip_time": ("node", "s", "time the web slipped over the roller"),
}
