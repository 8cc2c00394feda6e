"""Study ``slip-threshold``: how much wrap or friction each HSWL roller needs to hold the web,
across speeds and tensions, and what an idle roller that starts slipping does to the span
tensions (issue 6; thesis 5.12-5.13, 5.41-5.45).

1. Steady needs: at every operating point (``operating_point``) the product μα a roller
   needs is ln((T_high - t_c)/(T_low - t_c)) (``analysis.slip``); over speeds and zone
   tensions, with and without acceleration, and with a draw between zones.
2. Transient needs: the same check along a no-slip simulation of the HSWL speed change
   (compiled kernel), plus the slowly-varying ratio of (5.45).
3. Bearing failure on the idler, twice: in a standalone model of the rewind zone
   (``slip_chain``: process and rewind surface speeds held) and on the closed-loop HSWL
   (``webline.simulate`` with a ``roller_drag``); the idler's bearing drag rises, and the
   idler is adhered, held by the assumed wrap, or slipping on a 10° wrap.

Contact parameters: ``webline/data/slip/hswl_contact.toml`` (assumed; see its header).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

import webline
from webline.analysis import slip as an
from webline.line import Line, load_line
from webline.studies.output import pyplot, save
from webline.studies.result import StudyResult
from webline.studies.slip_chain import (
    Chain,
    Contact,
    Roller,
    Run,
    constant,
    initial_state,
    simulate_fixed,
    steady_state,
)
from webline.studies.slip_example import LBF, Analysis
from webline.units import ureg

FPM = float(ureg.Quantity(1.0, "ft/min").to("m/s").magnitude)


def _si(value: Any) -> float:
    if isinstance(value, str):
        return float(ureg.Quantity(value).to_base_units().magnitude)
    return float(value)


@dataclass(frozen=True)
class HswlContact:
    """Assumed contact of the HSWL rollers (SI): wraps [rad] by roller, μ0, μ', b [N·s/m],
    the bearing-failure case and the sweep grid."""

    wraps: dict[str, float]
    mu: float
    mu_k: float
    viscous: float
    failure_roller: str
    drag: float
    start: float
    rise: float
    small_wrap: float
    duration: float
    speeds: tuple[float, ...]
    tensions: tuple[float, ...]


def load_contact(name: str = "hswl_contact") -> HswlContact:
    """Read ``webline/data/slip/<name>.toml``."""
    d = tomllib.loads(resources.files("webline.data.slip").joinpath(f"{name}.toml").read_text())
    bf = d["bearing_failure"]
    return HswlContact(
        wraps={k: _si(v) for k, v in d["wrap"].items()}, mu=_si(d["friction"]["mu"]),
        mu_k=_si(d["friction"]["mu_kinetic"]), viscous=_si(d["friction"]["viscous"]),
        failure_roller=bf["roller"], drag=_si(bf["drag"]), start=_si(bf["start"]),
        rise=_si(bf["rise"]), small_wrap=_si(bf["small_wrap"]), duration=_si(bf["duration"]),
        speeds=tuple(_si(v) for v in d["sweep"]["speeds"]),
        tensions=tuple(_si(v) for v in d["sweep"]["tensions"]),
    )


def with_operation(line: Line, speed: float, tensions: dict[int, float]) -> Line:
    """The line at constant ``speed`` [m/s] with the loadcell spans' tension references [N]
    replaced (by span index)."""
    data = line.spec.model_dump(exclude_none=True)
    data["speed"] = speed
    for k, value in tensions.items():
        data["spans"][k]["tension"] = value
    return load_line(data)


def steady_needs(line: Line, c: HswlContact) -> list[dict[str, Any]]:
    """μα each roller needs at steady speed, over the speed x tension grid (every zone at
    the same tension), and while accelerating at the HSWL ramp rate (200 -> 1000 ft/min in
    5 s)."""
    rows = []
    loadcells = [z.loadcell for z in line.zones]
    accel = (1000 - 200) * FPM / 5.0
    for v in c.speeds:
        for tension in c.tensions:
            for a in (0.0, accel):
                run_line = with_operation(line, v, dict.fromkeys(loadcells, tension))
                if a:
                    profile = {"type": "ramp", "initial": max(v - a, 0.0), "final": v + a,
                               "start": 0.0, "duration": 2.0}
                    run_line = run_line.replace(speed=profile)
                op = webline.operating_point(run_line, 1.0)
                for need in an.operating_needs(run_line, op, c.wraps, c.mu):
                    rows.append({"speed_fpm": round(v / FPM), "tension_lbf": tension / LBF,
                                 "accel_m_s2": a, **need.as_row()})
    return rows


def draw_needs(line: Line, c: HswlContact, speed: float) -> list[dict[str, Any]]:
    """Zone 2 (process section) at a different tension from zones 1 and 3 (14.35 lbf): the
    master and process rollers must hold the difference."""
    rows = []
    base = line.spec.spans[line.zones[0].loadcell].tension
    assert isinstance(base, float)
    for ratio in (0.5, 0.75, 1.0, 1.5, 2.0, 3.0):
        run_line = with_operation(line, speed, {line.zones[1].loadcell: ratio * base})
        op = webline.operating_point(run_line)
        for need in an.operating_needs(run_line, op, c.wraps, c.mu):
            rows.append({"zone2_over_zone1": ratio, **need.as_row()})
    return rows


def transient_needs(line: Line, c: HswlContact, duration: float) -> tuple[dict[str, Any],
                                                                           webline.Result]:
    """Largest μα and (5.45) ratio along a no-slip simulation of the speed-change scenario."""
    result = webline.simulate(line.with_scenario("speed-change"), duration)
    needs = an.needs_along(result, c.wraps)
    ratios = an.slowly_varying_along(result, c.mu)
    row: dict[str, Any] = {}
    for name, values in needs.items():
        k = int(np.argmax(values))
        row[name] = {"max_mu_wrap": float(values[k]), "at_s": float(result.time[k]),
                     "min_mu_at_wrap": float(values[k] / c.wraps[name]),
                     "max_5_45_ratio": float(np.nanmax(ratios[name]))}
    return row, result


def rewind_zone(line: Line, c: HswlContact, contact: Contact | None) -> tuple[Chain, np.ndarray,
                                                                              np.ndarray]:
    """Standalone model of the HSWL rewind zone (process -> span3a -> idler -> span3b ->
    rewind) at the operating point, end speeds held; the idler's drag steps up."""
    op = webline.operating_point(line)
    i = line.spec.rollers.index(next(r for r in line.spec.rollers
                                     if r.name == c.failure_roller))
    idler = line.spec.rollers[i]
    drag, start, rise = c.drag, c.start, c.rise

    def extra_drag(t: float) -> float:
        return drag * min(max((t - start) / rise, 0.0), 1.0)

    chain = Chain(
        ea=line.ea, lengths=(line.spec.spans[i - 1].length, line.spec.spans[i].length),
        rollers=(Roller(speed=constant(float(op.speed[i - 1]))),
                 Roller(radius=idler.radius, inertia=idler.inertia,  # type: ignore[arg-type]
                        viscous=idler.friction,
                        drag=extra_drag, contact=contact),
                 Roller(speed=constant(float(op.speed[i + 1])))),
        tension_in=constant(float(op.tension[i - 2])),
    )
    y0 = initial_state(chain, op.tension[i - 1:i + 1], np.array([op.omega[i]]))
    y0, modes = steady_state(chain, 0.0, y0)
    return chain, y0, modes


