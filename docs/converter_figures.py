"""Draw the figures of docs/winder.md that come from the built-in `converter` line, and the
two of rockwell's web-break scenario.

    .venv/bin/python docs/converter_figures.py      # writes docs/img/converter-*.png, ...

Uses the report's own figure functions, so the docs show what `webline run converter
--scenario NAME` puts in its report.
"""

from __future__ import annotations

from pathlib import Path

import webline
from webline.report.plots.figures import tension_figure
from webline.report.plots.schematic import schematic
from webline.report.plots.splice_figures import splice_figure
from webline.report.plots.winder_figures import dancer_figure, diameter_figure, taper_figure
from webline.report.text.display import Display

IMG = Path(__file__).resolve().parent / "img"


def main() -> None:
    line = webline.load_line("converter")
    display = Display()
    figures = {"converter-schematic": schematic(line, display)}
    roll = webline.simulate(line, scenario="roll-change")
    rewind_zone = line.zones[line.controlled_zone(line.n_nodes - 1)].loadcell
    figures["converter-roll-change-taper"] = taper_figure(roll, display, rewind_zone)
    figures["converter-roll-change-diameter"] = diameter_figure(
        roll, display, [len(line.drives) - 1])
    figures["converter-web-break-tension"] = tension_figure(
        webline.simulate(line, scenario="web-break", raise_on_failure=False), display)
    figures["converter-flying-splice"] = splice_figure(
        webline.simulate(line, scenario="flying-splice"), display)
    rockwell = webline.load_line("rockwell")
    broken = webline.simulate(rockwell, scenario="web-break")
    figures["winder-break-tension"] = tension_figure(broken, display)
    figures["winder-break-dancer"] = dancer_figure(broken, display, [1])
    IMG.mkdir(exist_ok=True)
    for name, fig in figures.items():
        path = IMG / f"{name}.png"
        fig.savefig(path, dpi=90)
        print(path)


if __name__ == "__main__":
    main()
