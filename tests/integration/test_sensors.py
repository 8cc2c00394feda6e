"""Sensors in the loop (``[[sensors]]``, docs/line-file.md "sensors"): a loadcell's gain and
offset, an encoder's scale and a signal's delay act where the controllers read them, so the
loops hold the *reading* on the reference and the web settles where that puts it; the
result's ``tension`` and ``speed`` stay the true ones, ``tension_measured`` and
``speed_measured`` show what the sensors read. hswl (thesis Table 6.1) at its constant
500 ft/min: span 2's loadcell is the process drive's, the master sets the line speed."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import LineFileError

REF = 63.83198018  # hswl's 14.35 lbf set point [N]
V_REF = 2.54  # 500 ft/min [m/s]


def run(sensors, seconds=2.0, scenario=None):
    line = webline.load_line("hswl").replace({"sensors": sensors})
    return webline.simulate(line, seconds, scenario=scenario)


@pytest.fixture(scope="module")
def ideal():
    return webline.simulate(webline.load_line("hswl"), 2.0)


def test_an_ideal_declared_sensor_changes_nothing(ideal):
    """gain 1, offset 0, scale 1, no delay: the loop compiles as before sensors existed, so
    the run is bit for bit the ideal line's (benchmarks/trajectories.py checks every line)."""
    result = run([{"name": "lc2", "type": "loadcell", "span": "span2"},
                  {"name": "enc", "type": "encoder", "roller": "master"}])
    assert np.array_equal(result.states, ideal.states)


def test_a_loadcell_reading_high_holds_the_web_below_its_set_point(ideal):
    """Gain g: the process drive's PI holds g T on the reference, so T = T_ref / g; the
    operating point knows it, so the run starts and stays there (within the integration's
    1e-6 N); the reading shows the set point; the other zones do not notice."""
    result = run([{"name": "lc2", "type": "loadcell", "span": "span2", "gain": 1.03}])
    k = 1  # span2
    assert result.tension[:, k] == pytest.approx(REF / 1.03, abs=1e-5)
    assert result.tension_measured[:, k] == pytest.approx(REF, abs=1e-5)
    assert webline.operating_point(result.line).tension[k] == pytest.approx(REF / 1.03)
    for j in (0, 3):  # span1 (unwind), span3b (rewind): the same as the ideal line
        assert result.tension[-1, j] == pytest.approx(ideal.tension[-1, j], abs=1e-5)


def test_a_loadcell_offset_shifts_the_web_tension_by_it():
    result = run([{"name": "lc3", "type": "loadcell", "span": "span3b", "offset": "2 N"}])
    assert result.tension[:, 3] == pytest.approx(REF - 2.0, abs=1e-5)
    assert result.tension_measured[:, 3] == pytest.approx(REF, abs=1e-5)


def test_the_master_encoder_scale_sets_the_true_line_speed(ideal):
    """The master's speed loop holds s v on the reference: the web runs at v_ref / s, every
    node slower by the same factor (the draws are the tensions'); the loadcell spans keep
    their set points, and the idler's viscous tension drop (b ω / r into span3a) falls with
    the speed by the same factor."""
    result = run([{"name": "enc", "type": "encoder", "roller": "master", "scale": 1.02}])
    assert result.speed[:, 1] == pytest.approx(V_REF / 1.02, rel=1e-7)
    assert result.speed_measured[:, 1] == pytest.approx(V_REF, rel=1e-7)
    np.testing.assert_allclose(result.speed[-1], ideal.speed[-1] / 1.02, rtol=1e-6)
    for k in (0, 1, 3):  # the loadcell spans
        assert result.tension[-1, k] == pytest.approx(ideal.tension[-1, k], abs=1e-5)
    drop = [r.tension[-1, 3] - r.tension[-1, 2] for r in (ideal, result)]
    assert drop[1] == pytest.approx(drop[0] / 1.02, rel=1e-4)


def test_a_tension_drive_encoder_scale_is_trimmed_away(ideal):
    """A tension-controlled drive's speed reference is trimmed by its tension loop: its
    encoder's scale moves the trim, not the web (tension and speed as the ideal line's)."""
    result = run([{"name": "enc", "type": "encoder", "roller": "process", "scale": 1.02}])
    np.testing.assert_allclose(result.tension[-1], ideal.tension[-1], atol=1e-5)
    np.testing.assert_allclose(result.speed[-1], ideal.speed[-1], rtol=1e-7)
    assert result.speed_measured[-1, 2] == pytest.approx(1.02 * ideal.speed[-1, 2], rel=1e-7)
    d = result.drive_names.index("process")
    assert result.trim[-1, d] - ideal.trim[-1, d] == pytest.approx(0.02 * V_REF, rel=1e-3)


