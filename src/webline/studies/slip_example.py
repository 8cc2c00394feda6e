"""Study ``slip-example``: the free span of thesis Sec. 5.8 (Table 5.1, Figs 5.16-5.17).

Roller 1 (no slip) feeds span 2 (tension t2), which leaves over roller 2 where the web may
slip into span 3, whose tension t3 is prescribed. Both rollers step from 1000 to 1001 ft/min
at t = 0. Three cases as in Fig. 5.17 — no slip, slip on roller 2, slip plus a 2 Hz
disturbance t3 = 42 + 5 sin(4πt) lbf — each computed twice:

- *as printed*: (5.47) applied whatever the sign, started from Table 5.1's t2(0-) = 42 lbf,
  which is an equilibrium of none of the models (the thesis's curves);
- *webline*: the general-sign traction law with stiction (``physics.slip``), each case started
  from the equilibrium of its own model at 1000 ft/min.

Plus a web without stiction (μ0 = μ') whose upstream response to the downstream disturbance
is measured as friction grows, and a check of the fixed-step path against the event-located
reference. Parameters: ``webline/data/slip/free_span_sec5_8.toml``.
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Literal

import numpy as np

from webline.physics import slip as sl
from webline.studies.output import pyplot, save, write_text
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
from webline.studies.slip_events import simulate_events
from webline.units import ureg

DATA_PACKAGE = "webline.data.slip"
LBF = float(ureg.Quantity(1.0, "lbf").to("N").magnitude)
FPM = float(ureg.Quantity(1.0, "ft/min").to("m/s").magnitude)
Slip = Literal["none", "webline", "printed"]


@dataclass(frozen=True)
class Analysis:
    """Everything a slip study computed: figure files, named tables (rows of plain values,
    units in the column names), a short text of findings and extra data."""

    name: str
    figures: list[Path]
    tables: dict[str, list[dict[str, Any]]]
    text: str
    data: dict[str, Any] = field(default_factory=dict)

    def study_result(self, out_dir: Path, main: str) -> StudyResult:
        """The registry's ``StudyResult``: table ``main``, the text; every table is also
        written to ``<name>.json`` in ``out_dir``."""
        path = Path(out_dir) / f"{self.name.replace('-', '_')}.json"
        write_text(path, json.dumps({"summary": self.text, "tables": self.tables}, indent=1,
                                    default=float))
        return StudyResult(self.name, tuple(self.figures), self.tables[main], self.text)


@dataclass(frozen=True)
class FreeSpan:
    """Parameters of Sec. 5.8 in SI (see the data file for sources and assumptions)."""

    ea: float
    mass_per_length: float
    length: float
    wrap: float
    mu: float
    mu_k: float
    viscous: float
    radius: float
    t1: float
    t2_initial: float
    t3: float
    speed_before: float
    speed_after: float
    step_rollers: str
    amplitude: float
    frequency: float
    duration: float
    step: float
    start: str

    def contact(self, law: Literal["webline", "printed"] = "webline", *,
                mu: float | None = None, mu_k: float | None = None,
                centrifugal: bool = True) -> Contact:
        return Contact(self.wrap, self.mu if mu is None else mu,
                       self.mu_k if mu_k is None else mu_k, self.viscous,
                       self.mass_per_length if centrifugal else 0.0, law)


def _si(value: Any) -> float:
    if isinstance(value, str):
        return float(ureg.Quantity(value).to_base_units().magnitude)
    return float(value)


def load_free_span(name: str = "free_span_sec5_8") -> FreeSpan:
    """Read ``webline/data/slip/<name>.toml`` into SI parameters."""
    text = resources.files(DATA_PACKAGE).joinpath(f"{name}.toml").read_text()
    d = tomllib.loads(text)
    op, r2 = d["operation"], d["roller2"]
    return FreeSpan(
        ea=_si(d["web"]["ea"]), mass_per_length=_si(d["web"]["mass_per_length"]),
        length=_si(d["span"]["length"]), wrap=_si(r2["wrap"]), mu=_si(r2["mu"]),
        mu_k=_si(r2["mu_kinetic"]), viscous=_si(r2["viscous"]), radius=_si(r2["radius"]),
        t1=_si(op["t1"]), t2_initial=_si(op["t2_initial"]), t3=_si(op["t3"]),
        speed_before=_si(op["speed_before"]), speed_after=_si(op["speed_after"]),
        step_rollers=op["step_rollers"], amplitude=_si(d["disturbance"]["amplitude"]),
        frequency=_si(d["disturbance"]["frequency"]), duration=_si(d["run"]["duration"]),
        step=_si(d["run"]["step"]), start=d["run"]["start"],
    )


def free_span_chain(p: FreeSpan, *, slip: Slip, disturbance: bool, after_step: bool = True,
                    mu: float | None = None, mu_k: float | None = None,
                    centrifugal: bool = True) -> Chain:
    """The chain roller 1 -> span 2 -> roller 2 of Fig. 5.16 with speeds after (or before)
    the step; ``slip`` selects roller 2's contact law."""
    v = p.speed_after if after_step else p.speed_before
    v1 = v if p.step_rollers == "both" else p.speed_before
    contact = None if slip == "none" else p.contact(slip, mu=mu, mu_k=mu_k,
                                                     centrifugal=centrifugal)
    omega = 2.0 * math.pi * p.frequency
    t3 = p.t3
    amp = p.amplitude

    def t3_signal(t: float) -> float:
        return t3 + amp * math.sin(omega * t)

    return Chain(
        ea=p.ea, lengths=(p.length,),
        rollers=(Roller(speed=constant(v1)), Roller(speed=constant(v), contact=contact)),
        tension_in=constant(p.t1),
        tension_out=t3_signal if disturbance else constant(t3),
    )


