"""A schematic of a branched line (docs/branching.md) drawn as its webs run: one coloured path
per web through its rollers, the lamination nip where layers merge, the slitter where lanes
split, lanes on one shaft drawn as one roll with its lanes stacked beside it.

Rollers stand at their depth along the web tree from left (unwinds) to right (rewinds); each
web has a row, a laminate's layers spread above and below it, a base web's lanes likewise, and
a roller sits on the row of the web running through it (a junction on its laminate's or base
web's row, a shaft between its lanes'). Rolls, driven, master and idle rollers, drives and
loadcells look as on a single-path line's schematic (``report.plots.schematic``). Every drawn
element carries a ``gid`` naming what it is (``web:NAME``, ``junction:ROLLER``,
``loadcell:SPAN``, ``roller:NAME``, ``lane:SHAFT:LANE``) so that tests and tools can find it.
"""

from __future__ import annotations

from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle

from webline.model.web_graph import BranchedLine
from webline.report.plots.mpl_text import legend_label, literal
from webline.report.plots.schematic import COLORS, draw_roller, drawn_radius
from webline.report.text.branch_tables import SI, junction_kind, shaft_lanes
from webline.report.text.display import number_text, profile_text
from webline.spec.branched.check import kind_of
from webline.spec.branched.schema import WebPathSpec
from webline.spec.schema import IdleSpec

SPACING = 3.2  #: horizontal distance between roller depths in the drawing
ROW = 3.4  #: vertical distance between neighbouring webs' rows
#: colours of the webs, in file order (matplotlib's tab10 without its orange, the master's)
WEB_COLORS = ("#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
              "#7f7f7f", "#d62728")


def web_rows(line: BranchedLine) -> list[float]:
    """The row (y) of each web: the first web at 0, then along the web tree a laminate's
    layers spread around its row (first on top) and a base web's lanes likewise (lanes on one
    shaft sharing a row); a laminate or base web reached from one of its layers or lanes gets
    the row that puts that one in its place."""
    webs = line.spec.webs
    index = line.web_index
    layers = {w: [index[n] for n in web.layers or []] for w, web in enumerate(webs)}
    lanes: dict[int, list[int]] = {w: [] for w in range(len(webs))}
    for w, web in enumerate(webs):
        if web.slit_from:
            lanes[index[web.slit_from]].append(w)

    def slots(group: list[int]) -> dict[int, float]:
        """Each web of a group's offset from its laminate's or base web's row."""
        places = list(dict.fromkeys(_place(webs[c]) for c in group))
        size = max([_leaves(c, list(webs), layers, lanes) for c in group], default=1)
        return {c: -(places.index(_place(webs[c])) - (len(places) - 1) / 2) * ROW * size
                for c in group}

    rows: dict[int, float] = {}
    offset = 0.0
    for start in range(len(webs)):  # one pass per unconnected tree (normally one)
        if start in rows:
            continue
        rows[start] = offset
        todo = [start]
        while todo:
            w = todo.pop()
            for group in (layers[w], lanes[w]):  # its own layers and lanes around it
                for c, dy in slots(group).items():
                    if c not in rows:
                        rows[c] = rows[w] + dy
                        todo.append(c)
            owners = [p for p in range(len(webs)) if w in layers[p] or w in lanes[p]]
            for p in owners:  # its laminate or base web, placed to put it in its slot
                if p not in rows:
                    group = layers[p] if w in layers[p] else lanes[p]
                    rows[p] = rows[w] - slots(group)[w]
                    todo.append(p)
        offset = min(rows.values()) - 2 * ROW
    return [rows[w] for w in range(len(webs))]


def _place(web: WebPathSpec) -> str:
    """Where a child web runs: a lane by the roll it ends on, a layer by its own name."""
    return f"shaft {web.path[-1]}" if web.slit_from else web.name


