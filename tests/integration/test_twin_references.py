"""A log without the speed reference (issue 36 item 4, "Must show"): the reference is
reconstructed from the master's measured speed as the ramps the PLC commanded, and the fit
of the converter's five parameters comes back as from the same log with the reference,
within 5 % on every parameter (with the measured speed as the reference, 50 ms means, the
modulus came back 40 % off and the dancer damping on its bound)."""

from __future__ import annotations

import pytest

import webline
from webline.twin import load_measurements
from webline.twin.fitting.fit import fit
from webline.twin.traces.synthetic import synthetic_csv

TRUTH = {
    "rollers.infeed.inertia": 0.7,
    "rollers.chill.inertia": 2.4,
    "rollers.drum.friction": 0.09,
    "web.modulus": 3.3e9,
    "rollers.dancer.dancer.damping": 700.0,
}
FREE = {
    "rollers.infeed.inertia": "0.1 .. 2 kg*m**2",
    "rollers.chill.inertia": "0.5 .. 8 kg*m**2",
    "rollers.drum.friction": "0.005 .. 0.5 N*m*s",
    "web.modulus": "2 .. 6 GPa",
    "rollers.dancer.dancer.damping": "100 .. 3000 N*s/m",
}


def test_a_log_without_speed_ref_fits_as_one_with_it(tmp_path):
    line = webline.load_line("converter").with_scenario("startup")
    path = synthetic_csv(
        tmp_path / "log.csv", "converter", changes=TRUTH, duration=10.0, scenario="startup", seed=5
    )
    with_ref = fit(line, load_measurements(path, line), FREE, starts=2)
    without = load_measurements(path, line, mapping={"speed_ref[drum]": ""})
    assert "speed_ref[drum]" not in without.signals
    result = fit(line, without, FREE, starts=2)
    assert result.verdict.good, result
    for i, p in enumerate(result.parameters):
        assert result.value[i] == pytest.approx(with_ref.value[i], rel=0.05), p.path
    # the reference was reconstructed, and the replay says how
    from webline.twin.traces.replay import replay

    notes = replay(line, without).notes
    assert "reconstructed from speed[drum]" in notes[0] and "linear segments" in notes[0]


@pytest.mark.parametrize("name", ["converter", "laminator"])
def test_an_experiments_own_ramp_record_replays_exactly(name, tmp_path):
    """``webline experiment accel-ramps`` writes its speed reference as a 9-digit CSV, whose
    rounding bends the ramps' second differences by 2e-9 of the top speed on every tick; the
    replay's table keeps only the real corners (1.1e-4 on the converter), so the line
    replays its own record, torques included, to 1e-6 of each torque's range (with a corner
    on every tick it fell back to 2 000 bin means, and the unwind's torque missed the ramps'
    corners by 24 N·m on the converter, 11 N·m on the laminator)."""
    from typer.testing import CliRunner

    from webline.cli import app

    done = CliRunner().invoke(app, ["experiment", name, "accel-ramps", "--out", str(tmp_path)])
    assert done.exit_code == 0, done.output
    line = webline.load_line(name)
    replayed = webline.replay(line, tmp_path / "results.csv")
    torques = replayed.metrics[replayed.metrics.signal.str.startswith("torque[")]
    assert len(torques) == len(line.drives)
    assert (torques.nrmse < 1e-6).all(), torques
