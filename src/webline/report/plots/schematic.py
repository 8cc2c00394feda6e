"""A schematic of a line drawn from its topology: rolls, rollers, spans, drives, loadcells, zones.

Rollers stand in web order from left (unwind) to right (rewind), equally spaced; each circle's
size grows with the square root of its radius. Rolls show their core, driven rollers are
filled (the master-speed roller in orange), idle rollers are open; each drive is a box under its
roller, joined by a solid (direct), dashed (belt) or dotted (shaft) stem and labelled with its
drive train (transmission, backlash, the side its speed is measured on, brake); each loadcell
is a triangle on its span, each tension zone a shaded band; a nip is a second (grey) circle
pressed on its roller from above, labelled with its load and grip. Each zone's label names
the element that sets its tension (a dancer in position control, else the drive); a dancer
carries a double arrow along its travel with its use, load, stroke and set position; a roll
lists its winder functions (open loop, taper, diameter calculation, compensation) above it;
a span that breaks in the run is marked with a red cross and its time.
"""

from __future__ import annotations

import math

from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrowPatch, Rectangle

from webline.line import Line
from webline.report.plots.mpl_text import literal
from webline.report.text.describe import backlash_text
from webline.report.text.describe_winder import dancer_label, roll_labels, tension_setter_short
from webline.report.text.display import Display
from webline.spec.schema import DancerSpec, DriveSpec, IdleSpec, RewindSpec, UnwindSpec
from webline.spec.winder import WebBreak

SPACING = 3.0  #: distance between roller centres in the drawing
COLORS = {"roll": "#d8c49a", "core": "#8c8c8c", "master": "#f28e2b", "tension": "#4e79a7",
          "idle": "white", "drive": "#59595c", "loadcell": "#e15759", "web": "#222222",
          "nip": "#8f8f8f", "dancer": "#76b7b2", "winder": "#7a5195", "break": "#d62728"}
ZONE_SHADES = ("#eef3f8", "#f7f1e8")
#: line style of the motor-to-roller stem per transmission (dashed: belt, dotted: shaft)
STEM_STYLES = {"direct": "-", "belt": "--", "shaft": ":"}


def drawn_radius(radius: float, largest: float) -> float:
    """Size of a roller in the drawing for its ``radius`` [m] (largest roll = 1.0)."""
    return 0.3 + 0.7 * math.sqrt(radius / largest)