def _leaves(w: int, webs: list[WebPathSpec], layers: dict[int, list[int]],
            lanes: dict[int, list[int]]) -> int:
    """How many rows web ``w``'s own layers, or its lanes, need (1 without any): per place
    (a layer, a shaft's lanes) the most its webs need."""
    def need(group: list[int]) -> int:
        places: dict[str, int] = {}
        for c in group:
            place = _place(webs[c])
            places[place] = max(places.get(place, 1), _leaves(c, webs, layers, lanes))
        return sum(places.values())

    return max(1, need(layers[w]), need(lanes[w]))


def node_positions(line: BranchedLine) -> tuple[list[float], list[float]]:
    """x, y of every roller in drawing units: x by its depth along the web tree (the most
    spans between it and an unwind), y on the row of the web running through it (a junction:
    its laminate's or base web's; a shaft: the middle of its lanes')."""
    n = len(line.spec.rollers)
    depth = [0] * n
    for _ in range(n):  # longest path from a start: at most n passes over the spans
        for span in line.spans:
            depth[span.b] = max(depth[span.b], depth[span.a] + 1)
    rows = web_rows(line)
    y = []
    for i, roller in enumerate(line.spec.rollers):
        through = [w for w, web in enumerate(line.spec.webs) if roller.name in web.path[1:-1]]
        if i in line.junctions:  # the trunk: the laminate leaving a nip, the base web ending
            laminates = [w for w, web in enumerate(line.spec.webs)
                         if web.path[0] == roller.name and web.layers]
            bases = [w for w, web in enumerate(line.spec.webs) if web.path[-1] == roller.name]
            through = through or (laminates or bases)[:1]
        touching = [w for w, web in enumerate(line.spec.webs) if roller.name in web.path]
        pick = through or touching
        y.append(sum(rows[w] for w in pick) / len(pick))
    return [d * SPACING for d in depth], y


