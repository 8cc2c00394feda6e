"""The report's poles figure labels its symmetric-log axis in plain text (issue 37: building
matplotlib's mathtext parser for four tick labels cost each report about 0.2 s of CPU)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from webline.report.plots.mpl_text import power_label


@pytest.mark.parametrize(("value", "label"), [
    (0.0, "0"), (10.0, "10¹"), (100.0, "10²"), (-100.0, "−10²"), (1e-3, "10⁻³"),
    (-1e12, "−10¹²"), (1.0, "10⁰"), (25.0, "25"), (-2.5, "−2.5"),
])
def test_power_label_writes_powers_of_ten_with_superscripts(value, label) -> None:
    assert power_label(value) == label


def test_the_poles_figure_draws_without_mathtext() -> None:
    """Drawn in a fresh process (mathtext's parser is cached per process), its tick labels
    are the powers of ten of the axis and the parser was never built."""
    code = ("import matplotlib; matplotlib.use('Agg'); import io\n"
            "from matplotlib.mathtext import MathTextParser\n"
            "from webline.analysis.modes import Mode\n"
            "from webline.report.plots.figures import poles_figure\n"
            "fig = poles_figure([Mode(-150 + 30j, 'a'), Mode(-5 + 2j, 'b'), Mode(-0.5, 'c')])\n"
            "fig.savefig(io.BytesIO(), format='png')\n"
            "ax = fig.axes[0]\n"
            "print('|'.join(t.get_text() for t in ax.get_xticklabels() if t.get_text()))\n"
            "print(MathTextParser._parser is None)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    labels, untouched = done.stdout.split()
    assert "$" not in labels
    assert "−10²" in labels.split("|")  # the real part -150 /s lies beyond -100
    assert untouched == "True"
