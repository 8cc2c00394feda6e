"""The report's building blocks: unit display, plot envelopes, modes, schematic, tables."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest
from matplotlib.patches import Circle

import webline
from webline.analysis.modes import modes
from webline.model.operating_point import analysis_time
from webline.report.plots.schematic import schematic
from webline.report.text.describe import profile_text
from webline.report.text.display import Display, number_text
from webline.report.text.html import Section, Text, render
from webline.report.text.tables import make_table, modes_table
from webline.sim.results.decimate import envelope


def test_display_converts_to_imperial_units():
    imperial = Display("imperial")
    assert imperial.text(4.4482216152605, "force") == "1 lbf"  # 1 lbf = 4.4482216152605 N
    assert imperial.value(0.3048 / 60, "speed") == pytest.approx(1.0)  # 1 ft/min
    assert imperial.value(0.3048, "length") == pytest.approx(1.0)
    assert imperial.value(0.45359237 * 0.3048**2, "inertia") == pytest.approx(1.0)  # lb·ft²
    assert imperial.unit("torque") == "lbf·ft" and imperial.plain_unit("torque") == "lbf*ft"
    assert Display().text(63.832, "force") == "63.83 N"
    assert Display().label("tension", "force") == "tension [N]"
    with pytest.raises(ValueError):
        Display("cgs")  # type: ignore[arg-type]


def test_number_text():
    assert number_text(None) == "–" and number_text(float("nan")) == "–"
    assert number_text(-0.0) == "0" and number_text(1234567.0) == "1.235e+06"


def test_profile_text_in_imperial():
    line = webline.load_line("hswl").with_scenario("speed-change")
    assert profile_text(line.spec.speed, "speed", Display("imperial")) == \
        "ramp 200 → 1000 ft/min, 2 s to 7 s"


def test_envelope_keeps_extremes_and_order():
    rng = np.random.default_rng(1)
    time = np.linspace(0.0, 10.0, 100_001)
    values = rng.normal(size=time.size)
    values[12_345], values[67_890] = 50.0, -40.0
    t, y = envelope(time, values, bins=500)
    assert len(t) == 1000 + 100_001 % 500  # a min and a max per slice, then the remainder
    assert np.all(np.diff(t) >= 0)
    assert y.max() == 50.0 and y.min() == -40.0
    assert t[np.argmax(y)] == time[12_345]
    short = envelope(time[:10], values[:10])
    assert np.array_equal(short[1], values[:10])  # short signals are drawn as they are


def test_modes_of_a_second_order_system():
    wn, zeta = 10.0, 0.3  # [rad/s], [-]
    system = control.ss([[0.0, 1.0], [-wn**2, -2 * zeta * wn], ], [[0.0], [1.0]],
                        [[1.0, 0.0]], 0.0, states=["position", "velocity"])
    (mode,) = modes(system)
    assert mode.natural_frequency == pytest.approx(wn)
    assert mode.frequency_hz == pytest.approx(wn / (2 * math.pi))
    assert mode.damping == pytest.approx(zeta)
    assert mode.damped_frequency == pytest.approx(wn * math.sqrt(1 - zeta**2))
    first_order = modes(control.ss([[-3.0]], [[1.0]], [[1.0]], 0.0))
    assert first_order[0].damping == 1.0 and first_order[0].natural_frequency == 3.0
    table = modes_table([mode])
    assert table.rows[0][2:6] == ("10", "1.592", "9.539", "0.3")


def test_analysis_time_is_end_of_ramp_for_a_start_from_rest():
    line = webline.load_line("hswl")
    assert analysis_time(line) == 0.0
    assert analysis_time(line.with_scenario("startup")) == 11.0  # ramp 1 s + 10 s
    assert analysis_time(line.with_scenario("speed-change")) == 0.0  # starts at 200 ft/min


def test_schematic_draws_every_roller_core_drive_and_loadcell():
    line = webline.load_line("hswl")
    fig = schematic(line, Display("imperial"))
    ax = fig.axes[0]
    circles = [p for p in ax.patches if isinstance(p, Circle)]
    assert len(circles) == line.n_nodes + 2  # rollers + the two roll cores
    texts = [t.get_text() for t in ax.texts]
    assert texts.count("M") == len(line.drives)
    assert sum("loadcell" in t for t in texts) == len(line.zones)
    assert any("20 ft" in t for t in texts)  # span lengths in the chosen units
    unwind, rewind = circles[0], circles[-2]  # each roll is followed by its core
    assert max(c.radius for c in circles) == unwind.radius  # the largest roller, drawn largest
    assert circles[-1].radius < rewind.radius < unwind.radius


def test_render_escapes_text_and_has_no_external_reference():
    table = make_table("t", "<b>title</b>", ["a & b"], [["<script>"]])
    page = render("t<", "s", "ok", "ok", [Section("S", [table, Text("x < y", pre=True)])], "f")
    assert "<script>" not in page and "&lt;script&gt;" in page and "x &lt; y" in page
    assert "http" not in page.replace('"http-equiv"', "")
