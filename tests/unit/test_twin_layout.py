"""The twin's view of a branched line (``twin.traces.layout``): the signal names its runs
write load as they are, a wrong one is refused in one line with the branched name to use,
and the logged references drive it at the branched file's paths."""

from __future__ import annotations

import pandas as pd
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.twin.traces.drive import driven_line
from webline.twin.traces.layout import layout
from webline.twin.traces.measurements import load_measurements
from webline.twin.traces.read import MeasurementError


@pytest.fixture(scope="module")
def slitter_csv(tmp_path_factory):
    """One second of the slitter (5 time constants of its slowest loop: 0.625 s) as its run
    writes it."""
    return webline.simulate("slitter", 1.0).to_csv(tmp_path_factory.mktemp("s") / "run.csv")


def test_the_layout_of_a_branched_line_names_what_its_runs_record():
    view = layout(webline.load_line("slitter"))
    assert view.master == "pull"
    assert view.elements["roll"] == ("unwind/base", "rewind_shaft/lane_1",
                                     "rewind_shaft/lane_2", "rewind_3/lane_3")
    assert [(p.span, p.value, p.path) for p in view.set_points] == [
        ("unwind_zone", 300.0, "webs.base.spans.unwind_zone.tension"),
        ("lane_1_span", 100.0, "webs.lane_1.spans.lane_1_span.tension"),
        ("lane_2_span", 100.0, "webs.lane_2.spans.lane_2_span.tension"),
        ("lane_3_span", 100.0, "webs.lane_3.spans.lane_3_span.tension")]
    # the shaft's two lanes share their roller's radius in the file: no path of their own
    assert [r.path for r in view.rolls] == ["rollers.unwind.radius", "", "",
                                            "rollers.rewind_3.radius"]


def test_a_branched_runs_own_file_loads_and_its_logged_radii_drive_it(slitter_csv, tmp_path):
    frame = pd.read_csv(slitter_csv)
    frame["radius[rewind_3/lane_3] [m]"] = 0.1  # a fuller roll than the file's 0.08 m
    frame["radius[rewind_shaft/lane_1] [m]"] = 0.1
    path = tmp_path / "log.csv"
    frame.to_csv(path, index=False)
    data = load_measurements(path, "slitter")
    assert "tension[lane_1_span]" in data.signals and "speed[pull]" in data.signals
    assert "radius[unwind/base]" in data.signals
    driven = driven_line(data)
    view = layout(driven.line)
    assert {r.signal: r.radius for r in view.rolls}["radius[rewind_3/lane_3]"] == 0.1
    assert {r.signal: r.radius for r in view.rolls}["radius[rewind_shaft/lane_1]"] == 0.08
    assert any("radius[rewind_shaft/lane_1]: a lane on a shaft" in n for n in driven.notes)
    # no speed_ref in a run's file: the master's measured speed, reconstructed, drives it
    assert any(n.startswith("line speed: no speed reference logged") for n in driven.notes)


def test_a_single_path_name_on_a_branched_line_is_refused_with_the_branched_one(
        slitter_csv, tmp_path):
    frame = pd.read_csv(slitter_csv).rename(
        columns={"radius[rewind_3/lane_3] [m]": "radius[rewind_3] [m]"})
    path = tmp_path / "log.csv"
    frame.to_csv(path, index=False)
    with pytest.raises(MeasurementError) as info:
        load_measurements(path, "slitter")
    assert "'radius[rewind_3/lane_3]'" in str(info.value) and "\n" not in str(info.value)
    done = CliRunner().invoke(app, ["replay", "slitter", str(path), "-o", str(tmp_path / "o")])
    assert done.exit_code == 2 and "radius[rewind_3/lane_3]" in done.output, done.output
