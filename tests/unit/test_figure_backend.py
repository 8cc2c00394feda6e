"""Drawing a line or a report figure leaves the user's matplotlib backend alone: the figure
modules build ``matplotlib.figure.Figure`` objects, which need no pyplot backend. A module that
called ``matplotlib.use("Agg")`` at import switched a notebook's inline backend off, so the
tutorials' plots after a line's schematic were not shown (issue 37 item 5)."""

from __future__ import annotations

import subprocess
import sys

MODULES = ("webline.report.plots.schematic", "webline.report.plots.branch_schematic",
           "webline.report.plots.figures", "webline.report.notebook")


def test_importing_the_figure_modules_keeps_the_backend() -> None:
    """A backend chosen before (here ``svg``, not the ``Agg`` the modules used to force) is
    still the backend after importing every figure module and drawing a line's schematic."""
    code = ("import matplotlib; matplotlib.use('svg'); import matplotlib.pyplot\n"
            + "".join(f"import {m}\n" for m in MODULES)
            + "import webline; webline.load_line('hswl')._repr_html_()\n"
            + "print(matplotlib.get_backend())")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().lower() == "svg", done.stdout
