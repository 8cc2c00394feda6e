"""Figures of a branched line's run (docs/branching.md): the schematic, tensions per web and
lane against their references, the layers of each laminate, surface speeds, roll and lane
radii, motor torques against their limits, and each wound roll's stresses. Each figure comes
with a caption computed from the numbers it draws (``branch_figure_jobs``)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from webline.report.plots.branch_schematic import WEB_COLORS, branch_schematic
from webline.report.plots.figures import FigureJob, ReportFigure
from webline.report.plots.frame import framed_figure
from webline.report.plots.mpl_text import legend_label, literal
from webline.report.plots.wound_roll import wound_roll_caption, wound_roll_figure
from webline.report.text.branch_tables import (
    SI,
    force_label,
    junction_kind,
    shaft_lanes,
    small_length,
    span_display,
)
from webline.report.text.display import Display, number_text
from webline.sim.branches.findings.break_verdict import stop_factor
from webline.sim.branches.loop import layout as B
from webline.sim.branches.result import BranchResult
from webline.sim.results.decimate import envelope
from webline.sim.results.wound_roll import WoundRoll


def _plot(ax: Axes, time: np.ndarray, values: np.ndarray, *fmt: str, **style: object) -> list:
    """Plot a signal at screen resolution: the min/max envelope of its pixel columns
    (``sim.results.decimate.envelope``), so peaks stay visible in long runs."""
    return ax.plot(*envelope(time, values), *fmt, **style)  # type: ignore[arg-type]


def references(result: BranchResult) -> dict[int, np.ndarray]:
    """Span number -> its loadcell's tension reference [N] at every record."""
    return {int(k): profile_values(result, int(p)) for k, p, *_ in result.plan.cells}


def profile_values(result: BranchResult, p: int) -> np.ndarray:
    """The plan's reference profile ``p`` (0: the line speed [m/s]; a loadcell's tension [N])
    at every record: what ``plan.profile(p, t)`` interpolates; the line speed ramping to a
    stop after a detected web break as the drives had it (``break_verdict.stop_factor``)."""
    plan = result.plan
    off = plan.prof_off
    values = np.interp(result.time, plan.prof_t[off[p]:off[p + 1]],
                       plan.prof_v[off[p]:off[p + 1]])
    return values * stop_factor(plan, result.time, result.settings) if p == 0 else values


def largest_deviation(result: BranchResult) -> tuple[float, str, float]:
    """The largest |tension - reference| [N] over every loadcell span and record, the span's
    name and the time [s] it occurs; (nan, '', nan) for a run without loadcells or records."""
    tension = result.dataset["tension"].values
    best = (float("nan"), "", float("nan"))
    for k, ref in references(result).items():
        error = np.abs(tension[:, k] - ref)
        i = int(np.argmax(error)) if len(error) else -1
        if i >= 0 and not error[i] <= best[0]:
            best = (float(error[i]), result.plan.line.spans[k].name, float(result.time[i]))
    return best


def deviation_text(result: BranchResult, display: Display) -> str:
    """'12.3 N in film_zone at t = 2.1 s' of ``largest_deviation`` in ``display``'s units (per
    width: of that span's web); '' without one."""
    error, span, when = largest_deviation(result)
    if not span:
        return ""
    line = result.plan.line
    k = [s.name for s in line.spans].index(span)
    return (f"{span_display(display, line, k).text(error, 'force')} in {span} at "
            f"t = {number_text(when)} s")


def web_width(result: BranchResult, web: str) -> float:
    """The width [m] of web or lane ``web`` (a laminate's: its narrowest layer's)."""
    line = result.plan.line
    return line.materials[[w.name for w in line.spec.webs].index(web)].width