def schematic(line: Line, display: Display | None = None) -> Figure:
    """A figure of ``line``'s topology with span lengths and tension references in the chosen
    units."""
    display = display or Display()
    rollers = line.spec.rollers
    largest = max(r.radius for r in rollers)
    size = [drawn_radius(r.radius, largest) for r in rollers]
    x = [i * SPACING for i in range(line.n_nodes)]
    width, height = max(8.0, 1.9 * line.n_nodes), 4.4
    # fixed margins [in] (a thin edge, the title's room on top) instead of a layout engine,
    # which draws the figure twice when it is saved (``frame``): the axes carry no ticks and
    # keep their aspect inside this box
    fig = Figure(figsize=(width, height))
    fig.subplots_adjust(left=0.05 / width, right=1 - 0.05 / width, bottom=0.05 / height,
                        top=1 - 0.25 / height)
    ax = fig.add_subplot()
    nips = [getattr(r, "nip", None) for r in rollers]
    top = max(s + (0.0 if nip is None else 2 * drawn_radius(nip.radius, largest))
              for nip, s in zip(nips, size, strict=True)) + 1.6  # room for nips on top

    for z, zone in enumerate(line.zones):
        left, right = x[zone.first], x[zone.last]
        ax.add_patch(Rectangle((left, -3.0), right - left, top + 2.8,
                               color=ZONE_SHADES[z % 2], zorder=0))
        ax.text((left + right) / 2, top - 0.35,
                literal(f"zone {z + 1}: tension set by {tension_setter_short(line, z)}"),
                ha="center", va="center", fontsize=8, color="#555555")

    loadcells = {zone.loadcell for zone in line.zones}
    for k, span in enumerate(line.spec.spans):
        x0, x1, y0, y1 = x[k], x[k + 1], size[k], size[k + 1]
        ax.plot([x0, x1], [y0, y1], color=COLORS["web"], lw=1.6, zorder=2)
        xm, ym = (x0 + x1) / 2, (y0 + y1) / 2
        ax.add_patch(FancyArrowPatch(_along(x0, y0, x1, y1, 0.2), _along(x0, y0, x1, y1, 0.3),
                                     arrowstyle="-|>", mutation_scale=11, color=COLORS["web"],
                                     lw=0, zorder=3))
        label = literal(f"{line.span_name(k)}\n{display.text(span.length, 'length', 3)}")
        ax.text(xm, ym - 0.25, label, ha="center", va="top", fontsize=8)
        if k in loadcells:
            ax.plot([xm], [ym + 0.12], marker="v", ms=9, color=COLORS["loadcell"], zorder=4)
            ref = span.tension if isinstance(span.tension, float) else None
            text = "loadcell" + (f"\n{display.text(ref, 'force', 4)}" if ref else "")
            ax.text(xm, ym + 0.3, text, ha="center", va="bottom", fontsize=7,
                    color=COLORS["loadcell"])

    _winder_marks(ax, line, x, size, display)
    for i, (roller, s) in enumerate(zip(rollers, size, strict=True)):
        draw_roller(ax, roller, x[i], s, i == line.master)
        nip = getattr(roller, "nip", None)
        if nip is not None:  # the pressure roller rides on the roller, the web between
            s_n = drawn_radius(nip.radius, largest)
            ax.add_patch(Circle((x[i], s + s_n), s_n, facecolor=COLORS["nip"],
                                edgecolor="#333333", lw=1.2, zorder=3))
            ax.text(x[i] - s_n - 0.1, s + s_n, literal(
                f"nip {display.text(nip.load, 'force', 4)}\n{nip.grip}"), ha="right",
                va="center", fontsize=6.5, color="#444444", zorder=4)
        if not isinstance(roller, IdleSpec):
            style = STEM_STYLES[getattr(roller.drive.transmission, "type", "direct")]
            ax.plot([x[i], x[i]], [-s, -s - 0.55], color=COLORS["drive"], lw=2, ls=style,
                    zorder=1)
            ax.add_patch(Rectangle((x[i] - 0.45, -s - 1.05), 0.9, 0.5, color=COLORS["drive"],
                                   zorder=3))
            ax.text(x[i], -s - 0.8, "M", color="white", ha="center", va="center",
                    fontsize=8, weight="bold", zorder=4)
            ax.text(x[i] + 0.55, -s - 0.55, literal(drive_train_label(roller.drive, display)),
                    ha="left", va="center", fontsize=6.5, color=COLORS["drive"], zorder=4)
        below = -s - (1.2 if not isinstance(roller, IdleSpec) else 0.15)
        ax.text(x[i], below, literal(f"{roller.name}\n{display.text(roller.radius, 'length', 3)}"),
                ha="center", va="top", fontsize=8)

    any_nip = any(nip is not None for nip in nips)
    ax.legend(handles=_legend(any_nip), loc="lower center", bbox_to_anchor=(0.5, -0.02),
              ncol=8 if any_nip else 7, fontsize=7, frameon=False)
    ax.set_xlim(-1.4, x[-1] + 2.4)  # room for the rewind drive's drive-train label
    ax.set_ylim(-3.6, top)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(literal(f"{line.name}: {line.n_nodes} rollers, {line.n_spans} spans, "
                         f"{len(line.drives)} drives"), fontsize=10)
    return fig