def start(p: FreeSpan, *, slip: Slip, how: str, mu: float | None = None,
          mu_k: float | None = None, centrifugal: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Initial state and stick/slip modes: the equilibrium of the case's own model at the
    pre-step speed and mean t3 (``how="equilibrium"``), or Table 5.1's t2(0-)
    (``how="table"``; stuck if inside the stiction band, else slipping)."""
    before = free_span_chain(p, slip=slip, disturbance=False, after_step=False, mu=mu,
                             mu_k=mu_k, centrifugal=centrifugal)
    y0 = initial_state(before, np.array([p.t2_initial]))
    if how == "equilibrium":
        return steady_state(before, 0.0, y0)
    modes = np.zeros(2, dtype=int)
    c = before.rollers[1].contact
    if c is not None and c.law == "webline":
        t_c = sl.centrifugal_tension(c.mass_per_length, p.speed_before)
        modes[1] = sl.slip_state(p.t2_initial, p.t3, c.wrap, c.mu, c.mu_k, t_c, 0)
    return y0, modes


def run_case(p: FreeSpan, *, slip: Slip, disturbance: bool, how: str | None = None,
             duration: float | None = None, dt: float | None = None, mu: float | None = None,
             mu_k: float | None = None, centrifugal: bool = True,
             reference: bool = False) -> Run:
    """One case of Fig. 5.17 by fixed-step RK4 (or the event-located ``reference``)."""
    how = how or p.start
    duration = p.duration if duration is None else duration
    dt = p.step if dt is None else dt
    chain = free_span_chain(p, slip=slip, disturbance=disturbance, mu=mu, mu_k=mu_k,
                            centrifugal=centrifugal)
    y0, modes = start(p, slip=slip, how=how, mu=mu, mu_k=mu_k, centrifugal=centrifugal)
    if reference:
        t_eval = np.linspace(0.0, duration, round(duration / dt) + 1)
        return simulate_events(chain, y0, modes, duration, t_eval)
    return simulate_fixed(chain, y0, modes, duration, dt)


def response_amplitude(run: Run, period: float) -> float:
    """Peak-to-peak of t2 [N] over the last two periods of the disturbance."""
    keep = run.time >= run.time[-1] - 2.0 * period
    t2 = run.tension[keep, 0]
    return float(t2.max() - t2.min())


def friction_sweep(p: FreeSpan, mus: list[float], duration: float) -> list[dict[str, float]]:
    """No stiction (μ0 = μ' = mu): peak-to-peak of the upstream tension t2 [lbf] under the 2 Hz
    downstream disturbance, for each friction coefficient, from each one's equilibrium."""
    rows = []
    for mu in mus:
        run = run_case(p, slip="webline", disturbance=True, how="equilibrium",
                       duration=duration, mu=mu, mu_k=mu)
        rows.append({"mu": mu, "t2_peak_to_peak_lbf": response_amplitude(run, 1 / p.frequency)
                     / LBF, "slip_fraction": float(np.mean(np.abs(run.slip[:, 1]) > 0.0))})
    return rows


def threshold_friction(p: FreeSpan) -> float:
    """Smallest μ (μ0 = μ') for which roller 2 never slips under the disturbance, with t2 at
    its stuck equilibrium t1·v1/v2-adjusted value: the capstan must hold t3's extremes."""
    t2 = p.t1  # stuck equilibrium with equal roller speeds (E-6.5)
    t_c = sl.centrifugal_tension(p.mass_per_length, p.speed_after)
    worst = max(abs(math.log((p.t3 + s * p.amplitude - t_c) / (t2 - t_c))) for s in (-1, 1))
    return worst / p.wrap


def _row(name: str, run: Run, p: FreeSpan) -> dict[str, Any]:
    t2 = run.tension[:, 0] / LBF
    return {
        "case": name,
        "t2_start_lbf": round(float(t2[0]), 4),
        "t2_end_lbf": round(float(t2[-1]), 4),
        "t2_min_lbf": round(float(t2.min()), 4),
        "t2_max_lbf": round(float(t2.max()), 4),
        "slip_fraction": round(float(np.mean(np.abs(run.slip[:, 1]) > 0.0)), 4),
        "switches": int(run.switches[1]) if len(run.switch_times) > 1 else 0,
        "min_slip_power_W": float(run.power[:, 1].min()),
        "max_web_balance_m": float(np.abs(run.balance).max()),
    }


def run(out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Study ``slip-example``: figure ``slip_example.png``, the table of cases, and every
    table in ``slip_example.json`` (``analyse`` returns them all)."""
    return analyse(out_dir, quick=quick).study_result(out_dir, "cases")


def analyse(out_dir: Path, *, quick: bool = False) -> Analysis:
    """Run the study, write ``slip_example.png`` into ``out_dir`` and return its tables."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    p = load_free_span()
    duration = 1.0 if quick else p.duration
    printed = {
        "no slip": run_case(p, slip="none", disturbance=False, how="table", duration=duration),
        "slip (5.47)": run_case(p, slip="printed", disturbance=False, how="table",
                                duration=duration),
        "slip (5.47) + 2 Hz t3": run_case(p, slip="printed", disturbance=True, how="table",
                                          duration=duration),
    }
    ours = {
        "no slip": run_case(p, slip="none", disturbance=False, duration=duration),
        "slip": run_case(p, slip="webline", disturbance=False, duration=duration),
        "slip + 2 Hz t3": run_case(p, slip="webline", disturbance=True, duration=duration),
        "no stiction (μ0 = μ' = 0.02) + 2 Hz t3": run_case(
            p, slip="webline", disturbance=True, duration=duration, mu=p.mu_k, mu_k=p.mu_k),
    }
    reference = run_case(p, slip="webline", disturbance=True, duration=duration,
                         reference=True)
    fine = run_case(p, slip="webline", disturbance=True, duration=duration, dt=p.step / 4)
    fixed = ours["slip + 2 Hz t3"]
    mus = [0.01, 0.02, 0.05, 0.1] if quick else [0.005, 0.01, 0.02, 0.04, 0.06, 0.08, 0.1,
                                                 0.11, 0.15]
    sweep = friction_sweep(p, mus, duration)
    mu_free = threshold_friction(p)

    rows = [_row(f"as printed: {k}", v, p) for k, v in printed.items()]
    rows += [_row(f"webline: {k}", v, p) for k, v in ours.items()]
    check = {
        "max |t2 fixed 1 ms - events| [lbf]":
            float(np.abs(fixed.tension[:, 0] - reference.tension[:, 0]).max() / LBF),
        "max |t2 fixed 0.25 ms - events| [lbf]": float(np.abs(
            fine.tension[::4, 0] - reference.tension[:, 0]).max() / LBF),
        "switches fixed 1 ms": int(fixed.switches[1]),
        "switches fixed 0.25 ms": int(fine.switches[1]),
        "switches events": int(reference.switches[1]),
        "max switch-time difference [ms]": _switch_shift(fixed, reference) * 1e3,
    }
    figure = _figure(p, printed, ours, out_dir / "slip_example.png")
    t_c = sl.centrifugal_tension(p.mass_per_length, p.speed_after)
    fs_back = sl.stiction_limit(p.t1, p.wrap, p.mu, t_c, -1.0)
    text = (
        f"Table 5.1's t2(0-) = {p.t2_initial / LBF:.0f} lbf is not an equilibrium of (5.46): "
        f"with no slip the span relaxes to t1 = {p.t1 / LBF:.0f} lbf (time constant L/v = "
        f"{p.length / p.speed_before:.2f} s), and the printed (5.47) has its own equilibrium at "
        f"{printed['slip (5.47)'].tension[-1, 0] / LBF:.3f} lbf; the thesis's 'variations "
        "without disturbance' are this relaxation. webline starts each case at its own "
        "equilibrium. With stiction, roller 2 holds the 2 lbf difference t3 - t2 (its "
        f"stiction band backwards is {fs_back / LBF:.2f} lbf at t2 = 40 lbf), so the step "
        "leaves t2 unchanged, and the 2 Hz disturbance makes it slip only near the peaks of "
        f"t3 (slip fraction {_row('', fixed, p)['slip_fraction']:.3f}); the roller stops "
        f"slipping for mu >= {mu_free:.4f} (mu0 = mu'), where the upstream response is zero. "
        "The printed (5.47) dissipates negative power in "
        f"{np.mean(printed['slip (5.47) + 2 Hz t3'].power[:, 1] < 0):.0%} of the samples."
    )
    return Analysis(
        name="slip-example",
        figures=[figure],
        tables={"cases": rows, "friction_sweep": sweep, "fixed_step_check": [check]},
        text=text,
        data={"threshold_mu": mu_free},
    )


def _switch_shift(a: Run, b: Run) -> float:
    ta, tb = a.switch_times[1], b.switch_times[1]
    if len(ta) != len(tb) or not ta:
        return math.nan
    return float(np.max(np.abs(np.array(ta) - np.array(tb))))


def _figure(p: FreeSpan, printed: dict[str, Run], ours: dict[str, Run], path: Path) -> Path:
    plt = pyplot()

    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    panels = (("(a) as printed: (5.47), start t2 = 42 lbf (Table 5.1)", printed),
              ("(b) webline: general sign + stiction, start at equilibrium", ours))
    for ax, (title, runs) in zip(axes[0], panels, strict=True):
        for (name, r), style in zip(runs.items(), ["--", "-", ":", "-."], strict=False):
            ax.plot(r.time, r.tension[:, 0] / LBF, style, label=name)
        ax.set_title(title)
        ax.set_ylabel("t2 [lbf]")
        ax.legend(fontsize=8)
    ax = axes[1, 0]
    r = printed["slip (5.47) + 2 Hz t3"]
    ax.plot(r.time, r.slip[:, 1] / FPM, ":", label="as printed + 2 Hz")
    for name in ("slip + 2 Hz t3", "no stiction (μ0 = μ' = 0.02) + 2 Hz t3"):
        r = ours[name]
        ax.plot(r.time, r.slip[:, 1] / FPM, label=f"webline: {name}")
    ax.set_title("(c) slip velocity v_r2 - v2 at roller 2")
    ax.set_ylabel("[ft/min]")
    ax.set_xlabel("time [s]")
    ax.legend(fontsize=8)
    ax = axes[1, 1]
    r = printed["slip (5.47) + 2 Hz t3"]
    ax.plot(r.time, r.power[:, 1], ":", label="as printed + 2 Hz")
    r = ours["slip + 2 Hz t3"]
    ax.plot(r.time, r.power[:, 1], label="webline + 2 Hz")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_title("(d) power dissipated by slip at roller 2 (second law: >= 0)")
    ax.set_ylabel("[W]")
    ax.set_xlabel("time [s]")
    ax.legend(fontsize=8)
    return save(fig, path)


__all__ = ["Analysis", "FreeSpan", "analyse", "free_span_chain", "load_free_span", "run",
           "run_case"]