def bearing_failure(line: Line, c: HswlContact, duration: float) -> dict[str, Run]:
    """The idler's drag steps up: adhered (no slip model), assumed wrap, 10° wrap."""
    rho_a = an.mass_per_length(line)
    cases = {
        "adhered": None,
        f"wrap {math.degrees(c.wraps[c.failure_roller]):.0f}°": Contact(
            c.wraps[c.failure_roller], c.mu, c.mu_k, c.viscous, rho_a),
        f"wrap {math.degrees(c.small_wrap):.0f}°": Contact(c.small_wrap, c.mu, c.mu_k,
                                                          c.viscous, rho_a),
    }
    out = {}
    for name, contact in cases.items():
        chain, y0, modes = rewind_zone(line, c, contact)
        out[name] = simulate_fixed(chain, y0, modes, duration, 1e-3)
    return out


def bearing_failure_line(line: Line, c: HswlContact, duration: float) -> list[dict[str, Any]]:
    """The same bearing failure on the closed-loop HSWL (compiled kernel, all its controllers
    acting): a ``roller_drag`` ramping to the drag, the idler adhered or on a traction contact
    with the assumed or the small wrap. One row per case: tension step across the idler,
    slip fraction, smallest slip power (>= 0) and web balance."""
    i = next(k for k, r in enumerate(line.spec.rollers) if r.name == c.failure_roller)
    drag = {"type": "roller_drag", "roller": c.failure_roller,
            "torque": {"type": "ramp", "initial": 0.0, "final": c.drag, "start": c.start,
                       "duration": c.rise}}
    rows = []
    cases = (("line, adhered", None), ("line, assumed wrap", c.wraps[c.failure_roller]),
             ("line, small wrap", c.small_wrap))
    for name, wrap in cases:
        data = line.spec.model_dump(exclude_none=True)
        data["disturbances"] = [drag]
        if wrap is not None:
            data["rollers"][i]["wrap"] = wrap
            data["rollers"][i]["contact"] = {"type": "traction", "friction": c.mu,
                                             "kinetic_friction": c.mu_k, "viscous": c.viscous}
        r = webline.simulate(load_line(data), duration)
        step = r.tension[:, i] - r.tension[:, i - 1]
        step -= step[0]
        balance = r.web_unwound - r.web_rewound - (r.web_stored - r.web_stored[0])
        rows.append({"case": name, "step_end_N": float(step[-1]),
                     "step_peak_N": float(step.max()),
                     "slip_fraction": float(r.slipping[:, i].mean()),
                     "min_slip_power_W": float(r.slip_power[:, i].min()),
                     "max_web_balance_m": float(np.abs(balance).max())})
    return rows


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Study ``slip-threshold``: three figures, the table of the worst steady need of each
    roller, and every table in ``slip_threshold.json`` (``analyse`` returns them all)."""
    return analyse(out_dir, quick=quick).study_result(out_dir, "worst_steady")


def analyse(out_dir: Path, *, quick: bool = False) -> Analysis:
    """Run the study, write its figures into ``out_dir`` and return its tables."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    line = load_line("hswl")
    c = load_contact()
    if quick:
        c = HswlContact(**{**c.__dict__, "speeds": c.speeds[::2], "tensions": c.tensions[::2],
                           "duration": 1.5})
    steady = steady_needs(line, c)
    draw = draw_needs(line, c, 500 * FPM)
    transient, result = transient_needs(line, c, 9.0 if quick else 20.0)
    failure = bearing_failure(line, c, c.duration)
    failure_line = bearing_failure_line(line, c, c.duration)

    worst: dict[str, dict[str, Any]] = {}
    for row in steady:
        name = row["roller"]
        if name not in worst or row["mu_wrap_rad"] > worst[name]["mu_wrap_rad"]:
            worst[name] = row
    failure_rows = []
    for name, r in failure.items():
        diff = r.tension[:, 1] - r.tension[:, 0]
        final = float(diff[-1])
        late = r.time >= c.start + c.rise
        outside = np.nonzero(late & (np.abs(diff - final) > 0.02 * abs(final)))[0]
        failure_rows.append({
            "case": name,
            "t3a_end_lbf": float(r.tension[-1, 0] / LBF),
            "t3b_end_lbf": float(r.tension[-1, 1] / LBF),
            "difference_end_N": final,
            "difference_peak_N": float(diff.max()),
            "settled_within_2pct_s": float(r.time[outside[-1]] - c.start) if len(outside)
            else 0.0,
            "idler_speed_deficit_fpm": float(-r.slip[-1, 1] / FPM) + 0.0,
            "slip_fraction": float(np.mean(r.state[:, 1])),
            "max_slip_power_W": float(r.power[:, 1].max()),
            "min_slip_power_W": float(r.power[:, 1].min()),
            "max_web_balance_m": float(np.abs(r.balance).max()),
        })
    figures = [_steady_figure(steady, draw, c, out_dir / "slip_threshold_steady.png"),
               _transient_figure(result, c, out_dir / "slip_threshold_transient.png"),
               _failure_figure(failure, c, out_dir / "slip_threshold_bearing.png")]
    idle = worst.get("idler", {})
    adhered, small = failure_rows[0], failure_rows[2]
    ratio_545 = max(v["max_5_45_ratio"] for v in transient.values())
    idler = line.spec.rollers[3]
    drag_over_r = (c.drag + idler.friction * float(webline.operating_point(line).omega[3])) \
        / idler.radius
    text = (
        "At steady speed with every zone at the same tension the driven rollers hold only the "
        "idler's drag and the idler only its bearing drag over its radius: at most mu*alpha = "
        f"{idle.get('mu_wrap_rad', float('nan')):.3g} rad over the grid, accelerating "
        "included (a wrap of a few degrees at mu = 0.25). A draw between zones is what needs "
        "wrap: zone 2 at twice zone 1 needs mu*alpha = ln 2 = 0.69 on the master and process "
        "rollers (159 deg at mu = 0.25). Along the speed change the largest need is "
        + ", ".join(f"{k} {v['max_mu_wrap']:.3g} rad" for k, v in transient.items())
        + f", and (5.45) holds with a ratio below {ratio_545:.2g}. "
        f"When the idler's bearing drag rises by {c.drag:.2g} N*m, the tension difference "
        f"across it tends to (drag + bearing viscous)/R = {drag_over_r:.2f} N whether it "
        "slips or not (its torque balance), so the span tensions end alike "
        f"(span 3a {adhered['t3a_end_lbf']:.3f} lbf adhered, {small['t3a_end_lbf']:.3f} lbf "
        "slipping). The adhered idler rings in its lightly damped idler-span mode (peak "
        f"difference {adhered['difference_peak_N']:.2f} N, within 2 % after "
        f"{adhered['settled_within_2pct_s']:.1f} s); on a 10 deg wrap it slips, caps the "
        f"difference (peak {small['difference_peak_N']:.2f} N, settled after "
        f"{small['settled_within_2pct_s']:.1f} s: the viscous slip damps the mode) and turns "
        f"{small['idler_speed_deficit_fpm']:.2f} ft/min slower than the web. "
        "On the closed-loop line (all controllers acting) the step across the idler ends at "
        + ", ".join(f"{x['step_end_N']:.2f} N ({x['case']}, slipping "
                    f"{x['slip_fraction']:.0%} of the time)" for x in failure_line) + "."
    )
    return Analysis(
        name="slip-threshold", figures=figures,
        tables={"worst_steady": list(worst.values()), "steady": steady, "draw": draw,
                "transient": [{"roller": k, **v} for k, v in transient.items()],
                "bearing_failure": failure_rows, "bearing_failure_line": failure_line},
        text=text, data={"worst": worst},
    )


