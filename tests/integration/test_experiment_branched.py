"""`webline experiment` on a branched line (issue 26 item 2; docs/branching.md, "Tuning a
branched line"): the chain's identification tests on the laminator's drives and zones, and
what they identify read back from the traces they write."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from typer.testing import CliRunner

from webline.cli import app


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def window(df: pd.DataFrame, column: str, start: float, end: float) -> float:
    t = df["time [s]"].values
    return float(df[column].values[(t >= start) & (t < end)].mean())


def test_tension_step_on_laminator_identifies_each_webs_ea(tmp_path):
    """A 10 % step of a zone's set point changes the steady draw between the unwind and the
    nip by ΔT/EA (mass balance of the span at the unwind, whose wound-in strain is fixed:
    v_u/v_nip = (1 + ε_w)/(1 + T/EA)); the film's and foil's EA from the traces within 1 %
    (first-order in ε = T/EA ~ 1e-3; what the hold's end leaves of the transient)."""
    out = tmp_path / "e"
    result = invoke("experiment", "laminator", "tension-step", "-o", str(out))
    assert result.exit_code == 0, result.output
    plan = json.loads((out / "experiment.json").read_text())
    # three zones, each ramped in 50 ms and held 8.5 s (settled to 1 % of the draw's
    # change in 8.1-8.4 s), twice
    assert plan["duration_s"] == 52.0
    assert plan["logging_rate_hz"] == 1000.0
    df = pd.read_csv(out / "results.csv")
    for zone, unwind, ea, (start, end) in (("film_zone", "unwind_film", 103.5e3, (1, 9.5)),
                                           ("foil_zone", "unwind_foil", 630e3, (18, 26.5))):
        tension = f"tension[{zone}] [N]"
        step = window(df, tension, end - 1, end) - window(df, tension, start - 0.5, start)

        def draw(a: float, b: float, unwind: str = unwind) -> float:
            return 1 - (window(df, f"speed[{unwind}] [m/s]", a, b)
                        / window(df, "speed[nip] [m/s]", a, b))

        change = draw(end - 1, end) - draw(start - 0.5, start)
        assert step == pytest.approx(0.1 * (120 if zone == "film_zone" else 60), rel=1e-3)
        assert step / change == pytest.approx(ea, rel=0.01)
    assert (out / "traces.png").exists()


def test_accel_ramps_on_laminator_identify_the_nips_inertia(tmp_path):
    """Mid-ramp the nip's torque carries J a / r above the mean of its torques at rest and
    at the next hold (its viscous friction is linear in speed, and mid-ramp is mid-speed):
    J from the traces within 2 % of the file's 0.5 kg·m² (the zones' tension errors during
    the ramp move the nip's torque by < 0.01 N·m of the 2.1 N·m inertial term)."""
    out = tmp_path / "e"
    result = invoke("experiment", "laminator", "accel-ramps", "-o", str(out))
    assert result.exit_code == 0, result.output
    assert "each ramp 2 s" in result.output  # v/3 = 0.833 m/s at a = 0.417 m/s²
    df = pd.read_csv(out / "results.csv")
    accel, radius = (2.5 / 3) / 2.0, 0.1
    column = "torque[nip] [N*m]"
    inertial = window(df, column, 1.75, 2.25) - 0.5 * (
        window(df, column, 0.5, 1.0) + window(df, column, 6.0, 7.0))
    assert inertial * radius / accel == pytest.approx(0.5, rel=0.02)
    assert np.isfinite(df.values).all()


def test_dancer_step_on_a_line_without_dancer_is_one_line_exit_2():
    result = invoke("experiment", "laminator", "dancer-step")
    assert result.exit_code == 2, result.output
    assert result.output.strip() == "error: laminator: dancer-step: the line has no dancer"


def test_dancer_step_on_a_branched_line_steps_its_zones_tension(tmp_path):
    """The laminator with its film guide a dancer in position control (the dancer tests'
    line): dancer-step raises the load 10 %, and the film zone's tension, the load over the
    dancer's two strands, follows it by 10 % (1e-3: the position loop has settled by the
    hold's end); tension-step leaves the dancer's zone to it."""
    import tomllib
    from importlib import resources

    from webline.model.web_graph import load_branched
    from webline.twin.tuning.experiment_branched import tension_step, write_branched_experiment

    data = tomllib.loads(resources.files("webline.data.lines").joinpath("laminator.toml")
                         .read_text("utf-8"))
    guide = data["rollers"][1]  # guide_film, between the film unwind and the nip
    guide["type"] = "dancer"
    guide["dancer"] = {"mass": "5 kg", "travel": "0.2 m", "position": "0.1 m"}
    line = load_branched(data)
    plan, result = write_branched_experiment(line, "dancer-step", tmp_path)
    assert result.failure is None
    assert plan.derivation[0].startswith("guide_film: load 240 -> 264 N at 1 s")
    df = pd.read_csv(tmp_path / "results.csv")
    hold = plan.duration / 2 - 0.5
    before = window(df, "tension[film_zone] [N]", 0.5, 1.0)
    after = window(df, "tension[film_zone] [N]", 1.0 + hold - 0.5, 1.0 + hold)
    assert after / before == pytest.approx(1.1, rel=1e-3)
    assert "dancer_position[guide_film] [m]" in df.columns
    assert not any("film_zone" in text for text in tension_step(line).derivation)