def _winder_marks(ax: object, line: Line, x: list[float], size: list[float],
                  display: Display) -> None:
    """Dancers' travel and settings, rolls' winder functions, spans that break."""
    for i, roller in enumerate(line.spec.rollers):
        s = size[i]
        if isinstance(roller, DancerSpec):
            ax.add_patch(FancyArrowPatch((x[i], s + 0.05), (x[i], s + 0.75),  # type: ignore[attr-defined]
                                         arrowstyle="<|-|>", mutation_scale=9,
                                         color=COLORS["dancer"], lw=1.2, zorder=3))
            ax.text(x[i] + 0.15, s + 0.45, literal(dancer_label(line, i, display)),  # type: ignore[attr-defined]
                    ha="left", va="center", fontsize=6.5, color=COLORS["dancer"], zorder=4)
        labels = roll_labels(line, i) if isinstance(roller, UnwindSpec | RewindSpec) else []
        if labels:
            ax.text(x[i], s + 0.15, literal("\n".join(labels)), ha="center", va="bottom",  # type: ignore[attr-defined]
                    fontsize=6.5, color=COLORS["winder"], zorder=4)
    names = [line.span_name(k) for k in range(line.n_spans)]
    for item in line.spec.disturbances:
        if isinstance(item, WebBreak) and item.span in names:
            k = names.index(item.span)
            xm, ym = (x[k] + x[k + 1]) / 2, (size[k] + size[k + 1]) / 2
            ax.plot([xm], [ym], marker="X", ms=10, color=COLORS["break"], zorder=5)  # type: ignore[attr-defined]
            ax.text(xm, ym - 0.9, literal(f"breaks at {display.text(item.at, 'time', 3)}"),  # type: ignore[attr-defined]
                    ha="center", va="top", fontsize=7, color=COLORS["break"], zorder=5)


def drive_train_label(drive: DriveSpec, display: Display) -> str:
    """The drive train beside a motor box, one item a line: transmission (direct, belt or
    shaft), backlash if any, the side the speed loop measures, brake if any."""
    transmission = drive.transmission
    lines: list[str] = [transmission.type]
    backlash = getattr(transmission, "backlash", None)
    if backlash is not None:
        lines.append(f"backlash {backlash_text(backlash, display)}")
    lines.append(f"speed at {drive.feedback}")
    if drive.brake is not None:
        lines.append("brake")
    return "\n".join(lines)


def _along(x0: float, y0: float, x1: float, y1: float, f: float) -> tuple[float, float]:
    return x0 + f * (x1 - x0), y0 + f * (y1 - y0)


def draw_roller(ax: object, roller: object, x: float, size: float, master: bool,
            y: float = 0.0) -> Circle:
    """Draw a roller centred at (``x``, ``y``): a roll with its core, an idle roller open, a
    driven one filled (the master orange); returns its outer circle."""
    if isinstance(roller, UnwindSpec | RewindSpec):
        outer = ax.add_patch(Circle((x, y), size, facecolor=COLORS["roll"],  # type: ignore[attr-defined]
                                    edgecolor="#5a4a2a", lw=1.2, zorder=3))
        core = size * roller.core_radius / roller.radius
        ax.add_patch(Circle((x, y), core, facecolor=COLORS["core"], edgecolor="#444444",  # type: ignore[attr-defined]
                            zorder=4))
    elif isinstance(roller, IdleSpec):
        outer = ax.add_patch(Circle((x, y), size, facecolor=COLORS["idle"],  # type: ignore[attr-defined]
                                    edgecolor="#555555", lw=1.2, zorder=3))
    else:
        color = COLORS["master" if master else "tension"]
        outer = ax.add_patch(Circle((x, y), size, facecolor=color, edgecolor="#333333",  # type: ignore[attr-defined]
                                    lw=1.2, zorder=3))
    return outer


def _legend(nips: bool = False) -> list[Line2D]:
    def dot(color: str, label: str, marker: str = "o", edge: str = "#333333") -> Line2D:
        return Line2D([], [], ls="", marker=marker, ms=9, markerfacecolor=color,
                      markeredgecolor=edge, label=label)

    handles = [dot(COLORS["roll"], "roll (core grey)"), dot(COLORS["master"], "master (speed)"),
               dot(COLORS["tension"], "driven (tension)"), dot(COLORS["idle"], "idle roller"),
               dot(COLORS["drive"], "drive (motor)", "s"),
               dot(COLORS["loadcell"], "loadcell", "v", COLORS["loadcell"]),
               Line2D([], [], color=COLORS["web"], marker=">", ms=6, label="web (direction)")]
    if nips:
        handles.insert(4, dot(COLORS["nip"], "nip (pressure roller)"))
    return handles