def _steady_figure(steady: list[dict[str, Any]], draw: list[dict[str, Any]], c: HswlContact,
                   path: Path) -> Path:
    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    for tension in sorted({r["tension_lbf"] for r in steady}):
        rows = [r for r in steady if r["roller"] == "idler" and r["tension_lbf"] == tension
                and r["accel_m_s2"] > 0]
        ax1.plot([r["speed_fpm"] for r in rows], [r["mu_wrap_rad"] for r in rows], "o-",
                 label=f"{tension:.3g} lbf, accelerating")
    ax1.set_xlabel("line speed [ft/min]")
    ax1.set_ylabel("μα needed [rad]")
    ax1.set_title("idler: bearing drag and inertia over tension")
    ax1.legend(fontsize=8)
    for name in ("master", "process"):
        rows = [r for r in draw if r["roller"] == name]
        ax2.plot([r["zone2_over_zone1"] for r in rows], [r["min_mu_at_wrap"] for r in rows],
                 "o-", label=f"{name} (wrap {math.degrees(c.wraps[name]):.0f}°)")
    ax2.axhline(c.mu, color="k", lw=0.6, ls="--", label=f"assumed μ = {c.mu}")
    ax2.set_xlabel("zone 2 tension / zone 1 tension")
    ax2.set_ylabel("smallest μ that holds")
    ax2.set_title("driven rollers: draw between zones (500 ft/min)")
    ax2.legend(fontsize=8)
    return save(fig, path)


