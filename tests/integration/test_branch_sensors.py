"""Calibrated loadcells on a branched line (``[[sensors]]`` with ``[[webs]]``,
docs/branching.md "Sensors"): the zone's PI holds the loadcell's reading gain T + offset on
its reference, so the web settles at (T_ref - offset) / gain, as on a single-path line
(tests/integration/test_sensors.py). The laminator (src/webline/data/lines/laminator.toml):
film 120 N, foil 60 N, laminate 180 N."""

from __future__ import annotations

import numpy as np
import pytest
from test_branch_dancers import dancer_laminator

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.sim.branches.loop import layout as B

FILM, FOIL, LAMINATE = 120.0, 60.0, 180.0


def laminator(sensors):
    return load_branched("laminator").replace({"sensors": sensors})


def span(result, name):
    return result.span_names.index(name)


@pytest.fixture(scope="module")
def ideal():
    return webline.simulate("laminator", duration=0.5)


def test_an_ideal_declared_loadcell_changes_nothing(ideal):
    """gain 1, offset 0: the loop compiles as without sensors, bit for bit."""
    result = webline.simulate(laminator([{"name": "lc", "type": "loadcell",
                                          "span": "laminate_zone"}]), duration=0.5)
    assert np.array_equal(result.states, ideal.states)
    assert np.array_equal(result.tension_measured, result.tension)


def test_a_loadcell_reading_high_holds_the_laminate_below_its_set_point(ideal):
    """gain 1.03 on the laminate zone: the rewind's PI holds 1.03 T on 180 N, so the web
    carries 180 / 1.03 N; the operating point knows it (the run starts there), and the
    reading then follows the ideal line's tension (the growing rewind drifts both by 0.02 N
    in 0.5 s) within 1e-3 N; the film and foil zones, held by their own loadcells, keep
    theirs."""
    result = webline.simulate(laminator([{"name": "lc", "type": "loadcell",
                                          "span": "laminate_zone", "gain": 1.03}]),
                              duration=0.5)
    k = span(result, "laminate_zone")
    assert result.tension[0, k] == pytest.approx(LAMINATE / 1.03, abs=1e-6)
    assert result.tension_measured[:, k] == pytest.approx(ideal.tension[:, k], abs=1e-3)
    assert "tension_measured" in result.dataset and "tension_measured" not in ideal.dataset
    assert result.tension[:, k] == pytest.approx(ideal.tension[:, k] / 1.03, abs=1e-3)
    for name, ref in (("film_zone", FILM), ("foil_zone", FOIL)):
        j = span(result, name)
        assert result.tension[0, j] == pytest.approx(ref, abs=1e-6)
        assert result.tension[-1, j] == pytest.approx(ideal.tension[-1, j], abs=1e-5)


def test_the_loop_follows_a_step_to_the_calibrated_tension():
    """layer-upset: the film reference steps 120 -> 150 N at 2 s; with the film loadcell
    reading 3 % high and 1 N over, the film settles at (150 - 1) / 1.03 N (8 rad/s tension
    loop: settled to 1e-3 N within 3 s), having started at (120 - 1) / 1.03 N."""
    line = laminator([{"name": "lc", "type": "loadcell", "span": "film_zone", "gain": 1.03,
                       "offset": "1 N"}]).with_scenario("layer-upset")
    result = webline.simulate(line, duration=5.0)
    k = span(result, "film_zone")
    assert result.tension[0, k] == pytest.approx((FILM - 1.0) / 1.03, abs=1e-5)
    assert result.tension[-1, k] == pytest.approx((150.0 - 1.0) / 1.03, abs=1e-3)
    assert result.tension_measured[-1, k] == pytest.approx(150.0, abs=1.03e-3)
    # the ideal loadcell would have held 150 N: the calibration error is 4.5 N, not noise
    assert 150.0 - result.tension[-1, k] > 4.0


@pytest.mark.parametrize(("sensor", "key", "words"), [
    ({"name": "lc", "type": "loadcell", "span": "laminate[1]"}, "sensors[0].span",
     "no tension reference"),
    ({"name": "lc", "type": "loadcell", "span": "nowhere"}, "sensors[0].span", "no span"),
])
def test_what_a_branched_line_refuses(sensor, key, words):
    with pytest.raises(LineFileError) as error:
        laminator([sensor])
    assert key in str(error.value) and words in str(error.value)


def test_a_loadcell_on_a_zone_its_dancer_holds_is_refused():
    """The film zone held by its dancer's position: the loadcell is not in the loop, its
    calibration would not act, so the run refuses it naming the key (as the chain's)."""
    data = dancer_laminator()
    data["sensors"] = [{"name": "lc", "type": "loadcell", "span": "film_zone", "gain": 1.02}]
    with pytest.raises(LineFileError, match=r"sensors\[0\]\.span: the dancer of "
                       r"'unwind_film' controls span 'film_zone'"):
        webline.simulate(load_branched(data), 0.1)