def tensions_figure(result: BranchResult, display: Display = SI) -> Figure:
    """One axes per web (raw web, laminate, lane): the tension [N] of each of its spans
    against time [s], loadcell spans' references dotted (a laminate's layers: ``layers_figure``).
    Each axes' title gives its span tensions' range over the run."""
    ds = result.dataset
    refs = references(result)
    webs = list(ds["web"].values)
    fig = framed_figure(8.0, 1.0 + 1.9 * len(webs), rows=len(webs))
    axes = np.atleast_1d(fig.subplots(len(webs), 1, sharex=True))
    t = ds["time"].values
    names = list(ds["span"].values)
    for ax, web in zip(axes, webs, strict=True):
        shown = display.at_width(web_width(result, str(web)))  # (per width: its own)
        f = shown.factor("force")
        spans = ds["tension"].sel(span=ds["span_web"] == web)
        for name in spans["span"].values:
            line = _plot(ax, t, f * spans.sel(span=name).values, label=legend_label(str(name)))
            k = names.index(name)
            if k in refs:
                _plot(ax, t, f * refs[k], ":", color=line[0].get_color(),
                        label=legend_label(f"{name} reference"))
        low, high = f * float(spans.values.min()), f * float(spans.values.max())
        ax.set_title(literal(f"{web}: span tensions {low:.4g} to {high:.4g} "
                             f"{shown.unit('force')}"), fontsize=9,
                     color=WEB_COLORS[webs.index(web) % len(WEB_COLORS)])  # its schematic colour
        ax.set_ylabel(shown.label("tension", "force"))
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return fig


def tensions_caption(result: BranchResult, display: Display = SI) -> str:
    deviation = deviation_text(result, display)
    text = "Tension of every span, one panel per web and lane; loadcell references dotted."
    if display.per_width:
        text += " Tensions per width of their own web or lane."
    if deviation:
        text += f" Largest deviation from a reference: {deviation}."
    return text + "".join(f" {sentence}." for sentence in shaft_sums(result, display))


def shaft_sums(result: BranchResult, display: Display = SI) -> list[str]:
    """Per drive that controls the sum of several lanes' tensions (lanes on one shaft): that
    sum's largest deviation from the sum of their references [N], and each lane's range."""
    line = result.plan.line
    tension = result.dataset["tension"].values
    refs = references(result)
    out = []
    for zone in line.zones.values():
        if len(zone.loadcells) < 2:
            continue
        cells = list(zone.loadcells)
        error = np.abs(tension[:, cells].sum(axis=1) - sum(refs[k] for k in cells))
        lanes = ", ".join(
            f"{line.spans[k].name} {number_text(shown.value(tension[:, k].min(), 'force'))} "
            f"to {shown.text(tension[:, k].max(), 'force')}"
            for k in cells for shown in [span_display(display, line, k)])  # (its own width)
        # the sum per width of the lanes together (their widths add on the shaft)
        together = display.at_width(sum(line.materials[line.spans[k].web].width
                                        for k in cells))
        f, unit = together.factor("force"), together.unit("force")
        out.append(f"{line.spec.rollers[zone.node].name} holds the sum of "
                   f"{' + '.join(line.spans[k].name for k in cells)} within "
                   f"{number_text(f * float(error.max()) if len(error) else float('nan'))} "
                   f"{unit} of its reference; the lanes themselves: {lanes}")
    return out


def layers_figure(result: BranchResult, display: Display = SI) -> Figure:
    """Per laminate span: each layer's tension [N] and the laminate's (their sum)."""
    ds = result.dataset
    spans = list(dict.fromkeys(str(n).split("/")[0] for n in ds["layer_span"].values))
    fig = framed_figure(8.0, 1.0 + 1.9 * len(spans), rows=len(spans))
    axes = np.atleast_1d(fig.subplots(len(spans), 1, sharex=True))
    t = ds["time"].values
    line = result.plan.line
    for ax, span in zip(axes, spans, strict=True):
        k = [s.name for s in line.spans].index(span)
        f = span_display(display, line, k).factor("force")  # (per width: the laminate's)
        _plot(ax, t, f * ds["tension"].sel(span=span).values, color="#333333",
                label=legend_label(f"{span} (laminate)"))
        for name in ds["layer_span"].values:
            if str(name).split("/")[0] == span:
                layer = str(name).split("/")[1]
                f = display.at_width(web_width(result, layer)).factor("force")  # (its own)
                _plot(ax, t, f * ds["layer_tension"].sel(layer_span=name).values,
                        label=legend_label(f"layer {layer}"))
        ax.set_title(literal(f"{span}: layer tensions (bonded at the nip)"), fontsize=9)
        ax.set_ylabel(force_label(display, "tension"))
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return fig


def layers_caption(result: BranchResult, display: Display = SI) -> str:
    ds = result.dataset
    parts = []
    for name in ds["layer_span"].values:
        shown = display.at_width(web_width(result, str(name).split("/")[1]))  # (its own)
        values = ds["layer_tension"].sel(layer_span=name).values
        parts.append(f"{name} {number_text(shown.value(values.min(), 'force'))} to "
                     f"{shown.text(values.max(), 'force')}")
    how = "its own law at the strain it was bonded with at the nip plus the laminate's draw"
    return f"Each layer's tension in a laminate span, {how}: " + ", ".join(parts) + "."