def _transient_figure(result: webline.Result, c: HswlContact, path: Path) -> Path:
    plt = pyplot()
    needs = an.needs_along(result, c.wraps)
    fig, ax = plt.subplots(figsize=(8, 3.5))
    for name, values in needs.items():
        ax.plot(result.time, values, label=name)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("μα needed [rad]")
    ax.set_title("needs along the HSWL speed change 200 -> 1000 ft/min (no-slip run)")
    ax.legend(fontsize=8)
    return save(fig, path)


def _failure_figure(failure: dict[str, Run], c: HswlContact, path: Path) -> Path:
    plt = pyplot()
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(13, 4))
    zoom = c.start + 2.5
    for (name, r), style in zip(failure.items(), ["-", "--", ":"], strict=False):
        near = r.time <= zoom
        ax1.plot(r.time[near], r.tension[near, 1] - r.tension[near, 0], style, label=name)
        ax2.plot(r.time, r.tension[:, 0] / LBF, style, label=f"span 3a, {name}")
        ax2.plot(r.time, r.tension[:, 1] / LBF, style, label=f"span 3b, {name}")
        ax3.plot(r.time[near], r.slip[near, 1] / FPM, style, label=name)
    ax1.set_xlabel("time [s]")
    ax1.set_ylabel("t3b - t3a [N]")
    ax1.set_title(f"across the idler: bearing drag +{c.drag:g} N·m")
    ax1.legend(fontsize=8)
    ax2.set_xlabel("time [s]")
    ax2.set_ylabel("tension [lbf]")
    ax2.set_title("span tensions (process and rewind speeds held)")
    ax2.legend(fontsize=6)
    ax3.set_xlabel("time [s]")
    ax3.set_ylabel("v_r - v [ft/min]")
    ax3.set_title("slip velocity at the idler")
    ax3.legend(fontsize=8)
    return save(fig, path)
