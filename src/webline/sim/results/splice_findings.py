"""What a run's flying splices did to the web (docs/winder.md, S4): the splice's instant, the
tension disturbance in the spliced roll's zone, and a verdict finding where a splice
slackens the web."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from webline.line import Line
from webline.sim.elements.splice import splice_tick, splices
from webline.spec.splice import FlyingSplice
from webline.spec.winder import WebBreak
from webline.verdict import Finding


@dataclass(frozen=True)
class SpliceWindow:
    """A splice as it ran: the splice, its instant [s] (the first controller tick at or after
    ``splice.at``), the end of the time it is answerable for [s] (the next splice, a web
    break or the end of the run) and the spans of the roll's tension zone."""

    splice: FlyingSplice
    time: float
    until: float
    spans: tuple[int, ...]


def splice_windows(line: Line, dt: float, end: float) -> list[SpliceWindow]:
    """The splices of a run of ``line`` (controller period ``dt`` [s]) that happened by
    ``end`` [s], in time order."""
    items = sorted(splices(line), key=lambda s: s.at)
    stops = [s.at for s in items] + [d.at for d in line.spec.disturbances
                                      if isinstance(d, WebBreak)] + [end]
    out = []
    for item in items:
        time = splice_tick(item.at, dt) * dt
        if time > end:
            continue
        until = min((t for t in stops if t > item.at), default=end)
        k = 0 if item.roll == line.node_name(0) else line.n_spans - 1
        spans = tuple(line.zones[line.zone_of_span(k)].spans)
        out.append(SpliceWindow(item, time, max(until, time), spans))
    return out


def splice_findings(line: Line, dt: float, time: np.ndarray,
                    tension: np.ndarray) -> list[Finding]:
    """A ``warning`` ``splice_slack`` for each splice after which a span of the spliced roll's
    zone went slack (tension <= 0 N) before the splice's window ends: where (the span), when
    (first slack record [s]) and how long (the records' time slack, summed [s]). ``time``
    [s] and ``tension`` [N] (records x spans) are the run's records."""
    out: list[Finding] = []
    if len(time) < 2:
        return out
    step = np.diff(time, append=time[-1])
    for window in splice_windows(line, dt, float(time[-1])):
        inside = (time >= window.time) & (time <= window.until)
        for k in window.spans:
            slack = inside & (tension[:, k] <= 0.0)
            if not slack.any():
                continue
            first = float(time[np.argmax(slack)])
            duration = float(step[slack].sum())
            span = line.span_name(k)
            roll = window.splice.roll
            out.append(Finding(
                "warning", "splice_slack", span,
                f"the flying splice of {roll} at t = {window.time:.4g} s slackened {span}: "
                f"slack from t = {first:.4g} s, {1000 * duration:.4g} ms in all",
                first, {"roll": roll, "splice_s": window.time, "first_slack_s": first,
                        "slack_duration_s": duration,
                        "speed_mismatch": window.splice.speed_mismatch,
                        "slack_m": window.splice.slack}))
    return out