def test_a_fit_finds_the_laminate_loadcells_gain(tmp_path):
    """A record of the laminator whose laminate loadcell reads 3 % high (3 s at 150 m/min,
    200 Hz, sensor noise ``synthetic.NOISE``): its reading sits on 180 N as an ideal one's
    would, but the rewind's torque carries the true r T = r 180 / 1.03; the fit of
    ``sensors.lc.gain`` from the file's ideal loadcell finds 1.03 within 1 %, the truth
    inside its 95 % interval."""
    from webline.twin.fitting.fit import fit
    from webline.twin.traces.synthetic import synthetic_csv

    line = laminator([{"name": "lc", "type": "loadcell", "span": "laminate_zone"}])
    path = synthetic_csv(tmp_path / "record.csv", line, changes={"sensors.lc.gain": 1.03},
                         duration=3.0, scenario="layer-upset", rate=200.0, seed=1)
    result = fit(line.with_scenario("layer-upset"), path, {"sensors.lc.gain": "0.9 .. 1.1"},
                 starts=1)
    assert result.value[0] == pytest.approx(1.03, rel=0.01), result
    assert result.ci95[0, 0] <= 1.03 <= result.ci95[0, 1], result
    assert result.verdict.status == "good", result.verdict


@pytest.mark.parametrize("gain", [1.0, 1.03])
def test_the_linear_model_holds_the_reading_on_the_reference(gain):
    """Closed loop, the film zone's steady gain from its reference to its tension,
    -C A⁻¹ B: the tension integrator drives the reading's error to 0, so 1 N more reference
    is 1 / gain N more web (1 / 1.03 = 0.97087), to the solver's 1e-9."""
    from webline.sim.branches.equilibrium import operating_point
    from webline.sim.branches.linear import branch_linear_model
    from webline.sim.branches.plan import compile_branches

    plan = compile_branches(laminator([{"name": "lc", "type": "loadcell", "span": "film_zone",
                                        "gain": gain}]))
    model = branch_linear_model(plan, operating_point(plan), "closed")
    b = model.b[:, model.inputs.index("film_zone_tension_ref")]
    row = model.c[model.outputs.index("film_zone_tension")]
    assert max(np.linalg.eigvals(model.a).real) < 0.0  # (stable: the steady gain exists)
    assert row @ np.linalg.solve(model.a, -b) == pytest.approx(1.0 / gain, abs=1e-9)


def test_show_lists_the_calibrated_loadcells():
    """``webline show`` of a branched line: a sensors table (the single-path one's rows)."""
    from webline.report.text.branch_tables import line_tables

    line = laminator([{"name": "lc", "type": "loadcell", "span": "laminate_zone",
                       "gain": 1.03, "offset": "-1 N"}])
    (table,) = [t for t in line_tables(line) if t.key == "sensors"]
    assert table.rows == (("lc", "loadcell", "span laminate_zone", "1.03 x T - 1 N"),)
    assert not [t for t in line_tables(load_branched("laminator")) if t.key == "sensors"]


def test_a_state_feedback_drive_holds_its_loadcells_reading():
    """State feedback on every drive (docs/branching.md, "State feedback"), the film
    reference stepped 120 -> 130 N at 0.5 s, the film loadcell at gain 1.03: its reference
    tables are the readings', so the zone starts at 120 / 1.03 N and ends, 3.5 s on, with
    the reading at 130 N within 1e-4 N (the ideal line's: 130 - 8e-6 N), the web at
    130 / 1.03 N."""
    data = load_branched("laminator").spec.model_dump(exclude_none=True)
    data.pop("scenarios")
    for roller in data["rollers"]:
        if "controller" in roller:
            roller["controller"] = {"type": "state_feedback"}
    data["webs"][0]["spans"][1]["tension"] = {
        "type": "steps", "initial": 120.0, "steps": [{"time": 0.5, "value": 130.0}]}
    data["sensors"] = [{"name": "lc", "type": "loadcell", "span": "film_zone", "gain": 1.03}]
    result = webline.simulate(load_branched(data), 4.0)
    k = span(result, "film_zone")
    assert result.failure is None
    assert result.tension[0, k] == pytest.approx(FILM / 1.03, abs=1e-6)
    assert result.tension_measured[-1, k] == pytest.approx(130.0, abs=1e-4)
    assert result.tension[-1, k] == pytest.approx(130.0 / 1.03, abs=1e-4)


def test_a_fit_finds_the_nips_encoder_scale(tmp_path):
    """A record of the laminator whose master (nip) encoder reads 2 % high (1.5 s at
    150 m/min, 200 Hz, sensor noise ``synthetic.NOISE``): the nip's loop holds its reading on
    the reference, so the whole line runs 2 % slow; the fit of ``sensors.enc.scale`` from
    the file's ideal encoder finds 1.02 within 1 %."""
    from webline.twin.fitting.fit import fit
    from webline.twin.traces.synthetic import synthetic_csv

    line = laminator([{"name": "enc", "type": "encoder", "roller": "nip"}])
    path = synthetic_csv(tmp_path / "record.csv", line, changes={"sensors.enc.scale": 1.02},
                         duration=1.5, rate=200.0, seed=1)
    result = fit(line, path, {"sensors.enc.scale": "0.95 .. 1.05"}, starts=1)
    assert result.value[0] == pytest.approx(1.02, rel=0.01), result
    assert result.verdict.status == "good", result.verdict


