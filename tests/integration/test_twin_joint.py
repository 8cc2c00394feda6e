"""Several experiments in one fit (issue 36 item 2, "Must show"): hswl with five parameters
changed, an accel-ramps record (inertia, friction, the rewind's torque lag show in the drive
torques of a ramp) and a tension-step record (the web's EA in the draw a step of a zone's
set point needs, the span's length in its transient), each from ``webline experiment``'s
plan run on the true line with sensor noise; fitted jointly from the line file, with each
record its own scenario (its own references), the five come back within 5 % and inside
their 95 % intervals."""

from __future__ import annotations

import pytest

from webline.line import load_line
from webline.twin.fitting.fit import fit
from webline.twin.traces.synthetic import synthetic_csv
from webline.twin.tuning.experiment import plan_experiment

#: the true line: five values of hswl's file changed by 16-50 % (the file: 0.0843 kg m²,
#: 0.678 N m s, 2 ms, 8896 N, 6.10 m); the lag stays below the ~5.4 ms where the rewind's
#: tension loop starts its limit cycle
TRUTH = {
    "rollers.process.inertia": 0.11,
    "rollers.master.friction": 1.0,
    "rollers.rewind.drive.torque_lag": 0.004,
    "web.ea": 7500.0,
    "spans.span1.length": 7.0,
}
FREE = {
    "rollers.process.inertia": "0.01 .. 0.5 kg*m**2",
    "rollers.master.friction": "0.05 .. 3 N*m*s",
    "rollers.rewind.drive.torque_lag": "0.5 .. 20 ms",
    "web.ea": "4000 .. 20000 N",
    "spans.span1.length": "3 .. 15 m",
}
#: seconds of each record: the accel-ramps test's rest, first ramp and part of its hold;
#: the tension-step test's rest and the first zone's step (span 1, at 1 s) with its
#: transient (the unwind's tension loop settles in ~0.6 s; the span's L/v is ~2.4 s)
SECONDS = 6.0


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """(the line, the two records' paths) of the two experiments on the true line, 1 kHz."""
    line = load_line("hswl")
    folder = tmp_path_factory.mktemp("joint")
    paths = []
    for seed, name in enumerate(("accel-ramps", "tension-step")):
        plan = plan_experiment(line, name)
        paths.append(synthetic_csv(folder / f"{name}.csv", plan.line, changes=TRUTH,
                                   duration=min(SECONDS, plan.duration), rate=1000.0,
                                   seed=10 + seed))
    return line, paths


def test_joint_fit_of_two_experiments_gives_five_parameters(records):
    """Each record is driven by its own logged references (the ramps' speed, the step's
    tension set point): the line file, no scenario, serves both."""
    line, paths = records
    result = fit(line, paths, FREE, starts=4)
    assert [r.label for r in result.records] == ["accel-ramps.csv", "tension-step.csv"]
    assert result.identifiable.all(), result
    for i, p in enumerate(result.parameters):
        truth = TRUTH[p.path]
        assert result.value[i] == pytest.approx(truth, rel=0.05), (p.path, result)
        assert result.ci95[i, 0] <= truth <= result.ci95[i, 1], (p.path, result)
    # each record at its own noise floor (white noise of the estimated levels: ~1 ± 0.15)
    for record in result.records:
        assert 0.8 < record.residual_scale < 1.2, (record.label, result)
    assert result.verdict.good, result
