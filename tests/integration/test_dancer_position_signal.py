"""A dancer's carriage position is a result signal (``dancer_position[NAME] [m]`` in the CSV,
NetCDF and DataFrame), so a logged dancer position can be loaded, replayed and fitted like
any other signal (issue 24 item 1 lists it among the signals webline writes)."""

from __future__ import annotations

import numpy as np

import webline
from webline.twin import load_measurements
from webline.twin.replay import replay


def test_the_dancer_position_is_written_read_back_and_replayed(tmp_path) -> None:
    run = webline.simulate("rockwell", 2.0)  # longer than 5 loop time constants
    index = run.plan.state_names.index("dancer.position")
    assert np.array_equal(run.dancer_position[:, 0], run.states[:, index])  # the state itself
    path = run.to_csv(tmp_path / "results.csv")
    header = path.read_text(encoding="utf-8").splitlines()[0].split(",")
    assert "dancer_position[dancer] [m]" in header
    data = load_measurements(path, "rockwell")
    assert "dancer_position[dancer]" in data.to_dataframe().columns
    frame = replay("rockwell", path).metrics.set_index("signal")
    # the run's own log replays to the CSV's rounding: far below a position sensor's 0.1 mm
    assert frame.loc["dancer_position[dancer]", "max_abs"] < 1e-7  # m