def branch_schematic(line: BranchedLine) -> Figure:
    """A figure of ``line``'s web tree: one path per web in its colour, rollers labelled with
    name and radius, loadcell spans marked with their reference, drives, the lamination nips
    and slitters marked, lanes on one shaft stacked beside their roll."""
    rollers = line.spec.rollers
    largest = max(r.radius for r in rollers)
    size = [drawn_radius(r.radius, largest) for r in rollers]
    x, y = node_positions(line)
    shafts = shaft_lanes(line)
    width = max(x) - min(x) + 5.0
    height = max(y) - min(y) + 6.0
    fig = Figure(figsize=(max(8.0, 0.75 * width), max(4.0, 0.75 * height)),
                 layout="constrained")
    ax = fig.add_subplot()
    cells = {k for zone in line.zones.values() for k in zone.loadcells}
    setter = {k: line.spec.rollers[zone.node].name for zone in line.zones.values()
              for k in zone.loadcells}
    for w, web in enumerate(line.spec.webs):
        color = WEB_COLORS[w % len(WEB_COLORS)]
        spans = [line.spans[k] for k in line.web_spans(w)]
        xs = [x[spans[0].a]] + [x[span.b] for span in spans]
        ys = [y[spans[0].a]] + [y[span.b] for span in spans]
        at = 0.5  # where along each span its label and loadcell go
        last = spans[-1].b
        if last in shafts:  # a lane runs beside the other lanes of its shaft, to its place
            j, count = shafts[last].index(w), len(shafts[last])
            shift = (j - (count - 1) / 2) * -0.8 * size[last] / max(1, count - 1)
            ys[-1] += shift
            if len(spans) == 1 and spans[0].a in line.junctions:
                ys[0] += shift
            at = 0.25 + 0.35 * j / (count - 1)
        ax.plot(xs, ys, color=color, lw=2.2, zorder=2, gid=f"web:{web.name}",
                label=legend_label(f"{web.name} ({_kind(web)})"))
        for k, span in enumerate(spans):
            xm, ym = xs[k] + at * (xs[k + 1] - xs[k]), ys[k] + at * (ys[k + 1] - ys[k])
            ax.annotate("", (xs[k] + 0.3 * (xs[k + 1] - xs[k]), ys[k] + 0.3 * (ys[k + 1] - ys[k])),
                        (xs[k] + 0.2 * (xs[k + 1] - xs[k]), ys[k] + 0.2 * (ys[k + 1] - ys[k])),
                        arrowprops={"arrowstyle": "-|>", "color": color, "lw": 0}, zorder=3)
            ax.text(xm, ym - 0.3, literal(f"{span.name}\n{number_text(span.length, 3)} m"),
                    ha="center", va="top", fontsize=7, color=color, zorder=5)
            if span.index in cells:
                ref = line.span_tension_spec(span.index)
                ax.plot([xm], [ym + 0.15], marker="v", ms=9, color=COLORS["loadcell"],
                        zorder=4, gid=f"loadcell:{span.name}")
                ax.text(xm, ym + 0.35, literal(f"loadcell {profile_text(ref, 'force', SI)}\n"
                                               f"set by {setter[span.index]}"),
                        ha="center", va="bottom", fontsize=6.5, color=COLORS["loadcell"])
    for i, roller in enumerate(rollers):
        s = size[i]
        draw_roller(ax, roller, x[i], s, i == line.master, y[i]).set_gid(f"roller:{roller.name}")
        below = y[i] - s - 0.1
        if not isinstance(roller, IdleSpec):
            ax.add_patch(Rectangle((x[i] + s * 0.6, y[i] - s - 0.55), 0.7, 0.4,
                                   color=COLORS["drive"], zorder=3))
            ax.text(x[i] + s * 0.6 + 0.35, y[i] - s - 0.35, "M", color="white", ha="center",
                    va="center", fontsize=7, weight="bold", zorder=4)
            below -= 0.5
        ax.text(x[i], below, literal(f"{roller.name}\n{number_text(roller.radius * 1e3, 3)} mm"),
                ha="center", va="top", fontsize=7.5, gid=f"label:{roller.name}")
        junction = junction_kind(line, i)
        if junction:
            ax.plot([x[i]], [y[i] + s + 0.25], marker="D" if junction.endswith("nip") else "X",
                    ms=8, color="#333333", zorder=5, gid=f"junction:{roller.name}")
            ax.text(x[i], y[i] + s + 0.5, junction, ha="center", va="bottom", fontsize=7.5,
                    weight="bold")
        for j, w in enumerate(shafts.get(i, [])):  # the shaft seen from the side: its lanes
            lane = line.spec.webs[w]
            top = y[i] + s - j * (2 * s / len(shafts[i]))
            ax.add_patch(Rectangle((x[i] + s + 0.25, top - 2 * s / len(shafts[i])), 0.35,
                                   2 * s / len(shafts[i]), facecolor=WEB_COLORS[w % len(
                                       WEB_COLORS)], edgecolor="white", zorder=3,
                                   gid=f"lane:{roller.name}:{lane.name}"))
            ax.text(x[i] + s + 0.7, top - s / len(shafts[i]), literal(lane.name),
                    ha="left", va="center", fontsize=6.5)
    handles = [Line2D([], [], color=WEB_COLORS[w % len(WEB_COLORS)], lw=2.2,
                      label=legend_label(f"{web.name} ({_kind(web)})"))
               for w, web in enumerate(line.spec.webs)]
    handles.append(Line2D([], [], ls="", marker="v", ms=8, color=COLORS["loadcell"],
                          label="loadcell"))
    ax.legend(handles=handles, loc="upper left", fontsize=7, frameon=False)
    ax.set_xlim(min(x) - 1.6, max(x) + 3.0)
    ax.set_ylim(min(y) - 3.0, max(y) + 2.4)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(literal(f"{line.name}: {len(line.spec.webs)} webs, {len(rollers)} rollers, "
                         f"{len(line.spans)} spans, {len(line.drives)} drives"), fontsize=10)
    return fig


def _kind(web: WebPathSpec) -> str:
    return {"web": "raw web", "laminate": "laminate", "lane": "lane"}[kind_of(web)]