def speeds_figure(result: BranchResult, display: Display = SI) -> Figure:
    """Surface speed [m/s] of every roller (a shaft: the lane its drive measures)."""
    ds = result.dataset
    fig = framed_figure(8.0, 3.4)
    ax = fig.subplots()
    f = display.factor("speed")
    for name in ds["node"].values:
        _plot(ax, ds["time"].values, f * ds["speed"].sel(node=name).values,
              label=legend_label(str(name)))
    _plot(ax, ds["time"].values, f * profile_values(result, 0), ":", color="black",
          label="line speed reference")
    ax.set_ylabel(display.label("surface speed", "speed"))
    ax.set_xlabel("time [s]")
    ax.legend(fontsize=7, loc="best", ncol=2)
    ax.grid(alpha=0.3)
    return fig


def speeds_caption(result: BranchResult, display: Display = SI) -> str:
    f, unit = display.factor("speed"), display.unit("speed")
    speed = f * result.dataset["speed"].values
    final = speed[-1]
    master = result.plan.line.master
    error = np.abs(speed[:, master] - f * profile_values(result, 0))
    scale = float(np.max(np.abs(speed))) if speed.size else 0.0

    def shown(v: float) -> str:  # round-off of a roller at rest (1e-16 m/s) shown as 0
        return number_text(0.0 if abs(v) < 1e-9 * scale else float(v))

    return (f"Surface speed of every roller against the line speed reference (dotted): "
            f"{shown(speed.min())} to {shown(speed.max())} {unit} over the run; at "
            f"the end they span {shown(final.min())} to {shown(final.max())} {unit}. "
            f"The master {result.plan.line.spec.rollers[master].name} follows the reference "
            f"within {number_text(float(error.max()) if len(error) else float('nan'))} {unit}.")


def radii_figure(result: BranchResult, display: Display = SI) -> Figure:
    """Wound radius [mm] of every roll and lane, one panel per roll node."""
    ds = result.dataset
    nodes = list(dict.fromkeys(str(n).split("/")[0] for n in ds["roll"].values))
    fig = framed_figure(8.0, 1.0 + 1.7 * len(nodes), rows=len(nodes))
    axes = np.atleast_1d(fig.subplots(len(nodes), 1, sharex=True))
    webs = list(ds["web"].values)
    small, unit = small_length(display)
    for ax, node in zip(axes, nodes, strict=True):
        for name in ds["roll"].values:
            if str(name).split("/")[0] == node:
                web = str(name).split("/")[1]
                _plot(ax, ds["time"].values, small * ds["radius"].sel(roll=name).values,
                        color=WEB_COLORS[webs.index(web) % len(WEB_COLORS)],
                        label=legend_label(web))
        ax.set_title(literal(node), fontsize=9)
        ax.set_ylabel(f"radius [{unit}]")
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return fig


def radii_caption(result: BranchResult, display: Display = SI) -> str:
    ds = result.dataset
    small, unit = small_length(display)
    parts = [f"{name} {number_text(small * ds['radius'].sel(roll=name).values[0])} → "
             f"{number_text(small * ds['radius'].sel(roll=name).values[-1])} {unit}"
             for name in ds["roll"].values]
    text = "Wound radius of every roll and lane (start → end): " + ", ".join(parts) + "."
    line = result.plan.line
    radius = ds["radius"].values
    for node in dict.fromkeys(r.node for r in line.rolls):  # lanes on one shaft drift apart
        rolls = [j for j, r in enumerate(line.rolls) if r.node == node]
        if len(rolls) > 1:
            spread = small * (radius[-1, rolls].max() - radius[-1, rolls].min())
            text += (f" The lanes on {line.spec.rollers[node].name} end "
                     f"{number_text(spread, 3)} {unit} apart.")
    return text


