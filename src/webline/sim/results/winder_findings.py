"""Verdict findings of the winder functions (docs/winder.md W5-W8): a web break, how and
when the monitor detected it, the stop and whether the driven rollers came to rest."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from webline.line import Line
from webline.sim.elements import layout as L
from webline.spec.winder import WebBreak
from webline.verdict import Finding

METHODS = {L.BREAK_TENSION: "tension below its threshold",
           L.BREAK_DANCER: "dancer at its end stop",
           L.BREAK_DIAMETER: "diameter calculated running the wrong way",
           L.BREAK_OVERSPEED: "overspeed of an open-loop roll at its speed limit"}

#: after the stop a driven roller is at rest below this fraction of the line speed at the
#: break (issue 21: 2 %; a roller held by a speed loop or a brake creeps at well under it)
REST_FRACTION = 0.02

HOLD_TEXT = {"zero_speed": "the drives holding zero speed", "brakes": "brakes set",
             "off": "torque off",
             "stall_tension": "the rolls holding their stall tension, the other drives zero "
                              "speed"}


@dataclass(frozen=True)
class AfterStop:
    """The driven rollers after a break's stop: ``peak`` [m/s] the largest surface speed of
    each after it, ``names`` theirs, ``settled`` [s] the time from which every one stayed
    below the rest limit (None: still above it at the end); ``loss`` [N] the largest
    tension lost by each intact zone after it (its tension at the stop less its least after
    it, by the zone's loadcell span)."""

    peak: np.ndarray
    names: list[str]
    settled: float | None
    loss: dict[str, float] = field(default_factory=dict)


#: (stop time [s], rest limit [m/s]) -> the driven rollers after the stop
AfterStopReader = Callable[[float, float], AfterStop]


def after_stop_from_records(time: np.ndarray, speed: np.ndarray, names: list[str],
                            tension: np.ndarray | None = None,
                            zones: Sequence[str] = ()) -> AfterStopReader:
    """``AfterStopReader`` of a run's records: times [s] and the driven rollers' surface
    speeds [m/s] (time x roller); ``tension`` [N] (time x zone) of the intact zones named
    ``zones`` (their loadcell spans)."""
    def read(stop: float, limit: float) -> AfterStop:
        after = time >= stop
        moving = np.abs(speed[after]).max(axis=1) >= limit
        t = time[after]
        settled = None if moving[-1] else float(t[np.flatnonzero(moving)[-1] + 1]
                                                 if moving.any() else t[0])
        return AfterStop(np.abs(speed[after]).max(axis=0), names, settled,
                         zone_losses(tension[after], zones) if tension is not None else {})
    return read


def intact_loadcells(plan: Any) -> list[int]:
    """The loadcell span of every tension zone of ``plan``'s line that no web break cuts."""
    broken = np.isfinite(plan.spans[:, L.S_BREAK])
    return [z.loadcell for z in plan.line.zones if not broken[z.first:z.last].any()]


def zone_losses(tension: np.ndarray, zones: Sequence[str]) -> dict[str, float]:
    """The largest tension [N] each zone (named by ``zones``, a column of ``tension``,
    records x zone from the stop on) lost after the stop: its first value less its least."""
    return {name: float(tension[0, z] - tension[:, z].min()) for z, name in enumerate(zones)}


def rest_limits(line: Line) -> list[tuple[float, float]]:
    """Each web break's (stop time [s] after its detection, rest limit [m/s] after the stop:
    ``REST_FRACTION`` x the line speed at the break), in the line file's order."""
    return [(b.stop_time, REST_FRACTION * _line_speed(line, b.at))
            for b in line.spec.disturbances if isinstance(b, WebBreak)]


def break_findings(line: Line, end: float, monitor: tuple[float, int],
                   after_stop: AfterStopReader | None = None) -> list[Finding]:
    """One finding per web break that happened within a run of ``line`` whose last record is
    at ``end`` [s] (the monitor's detection time [s] and method in ``monitor``): ``warning``
    when the monitor detected it (method, time to detect, the stop and whether the driven
    rollers came to rest after it, from ``after_stop``), ``failed`` when it did not."""
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
        details |= {"detected_s": detected, "time_to_detect_s": delay,
                    "method": METHODS[method], "stop_s": stop, "hold": b.hold}
        if end < stop:
            text = f"ramping to a stop by t = {stop:.4g} s (after the run)"
        elif after_stop is None:
            text = (f"ramped down by t = {stop:.4g} s, {HOLD_TEXT[b.hold]} (whether the "
                    f"driven rollers came to rest is not known without their speeds)")
        else:
            rest, text = _rest(after_stop, _line_speed(line, b.at), b.hold, stop)
            details |= rest
        found = (f"detected by {METHODS[method]} after {1000 * delay:.3g} ms" if delay >= 0.0
                 else f"but the monitor had already tripped by {METHODS[method]} at "
                 f"t = {detected:.4g} s, before it (a false alarm)")
        out.append(Finding("warning", "web_break", b.span,
                           f"web break in {b.span} at t = {b.at:.4g} s {found}; {text}",
                           b.at, details))
    return out


def _line_speed(line: Line, at: float) -> float:
    """The line-speed reference [m/s] at the break (the top speed if the line stood)."""
    from webline.profiles import breakpoints

    times, values = breakpoints(line.spec.speed)
    speed = abs(float(np.interp(at, times, values)))
    return speed if speed > 0.0 else float(np.abs(values).max())


def _rest(after_stop: AfterStopReader, line_speed: float, hold: str, stop: float
          ) -> tuple[dict[str, object], str]:
    """Details and words on the driven rollers after the stop."""
    limit = REST_FRACTION * line_speed
    state = after_stop(stop, limit)
    worst = int(np.argmax(state.peak))
    peak, name = float(state.peak[worst]), state.names[worst]
    details: dict[str, object] = {
        "largest_driven_speed_after_stop_m_per_s": peak, "fastest_after_stop": name,
        "rest_fraction": REST_FRACTION, "line_speed_m_per_s": line_speed,
        "at_rest_from_s": state.settled,
        "largest_tension_loss_after_stop_N": dict(state.loss)}
    share = peak / line_speed if line_speed > 0 else float("inf")
    lost = loss_text(state.loss)
    if peak < limit:
        return details, (f"stopped by t = {stop:.4g} s, {HOLD_TEXT[hold]}: every driven "
                         f"roller stayed below {REST_FRACTION:.0%} of line speed after it "
                         f"(largest {name}, {peak:.3g} m/s, {share:.2%}){lost}")
    since = ("still above it at the end" if state.settled is None
             else f"all below it from t = {state.settled:.4g} s on")
    return details, (f"ramped down by t = {stop:.4g} s, {HOLD_TEXT[hold]}, but did not come "
                     f"to rest: after it {name} turned at up to {peak:.3g} m/s "
                     f"({share:.1%} of line speed; rest is below {REST_FRACTION:.0%}), "
                     f"{since}{lost}")


def loss_text(loss: dict[str, float]) -> str:
    """Words on the intact zones' largest tension loss after the stop ('' without one)."""
    if not loss:
        return ""
    worst = max(loss, key=lambda name: loss[name])
    return (f"; the intact zones lost at most {loss[worst]:.3g} N of their tension after it "
            f"({worst})")
