"""The verdict on a web break of a branched line (docs/branching.md, "Web breaks"; the
chain's docs/winder.md W5, W8): what the monitor found, when, and how the line stopped,
computed from the run's records."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.disturb import web_break
from webline.sim.branches.loop import layout as B
from webline.sim.results.winder_findings import loss_text, zone_losses
from webline.spec.branched.check import kind_of
from webline.spec.winder import WebBreak
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan

#: the verdict says "stopped" only where every driven roller stays below this fraction of
#: the line speed at the break after the stop ramp (the chain's W8 ``rest_fraction``)
REST_FRACTION = 0.02
_METHODS = {B.BREAK_TENSION: "tension below its threshold", B.BREAK_DIAMETER:
            "the calculated diameter running the wrong way",
            B.BREAK_OVERSPEED: "overspeed of an open-loop roll at its speed limit"}


def detection(plan: BranchPlan, istate: np.ndarray) -> dict[str, float]:
    """The monitor's record after a run with a break (empty without one): the time it found
    the break [s] (NaN: never), the method (``layout`` BREAK_*, 0: none) and where (the
    loadcell's span or the drive, -1: none)."""
    if not plan.offsets[B.O_BREAK]:
        return {}
    found = istate[0, B.I_DETECT] >= 0.0
    return {"break_detected_s": float(istate[0, B.I_DETECT]) if found else math.nan,
            "break_method": float(istate[0, B.I_METHOD]) if found else 0.0,
            "break_where": float(istate[0, B.I_WHERE]) if found else -1.0}


def intact(plan: BranchPlan, time: np.ndarray) -> np.ndarray:
    """Records x spans: False where the span is broken at that time [s]."""
    return time[:, None] < plan.sf[None, :, B.SF_BREAK]


def break_findings(plan: BranchPlan, time: np.ndarray, speed: np.ndarray,
                   settings: dict[str, float], tension: np.ndarray | None = None
                   ) -> list[Finding]:
    """The verdict on a web break (W5, W8), one finding per web or lane it cuts: where and
    when it broke, what found it (the loadcell's span or the drive) and after how long, the
    stop ramp's end and whether every driven roller then stayed below ``REST_FRACTION`` of
    the line speed at the break (else the fastest and its speed); a warning, or ``failed``
    where nothing found the break by the end of the run. None where the run ends before it.
    ``time`` [s] and ``speed`` [m/s] (records x nodes, surface speeds) are the run's,
    ``settings`` its ``detection``, ``tension`` [N] (records x spans) its span tensions:
    with them, the largest tension each intact zone lost after the stop (by its first
    loadcell span's name)."""
    line = plan.line
    item = web_break(line)
    if item is None or not len(time) or time[-1] < item.at:
        return []
    cut = np.isfinite(plan.sf[:, B.SF_BREAK])
    webs = sorted({line.spans[k].web for k in np.nonzero(cut)[0]})
    detected = settings.get("break_detected_s", math.nan)
    where = f"web break in {item.span} at t = {item.at:.4g} s"
    if not math.isfinite(detected):
        text = f"{where} not detected by the end of the run (t = {time[-1]:.4g} s)"
        return [Finding("failed", "web_break", line.spec.webs[w].name,
                        f"{text}; it cuts {_kind(plan, w)}", item.at) for w in webs]
    method = int(settings["break_method"])
    spot = int(settings["break_where"])
    by = (f"loadcell {line.spans[spot].name}" if method == B.BREAK_TENSION
          else f"drive {line.spec.rollers[line.drives[spot]].name}")
    stop = detected + item.stop_time
    details: dict[str, object] = {"span": item.span, "break_s": item.at, "detected_s": detected,
                                  "method": _METHODS[method], "by": by, "stop_s": stop}
    text = (f"{where} detected by {_METHODS[method]} ({by}) after "
            f"{1e3 * (detected - item.at):.3g} ms; ")
    after = time >= stop
    if not np.any(after):
        text += f"still ramping down at the end of the run (stop at t = {stop:.4g} s)"
    else:
        text += _after_stop(plan, time, speed, item, stop, after, details)
        if tension is not None:
            kept = [z for z in line.zones.values()
                    if z.loadcells and not cut[list(z.spans)].any()]  # the intact zones
            names = [line.spans[z.loadcells[0]].name for z in kept]
            columns = tension[after][:, [z.loadcells[0] for z in kept]]
            details["largest_tension_loss_after_stop_N"] = zone_losses(columns, names)
            text += loss_text(zone_losses(columns, names))
    return [Finding("warning", "web_break", line.spec.webs[w].name,
                    f"{text}; it cuts {_kind(plan, w)}", item.at, details) for w in webs]


def _after_stop(plan: BranchPlan, time: np.ndarray, speed: np.ndarray, item: WebBreak,
                stop: float, after: np.ndarray, details: dict[str, object]) -> str:
    """Words and numbers on the driven rollers after the stop ramp (W8)."""
    line = plan.line
    speed = np.abs(speed[:, list(line.drives)])
    rest = REST_FRACTION * abs(plan.profile(0, item.at))
    late = speed[after]
    fastest = int(np.argmax(np.max(late, axis=0)))
    peak = float(np.max(late))
    name = line.spec.rollers[line.drives[fastest]].name
    moving = np.nonzero(np.any(speed > rest, axis=1) & after)[0]
    details.update({"largest_driven_speed_after_stop_m_per_s": peak,
                    "fastest_after_stop": name, "rest_m_per_s": rest})
    hold = {"zero_speed": "holding zero speed", "off": "with their torque off",
            "brakes": "with their torque off and brakes set",
            "stall_tension": "holding zero speed, the rolls their stall tension"}[item.hold]
    if not len(moving):
        return (f"stopped by t = {stop:.4g} s, the drives {hold}: every driven roller "
                f"stayed below {100 * REST_FRACTION:.3g}% of line speed after it (largest "
                f"{name}, {peak:.3g} m/s)")
    last = int(moving[-1])
    calm = (f"all below it from t = {time[last + 1]:.4g} s on"
            if last + 1 < len(time) else "never all below it")
    details["at_rest_from_s"] = float(time[last + 1]) if last + 1 < len(
        time) else math.nan
    return (f"ramped down by t = {stop:.4g} s, the drives {hold}, but did not come to rest: "
            f"after it {name} turned at up to {peak:.3g} m/s (rest is below "
            f"{100 * REST_FRACTION:.3g}% of line speed), {calm}")


def _kind(plan: BranchPlan, w: int) -> str:
    """'lane lane_1 (lane_1_span)': the web or lane and its spans the break cuts."""
    line = plan.line
    web = line.spec.webs[w]
    spans = [s.name for s in line.spans if s.web == w and math.isfinite(
        plan.sf[s.index, B.SF_BREAK])]
    return f"{kind_of(web)} {web.name} ({', '.join(spans)})"


def without_cut_jump(plan: BranchPlan, time: np.ndarray, balance: np.ndarray,
                     w: int) -> np.ndarray:
    """Web ``w``'s length balance [m] over ``time`` [s] without its jump at the break: the
    cut spans' stretch let go (L ε, the frozen span counting L), which is no drift. The
    balance is conserved on either side (``sim.branches.loop.breaks.web_flows``)."""
    at = plan.sf[plan.line.web_spans(w), B.SF_BREAK]
    if not np.any(np.isfinite(at)):
        return balance
    i = int(np.searchsorted(time, np.min(at)))
    out = balance.copy()
    if 0 < i < len(out):
        out[i:] -= out[i] - out[i - 1]
    return out


def stop_factor(plan: BranchPlan, time: np.ndarray, settings: dict[str, float]) -> np.ndarray:
    """The factor [-] on the line-speed reference at ``time`` [s]: 1, and after a detected
    break the stop ramp, 1 - (t - t_detected) / stop time down to 0 (``loop.breaks``)."""
    detected = settings.get("break_detected_s", math.nan)
    if not math.isfinite(detected):
        return np.ones(len(time))
    return np.clip(1.0 - (time - detected) / plan.df[0, B.D_BSTOP], 0.0, 1.0)
