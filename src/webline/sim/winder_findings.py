"""Verdict findings of the winder functions (docs/winder.md W5): a web break, how and when
the monitor detected it, and the stop."""

from __future__ import annotations

import math
from collections.abc import Callable

from webline.line import Line
from webline.sim import layout as L
from webline.spec.winder import WebBreak
from webline.verdict import Finding

METHODS = {L.BREAK_TENSION: "tension below its threshold",
           L.BREAK_DANCER: "dancer at its end stop",
           L.BREAK_DIAMETER: "diameter calculated running the wrong way"}


def break_findings(line: Line, end: float, monitor: tuple[float, int],
                   largest_speed_after: Callable[[float], float] | None = None,
                   ) -> list[Finding]:
    """One finding per web break that happened within a run of ``line`` whose last record is
    at ``end`` [s] (the monitor's detection time [s] and method in ``monitor``): ``warning``
    when the monitor detected it (method, time to detect, the stop), ``failed`` when it did
    not. ``largest_speed_after(t)``: the largest web speed [m/s] recorded from ``t`` on (the
    details' residual speed after the stop; NaN without it)."""
    out = []
    detected, method = monitor
    for b in line.spec.disturbances:
        if not isinstance(b, WebBreak) or b.at > end:
            continue
        details: dict[str, object] = {"break_s": b.at, "span": b.span}
        if detected < 0.0:
            out.append(Finding("failed", "web_break", b.span,
                               f"the web broke in {b.span} at t = {b.at:.4g} s and the "
                               f"monitor did not detect it by the end, t = {end:.4g} s",
                               b.at, details))
            continue
        delay = detected - b.at
        stop = detected + b.stop_time
        stopped_in_run = end >= stop
        residual = (largest_speed_after(stop) if stopped_in_run and largest_speed_after
                    else math.nan)
        details |= {"detected_s": detected, "time_to_detect_s": delay,
                    "method": METHODS[method], "stop_s": stop,
                    "largest_speed_after_stop_m_per_s": residual}
        stopped = (f"ramped to a stop by t = {stop:.4g} s, torque off" if stopped_in_run
                   else f"ramping to a stop by t = {stop:.4g} s (after the run)")
        found = (f"detected by {METHODS[method]} after {1000 * delay:.3g} ms" if delay >= 0.0
                 else f"but the monitor had already tripped by {METHODS[method]} at "
                 f"t = {detected:.4g} s, before it (a false alarm)")
        out.append(Finding("warning", "web_break", b.span,
                           f"web break in {b.span} at t = {b.at:.4g} s {found}; {stopped}",
                           b.at, details))
    return out