def test_a_loadcell_delay_shows_the_reading_late_and_costs_damping():
    """The process zone's 25 % tension step (scenario tension-step, at 2 s): the reading is
    the tension one delay late (to the interpolation between records), and a 20 ms delay in
    the tension loop's feedback lets the step overshoot more than without it."""
    late = run([{"name": "lc2", "type": "loadcell", "span": "span2", "delay": "20 ms"}],
               seconds=4.0, scenario="tension-step")
    prompt = run([], seconds=4.0, scenario="tension-step")
    t = late.time
    shifted = np.interp(t - 0.020, t, late.tension[:, 1])
    assert np.max(np.abs(late.tension_measured[:, 1] - shifted)) < 1e-9
    step = 18 * 4.4482216152605 - REF
    overshoot = [(r.tension[:, 1].max() - (REF + step)) / step for r in (prompt, late)]
    assert overshoot[1] > overshoot[0] + 0.01, overshoot


def test_the_closed_loop_linear_model_holds_the_reading():
    """The linear model reads the loadcell through its gain: the DC gain from span 2's
    tension reference to its true tension is 1/g."""
    line = webline.load_line("hswl").replace(
        {"sensors": [{"name": "lc2", "type": "loadcell", "span": "span2", "gain": 1.03}]})
    sys = webline.linearize(line)
    i, j = sys.output_labels.index("span2_tension"), sys.input_labels.index("zone2_tension_ref")
    assert np.real(sys.dcgain()[i, j]) == pytest.approx(1 / 1.03, rel=1e-6)


@pytest.mark.parametrize(("sensors", "key", "words"), [
    ([{"name": "a", "type": "loadcell", "span": "nope"}], "sensors[0].span", "no span named"),
    ([{"name": "a", "type": "loadcell", "span": "span3a"}], "sensors[0].span",
     "no tension reference"),
    ([{"name": "a", "type": "encoder", "roller": "idler"}], "sensors[0].roller", "no drive"),
    ([{"name": "a", "type": "encoder", "roller": "master"},
      {"name": "a", "type": "loadcell", "span": "span2"}], "sensors[1].name", "used twice"),
    ([{"name": "a", "type": "encoder", "roller": "master"},
      {"name": "b", "type": "encoder", "roller": "master"}], "sensors[1]", "already measures"),
    ([{"name": "a", "type": "loadcell", "span": "span2", "gain": 0}], "sensors", "> 0"),
])
def test_a_sensor_the_line_cannot_have_is_refused_naming_its_key(sensors, key, words):
    with pytest.raises(LineFileError) as caught:
        webline.load_line("hswl").replace({"sensors": sensors})
    assert key in str(caught.value) and words in str(caught.value)


def test_a_delay_beyond_the_modelled_samples_is_refused_naming_its_key():
    line = webline.load_line("hswl").replace(
        {"sensors": [{"name": "a", "type": "loadcell", "span": "span2", "delay": "50 ms"}]})
    with pytest.raises(LineFileError, match=r"sensors\[0\]\.delay: .* at most 32"):
        webline.simulate(line, 0.1)


def test_a_loadcell_on_a_zone_a_dancer_holds_is_refused():
    """The converter's unwind zone is held by its dancer (the loadcell only monitors): a
    calibration there would not act in the loop, so it is refused naming the key."""
    line = webline.load_line("converter").replace(
        {"sensors": [{"name": "a", "type": "loadcell", "span": "unwind_span", "gain": 1.02}]})
    with pytest.raises(LineFileError, match=r"sensors\[0\]\.span: .*with a dancer"):
        webline.simulate(line, 0.1)


def test_show_and_the_report_list_the_calibrated_sensors():
    """``webline show`` and the report's line section: a sensors table in the chosen units
    (here the offset in lbf: 0.5 lbf = 2.224 N)."""
    from webline.report.text.describe import line_tables
    from webline.report.text.display import Display

    line = webline.load_line("hswl").replace({"sensors": [
        {"name": "lc2", "type": "loadcell", "span": "span2", "gain": 1.03,
         "offset": "-0.5 lbf", "delay": "3 ms"},
        {"name": "enc", "type": "encoder", "roller": "master", "scale": 1.02}]})
    imperial = Display("imperial", line.spec.web.width)
    (table,) = [t for t in line_tables(line, imperial) if t.key == "sensors"]
    assert tuple(table.rows[0][:3]) == ("lc2", "loadcell", "span span2")
    assert "1.03 x T - 0.5 lbf" in table.rows[0][3] and "late" in table.rows[0][3]
    assert table.rows[1][3] == "1.02 x v"
    assert not [t for t in line_tables(webline.load_line("hswl"), imperial)
                if t.key == "sensors"]
