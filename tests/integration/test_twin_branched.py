"""Replay and fit on a branched line (issue 33 item 3, issue 36 item 10): the laminator's own
identification record (``webline experiment tension-step``, docs/commissioning.md) made on a
"true" laminator whose film is 12 % stiffer and whose nip roller is 20 % heavier than the
line file says, cut to its first step (the film zone's set point 120 -> 132 N at 1 s, back at
15 s) and logged with white sensor noise of known size.

The twin reads the record as it reads a single-path line's (the same loader, drive, replay
and fit): the true line replayed leaves the noise, the file's line does not, and the fit
finds the two changed values.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import webline
from webline.twin.traces.replay import Replay
from webline.twin.traces.synthetic import NOISE
from webline.twin.tuning.experiment_branched import write_branched_experiment

pytestmark = pytest.mark.slow

#: the line file's film EA [N] and nip inertia [kg m²] and the true machine's
FILE_EA, FILE_INERTIA = 103.5e3, 0.5
TRUE_EA, TRUE_INERTIA = 1.12 * FILE_EA, 1.2 * FILE_INERTIA
#: the record's length [s]: the film zone's step up and back (the other zones' steps follow)
CUT = 16.0
FREE = {"webs.film.web.ea": "50 .. 200 kN", "rollers.nip.inertia": "0.2 .. 1.5 kg*m**2"}


def truth() -> webline.BranchedLine:
    return webline.load_line("laminator").replace(
        {"webs.film.web.ea": TRUE_EA, "rollers.nip.inertia": TRUE_INERTIA})


@pytest.fixture(scope="module")
def record(tmp_path_factory) -> Path:
    """The experiment's results.csv (every 1 ms tick, references logged exactly, as a PLC
    logs them) cut at ``CUT``, its loadcells', encoders' and torques' columns with noise
    (``synthetic.NOISE``)."""
    folder = tmp_path_factory.mktemp("experiment")
    _, result = write_branched_experiment(truth(), "tension-step", folder)
    assert result.failure is None
    frame = pd.read_csv(folder / "results.csv")
    frame = frame[frame["time [s]"] <= CUT].copy()
    # what a machine logs: loadcells (the spans with a set point), encoders, drive torques
    cells = {c.replace("tension_ref[", "tension[") for c in frame if c.startswith("tension_ref[")}
    frame = frame[[c for c in frame if c.partition("[")[0] not in ("tension", "torque_cmd")
                   or c in cells]]
    rng = np.random.default_rng(7)
    for column in frame.columns:
        kind = column.partition("[")[0]
        if kind in NOISE:
            frame[column] += rng.normal(0.0, NOISE[kind], len(frame))
    path = folder / "record.csv"
    frame.to_csv(path, index=False, float_format="%.9g")
    return path


def rms_over_noise(replayed: Replay) -> dict[str, float]:
    """Each compared signal's RMS error over the noise added to it."""
    return {row.signal: row.rms / NOISE[row.signal.partition("[")[0]]
            for row in replayed.metrics.itertuples()}


def test_the_true_line_replayed_leaves_the_noise_and_the_files_line_does_not(record):
    """Replayed, the true laminator leaves each signal's noise: RMS error 0.97-1.03 x the
    noise added (16 001 points of white noise give its RMS to 0.56 %, so 5 standard errors;
    a model error of 0.3 x the noise would add 4.5 %). The file's laminator, softer film and
    lighter nip, misses the unwind's torque at the film's step (the unwound web's strain
    sets the roll's speed, so its torque, through EA; more than 3 x the noise) and the nip's
    torque as the steps move the nip's load (more than 1.1 x)."""
    true = rms_over_noise(webline.replay(truth(), record))
    assert {"tension", "speed", "torque"} <= {name.partition("[")[0] for name in true}
    assert len(true) == 3 + 7 + 4  # loadcell spans, rollers, drives
    for signal, ratio in true.items():
        assert 0.97 < ratio < 1.03, (signal, ratio)
    files = rms_over_noise(webline.replay("laminator", record))
    assert files["torque[unwind_film]"] > 3.0, files
    assert files["torque[nip]"] > 1.1 * true["torque[nip]"], files


def test_fit_finds_the_films_ea_and_the_nips_inertia(record):
    """From the file's values, the fit of the film's EA and the nip's inertia reaches the noise
    (residual scale 0.9-1.1) and finds both within 1 % of the truth and inside their 95 %
    intervals, with the verdict good: the same fit as on a single-path line, its paths the
    branched line file's (``webs.NAME.web.ea``)."""
    fitted = webline.fit("laminator", record, FREE, starts=1)
    assert fitted.verdict.status == "good", fitted
    assert 0.9 < fitted.residual_scale < 1.1, fitted
    for i, true in enumerate((TRUE_EA, TRUE_INERTIA)):
        assert fitted.value[i] == pytest.approx(true, rel=0.01), fitted
        assert fitted.ci95[i, 0] <= true <= fitted.ci95[i, 1], fitted
    # the fitted line is the file's branched line with the two values set
    assert fitted.fitted_line.branched
    assert fitted.fitted_line.materials[0].ea == pytest.approx(fitted.value[0], rel=1e-12)