def test_an_encoder_scale_and_delays_act_on_a_branched_line():
    """The nip's encoder 2 % high: its speed loop holds 1.02 v on the reference, so the
    laminate runs at 150 m/min / 1.02 from the start (the operating point knows it) and
    ``speed_measured`` shows the reference; the film loadcell 5 ms and the rewind's encoder
    2 ms late leave the start steady (their buffers start at the initial readings): the
    film zone's first five records (the delay) within 1e-8 N of its reference."""
    result = webline.simulate(laminator([
        {"name": "enc", "type": "encoder", "roller": "nip", "scale": 1.02},
        {"name": "lc", "type": "loadcell", "span": "film_zone", "delay": "5 ms"},
        {"name": "enc_rw", "type": "encoder", "roller": "rewind", "delay": "2 ms"}]), 0.3)
    nip = list(result.dataset.node.values).index("nip")
    speed = result.dataset.speed.values[:, nip]
    assert speed[0] == pytest.approx(2.5 / 1.02, rel=1e-9)
    assert np.max(np.abs(speed - 2.5 / 1.02)) < 1e-6
    assert np.max(np.abs(result.dataset.speed_measured.values[:, nip] - 2.5)) < 1.1e-6
    k = span(result, "film_zone")  # (a buffer started empty would read 0 N for 5 ms: the
    # PI would pull tens of newtons; the unwinding roll drifts the zone 9e-4 N in 0.3 s)
    assert np.max(np.abs(result.tension[:5, k] - FILM)) < 1e-8
    assert np.max(np.abs(result.tension[:, k] - FILM)) < 2e-3


def test_a_delay_beyond_the_modelled_samples_is_refused_on_the_cli(tmp_path):
    """40 ms at 1 kHz is 40 controller samples, beyond the 32 the loops model: one line
    naming the key, exit 2 (as the chain's, test_sensors.py)."""
    from importlib import resources

    from typer.testing import CliRunner

    from webline.cli import app

    text = resources.files("webline.data.lines").joinpath("laminator.toml").read_text("utf-8")
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("[[webs]]", '[[sensors]]\nname = "lc"\ntype = "loadcell"\n'
                                'span = "film_zone"\ndelay = "40 ms"\n\n[[webs]]', 1),
                   encoding="utf-8")
    result = CliRunner().invoke(app, ["run", str(bad), "-d", "0.01", "-o",
                                      str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "sensors[0].delay" in lines[0] and "at most 32" in lines[0], lines


@pytest.mark.parametrize("scale", [1.0, 1.02])
def test_the_linear_model_holds_the_masters_reading_on_the_line_speed(scale):
    """Closed loop, the steady gain from the line speed reference to the nip's surface
    speed, -C A⁻¹ B: the nip's speed loop integrates its encoder's error away, so the nip
    runs at the reference / scale (1 / 1.02 = 0.98039), to the solver's 1e-9."""
    from webline.sim.branches.equilibrium import operating_point
    from webline.sim.branches.linear import branch_linear_model
    from webline.sim.branches.plan import compile_branches

    plan = compile_branches(laminator([{"name": "enc", "type": "encoder", "roller": "nip",
                                        "scale": scale}]))
    model = branch_linear_model(plan, operating_point(plan), "closed")
    b = model.b[:, model.inputs.index("line_speed_ref")]
    row = model.c[model.outputs.index("nip_speed")]
    assert max(np.linalg.eigvals(model.a).real) < 0.0
    assert row @ np.linalg.solve(model.a, -b) == pytest.approx(1.0 / scale, abs=1e-9)


def test_loadcells_one_zone_sums_take_one_delay():
    """The slitter's shaft sums its lanes' loadcells and its loop delays that sum: two
    delays in one zone are refused naming the key; one delay for both is taken."""
    from webline.sim.branches.plan import compile_branches

    def sensors(second):
        return [{"name": "a", "type": "loadcell", "span": "lane_1_span", "delay": "3 ms"},
                {"name": "b", "type": "loadcell", "span": "lane_2_span", "delay": second}]

    slitter = load_branched("slitter")
    with pytest.raises(LineFileError, match=r"sensors\[1\]\.delay: the zone of "
                       r"'rewind_shaft' sums this loadcell with 'a'"):
        compile_branches(slitter.replace({"sensors": sensors("2 ms")}))
    plan = compile_branches(slitter.replace({"sensors": sensors("3 ms")}))
    d = list(plan.line.drives).index(plan.line.node_index["rewind_shaft"])
    assert plan.df[d, B.D_TDELAY] == 3.0 and plan.offsets[B.O_SENSORS] == 1
