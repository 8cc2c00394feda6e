"""Study ``tension-observer``: the HSWL with the process zone's loadcell replaced by a section
observer (thesis Sec. 6.4, first item of future work; ``webline.sim.drives.observer``).

Decentralized state feedback on every drive (webline's LQ design), the disturbances and noise of
``hswl-controllers`` (wound-in ripple 1 lbf at 1 Hz, eccentric idler, 0.05 lbf / 0.5 ft/min
noise), 500 and 1500 ft/min. The process drive feeds back span 2's tension from (a) its
loadcell, (b) the observer, (c, d) the observer with EA 20 % high / low. Measured over the
second half of each run: the observer's estimation error (the observer replayed on the
recorded states, every tick, with the loop's noise), and the RMS tension error of every zone.
The thesis proposes the observer but gives no numbers: there is no thesis figure to compare.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import webline
from webline.control.select import with_controller
from webline.line import Line, load_line
from webline.sim.core.plan import compile_plan
from webline.sim.drives.controllers import drive_inertia
from webline.sim.drives.observer import observe
from webline.sim.elements import layout as L
from webline.sim.elements.signals import gaussian
from webline.studies.hswl_controllers import disturbances
from webline.studies.output import finish, pyplot, save
from webline.studies.result import StudyResult

SPEEDS_FPM = (500.0, 1500.0)
DRIVE = "process"  #: the drive whose loadcell is removed (zone: span2 only)
CASES = {"loadcell": None, "observer": 1.0, "observer, EA +20 %": 1.2,
         "observer, EA -20 %": 0.8}
DURATION, QUICK_DURATION = 40.0, 6.0  #: [s]; metrics over the second half


def case_line(base: Line, fpm: float, ea_factor: float | None) -> Line:
    """``base`` at ``fpm`` with state feedback, the study's disturbances, and the process
    drive on its observer (EA x ``ea_factor``) unless ``ea_factor`` is None."""
    over: dict[str, dict[str, object]] = {}
    if ea_factor is not None:
        over[DRIVE] = {"tension_feedback": "observer", "observer_ea": ea_factor * base.ea}
    line = with_controller(base.replace(speed=f"{fpm} ft/min"), "state_feedback", overrides=over)
    return line.replace(disturbances=disturbances())


def replay(line: Line, result: webline.Result, ea_factor: float = 1.0,
           initial_error: float = 0.0) -> np.ndarray:
    """The observer's estimate T̂ [N] of the process drive's span at every record (records
    must be every tick), run on the recorded states with the loop's speed noise, started
    ``initial_error`` [N] off the equilibrium tension."""
    data = line.spec.model_dump(exclude_none=True)
    for r in data["rollers"]:
        if r["name"] == DRIVE:
            r["controller"] |= {"tension_feedback": "observer", "observer_ea": ea_factor * line.ea}
    plan = compile_plan(load_line(data))
    d = [line.node_name(i) for i in line.drives].index(DRIVE)
    i = line.drives[d]
    _, istate = plan.initial_state(plan.op)
    istate[d, L.I_THAT] += initial_error
    ns, ds, off = plan.node_structure, plan.drive_structure, plan.offsets
    span_ref = plan.op.tension.copy()
    seed, noise = int(plan.web[L.W_SEED]), plan.web[L.W_NOISE_V]
    out = np.empty(len(result.time))
    for m, (t, x) in enumerate(zip(result.time, result.states, strict=True)):
        tick = round(t / plan.dt)
        radius = plan.nodes[i, L.N_RADIUS]
        v = radius * x[off[L.O_OMEGA] + i]
        if off[L.O_NOISE] and noise > 0.0:
            v += noise * gaussian(seed, tick, 2 * d)
        inertia = drive_inertia(d, i, radius, ns, ds, plan.nodes, plan.drives, plan.web)
        out[m] = observe(d, i, plan.dt, tick, radius, inertia, v / radius, x, istate, ds, off,
                         plan.nodes, plan.drives, plan.web, span_ref)
    return out


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Run every case at both speeds; figure of the estimate against the truth, table, summary."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    base = load_line("hswl")
    duration = QUICK_DURATION if quick else DURATION
    rows: list[dict[str, object]] = []
    traces = {}
    for fpm in SPEEDS_FPM:
        for name, factor in CASES.items():
            line = case_line(base, fpm, factor)
            result = webline.simulate(line, duration,
                                      record_interval=1.0 / line.spec.control.sample_rate)
            window = result.time >= duration / 2
            k = [z.loadcell for z in line.zones]
            err = (result.tension - result.tension_ref)[window][:, k]
            span = line.zones[line.controlled_zone(line.drives[2])].loadcell  # type: ignore[index]
            estimate = replay(line, result, factor if factor is not None else 1.0)
            est_err = (estimate - result.tension[:, span])[window]
            row: dict[str, object] = {"speed_fpm": fpm, "case": name,
                                      "verdict": result.verdict.status,
                                      "estimation_rms_N": float(np.sqrt(np.mean(est_err**2))),
                                      "estimation_mean_N": float(np.mean(est_err))}
            for z, kk in zip(line.zones, k, strict=True):
                row[f"rms_error_{line.span_name(z.loadcell)}_N"] = float(
                    np.sqrt(np.mean(err[:, k.index(kk)] ** 2)))
            rows.append(row)
            traces[(fpm, name)] = (result.time, result.tension[:, span], estimate)
    figure = _figure(traces, out_dir / "tension_observer.png")
    return finish("tension-observer", out_dir, [figure], rows, _summary(rows, duration))


def _summary(rows: list[dict[str, object]], duration: float) -> str:
    lines = [f"HSWL, state feedback, {duration:g} s per run (metrics over the second half); "
             f"the {DRIVE} drive's span-2 tension from its loadcell or from the observer."]
    for fpm in SPEEDS_FPM:
        at = {str(r["case"]): r for r in rows if r["speed_fpm"] == fpm}
        lc = float(at["loadcell"]["rms_error_span2_N"])  # type: ignore[arg-type]
        ob = float(at["observer"]["rms_error_span2_N"])  # type: ignore[arg-type]
        change = "lower" if ob < lc else "higher"
        lines.append(
            f"{fpm:.0f} ft/min: span-2 RMS tension error {lc:.4f} N with the loadcell, {ob:.4f} N "
            f"with the observer ({change}); observer estimation error RMS "
            f"{float(at['observer']['estimation_rms_N']):.3f} N (mean "  # type: ignore[arg-type]
            f"{float(at['observer']['estimation_mean_N']):+.3f} N); with EA +20 % / -20 %: "  # type: ignore[arg-type]
            f"estimation mean {float(at['observer, EA +20 %']['estimation_mean_N']):+.3f} / "  # type: ignore[arg-type]
            f"{float(at['observer, EA -20 %']['estimation_mean_N']):+.3f} N, span-2 RMS error "  # type: ignore[arg-type]
            f"{float(at['observer, EA +20 %']['rms_error_span2_N']):.3f} / "  # type: ignore[arg-type]
            f"{float(at['observer, EA -20 %']['rms_error_span2_N']):.3f} N.")  # type: ignore[arg-type]
    lines.append("The thesis proposes the observer (Sec. 6.4) without results: no thesis number "
                 "to compare.")
    return "\n".join(lines)


def _figure(traces: dict, path: Path) -> Path:
    plt = pyplot()
    fig, axes = plt.subplots(len(SPEEDS_FPM), 1, figsize=(7, 2.4 * len(SPEEDS_FPM)))
    for ax, fpm in zip(np.atleast_1d(axes), SPEEDS_FPM, strict=True):
        t, true, est = traces[(fpm, "observer")]
        ax.plot(t, true, lw=0.6, label="span 2 tension (true)")
        ax.plot(t, est, lw=0.6, label="observer estimate")
        ax.set_ylabel("[N]")
        ax.set_title(f"{fpm:.0f} ft/min, process drive on the observer", fontsize=9)
        ax.legend(fontsize=7)
    np.atleast_1d(axes)[-1].set_xlabel("time [s]")
    return save(fig, path)