def torques_figure(result: BranchResult, display: Display = SI) -> Figure:
    """Motor torque [N·m] of every drive with its limits ± (dashed), one panel per drive."""
    ds = result.dataset
    drives = list(ds["drive"].values)
    f, unit = display.factor("torque"), display.unit("torque")
    limits = f * result.plan.df[:, B.D_LIMIT]
    fig = framed_figure(8.0, 1.0 + 1.6 * len(drives), rows=len(drives))
    axes = np.atleast_1d(fig.subplots(len(drives), 1, sharex=True))
    t = ds["time"].values
    for ax, name, limit in zip(axes, drives, limits, strict=True):
        _plot(ax, t, f * ds["torque"].sel(drive=name).values, label="torque")
        ax.axhline(limit, color="#d62728", ls="--", lw=1, label="limit")
        ax.axhline(-limit, color="#d62728", ls="--", lw=1)
        peak = f * float(np.max(np.abs(ds["torque"].sel(drive=name).values)))
        ax.set_title(literal(f"{name}: largest |torque| {peak:.4g} of {limit:.4g} {unit} "
                             f"({100 * peak / limit:.3g} % of its limit)"), fontsize=9)
        ax.set_ylabel(display.label("torque", "torque"))
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return fig


def torques_caption(result: BranchResult, display: Display = SI) -> str:
    ds = result.dataset
    f, unit = display.factor("torque"), display.unit("torque")
    limits = f * result.plan.df[:, B.D_LIMIT]
    peak = f * np.max(np.abs(ds["torque"].values), axis=0)
    share = peak / limits
    d = int(np.argmax(share))
    parts = [f"{name} {number_text(p)} {unit} of {number_text(lim)}"
             for name, p, lim in zip(ds["drive"].values, peak, limits, strict=True)]
    return ("Motor torque of every drive against its limit (dashed); largest |torque|: "
            + ", ".join(parts) + f". Closest to its limit: {ds['drive'].values[d]} at "
            f"{number_text(100 * share[d], 3)} %.")


def schematic_caption(result: BranchResult) -> str:
    """The schematic's caption: its webs, junctions and shafts, named from the topology."""
    line = result.plan.line
    junctions = [f"{junction_kind(line, i)} at {line.spec.rollers[i].name}"
                 for i in sorted(line.junctions)]
    shafts = [f"{' and '.join(line.spec.webs[w].name for w in webs)} on one shaft at "
              f"{line.spec.rollers[node].name}" for node, webs in shaft_lanes(line).items()]
    return ("The line as its webs run, one colour per web ("
            + ", ".join(w.name for w in line.spec.webs) + "); "
            + "; ".join([*junctions, *shafts, "loadcells marked with their references"]) + ".")


def _marked(fig: Figure, result: BranchResult) -> Figure:
    """Where a run stopped early, a red dotted line at its last record on every axes of a
    time plot ``fig``."""
    if result.failure is not None and len(result.time):
        for ax in fig.axes:
            ax.axvline(float(result.time[-1]), color="#d62728", ls=":", lw=1.2)
    return fig


def branch_figure_jobs(result: BranchResult, display: Display = SI) -> list[FigureJob]:
    """The jobs that draw every figure of a branched run's report, in report order, its
    numbers in ``display``'s units ('si' or 'imperial')."""
    def one(key: str, caption: Callable[[BranchResult, Display], str],
            make: Callable[[BranchResult, Display], Figure]) -> FigureJob:
        return lambda: [ReportFigure(key, caption(result, display),
                                     _marked(make(result, display), result))]

    jobs: list[FigureJob] = [
            lambda: [ReportFigure("schematic", schematic_caption(result),
                                  branch_schematic(result.plan.line))],
            one("tensions", tensions_caption, tensions_figure)]
    if len(result.dataset["layer_span"]):
        jobs.append(one("layers", layers_caption, layers_figure))
    jobs.append(one("speeds", speeds_caption, speeds_figure))
    if len(result.dataset["roll"]):
        jobs.append(one("radii", radii_caption, radii_figure))
    jobs.append(one("torques", torques_caption, torques_figure))
    for name, roll in result.wound_rolls.items():  # each rewound roll (docs/wound-roll.md)
        jobs.append(_wound_roll_job(roll_figure_key(name), roll))
    return jobs


def roll_figure_key(name: str) -> str:
    """The figure key (and file name) of roll ``name`` (``roller/web``): ``wound_roll_``
    and the name with its slash as an underscore."""
    return "wound_roll_" + name.replace("/", "_")


def _wound_roll_job(key: str, roll: WoundRoll) -> FigureJob:
    return lambda: [ReportFigure(key, wound_roll_caption(roll), wound_roll_figure(roll))]
