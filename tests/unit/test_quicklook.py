"""``Result.plot()`` and the notebook display of a ``Result``."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline import ArgumentError


@pytest.fixture(scope="module")
def result():
    return webline.simulate("hswl", "12 s", scenario="speed-change")


def test_plot_keeps_every_tension_peak(result) -> None:
    """12 001 records per span become a min/max envelope of at most ~2 points per pixel
    column, and each span's largest and smallest tension are still drawn."""
    figure = result.plot(("tension", "speed", "torque"))
    axes = figure.axes
    assert len(axes) == 3
    solid = [ln for ln in axes[0].get_lines() if ln.get_linestyle() == "-"]
    assert len(solid) == len(result.span_names)
    for k, line in enumerate(solid):
        y = np.asarray(line.get_ydata())
        assert len(y) <= 2 * 1000 + 13
        assert y.max() == result.tension[:, k].max() and y.min() == result.tension[:, k].min()


def test_plot_refuses_unknown_signals(result) -> None:
    with pytest.raises(ArgumentError, match="signals"):
        result.plot(("tension", "pressure"))


def test_notebook_display_states_the_verdict(result) -> None:
    html = result._repr_html_()
    assert result.status in html and "hswl" in html
    for span in result.span_names:
        assert f"<td>{span}</td>" in html
