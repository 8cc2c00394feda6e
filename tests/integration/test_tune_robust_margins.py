"""Issue 36, item 8: tuning's robustness draws are checked against the same margin and
damping limits as the nominal tuned line, not only for stability.

The case: a fit of hswl's rewind torque lag returns the file's 2 ms with an honest, wide
interval (1.5 ms standard error). The phase margin of the rewind's loop falls with the lag
(``stability_constraints`` on hswl: 45.3° at 1 ms, 40.1° at 2 ms, 35.1° at 2.65 ms, 29.8° at
3 ms), so the draws that put the lag where the truth may be (above 2.66 ms: a third of the
truncated normal) miss a 35° limit the nominal line meets. The robustness check must fail
and name the phase margin; with a narrow interval (50 µs: ±0.3°) every draw meets it.
"""

from __future__ import annotations

import json

import pytest

from webline.twin.tuning.tune import tune
from webline.twin.tuning.tune_constraints import Limits
from webline.twin.tuning.tune_output import tune_json
from webline.twin.tuning.tune_robust import fit_uncertain

LAG = "rollers.rewind.drive.torque_lag"
PHASE = "phase margin [deg]"
#: hswl as given has a controlled mode damped 0.22 and a 40.07° phase margin: limits it meets
LIMITS = Limits(phase_margin_deg=35.0, min_damping=0.1)
#: 20 draws: a third missing is 7 expected, 3 or more with 99 % (binomial), above the 2
#: the required 90 % allows
DRAWS = 20


def _tune_on_fit(tmp_path, stderr: float):
    """``tune`` of hswl as it is (one candidate: the line) on its 10 s tension step, the
    robustness draws from a good fit of the rewind's lag at 2 ms with ``stderr`` [s]."""
    path = tmp_path / "fit.json"
    path.write_text(json.dumps({"verdict": "good", "parameters": {
        LAG: {"value": 0.002, "stderr": stderr, "bounds": [0.0005, 0.02]}}}))
    dists, _ = fit_uncertain(path)
    return tune("hswl", ["tension-step"], constraints=LIMITS, uncertain=dists,
                samples=DRAWS, seed=3, evaluations=1)


def test_wide_lag_interval_fails_the_robust_phase_margin(tmp_path) -> None:
    result = _tune_on_fit(tmp_path, 0.0015)
    nominal = {c.name: c for c in result.after.constraints}
    assert result.after.feasible, [c for c in result.after.constraints if not c.holds]
    assert nominal[PHASE].value == pytest.approx(40.07, abs=0.05)
    check = result.robust
    assert not check.holds and not result.holds
    # the failing draws say which margin they miss, and by how much
    assert any(PHASE in r for r in check.reasons), check.reasons
    worst = {c.name: c for c in check.worst}
    assert set(nominal) <= set(worst)  # every nominal constraint is checked on the draws
    assert not worst[PHASE].holds and worst[PHASE].value < LIMITS.phase_margin_deg
    assert worst[PHASE].value < nominal[PHASE].value
    missed = check.missing[PHASE]
    assert DRAWS - check.passed >= missed >= 3
    data = tune_json(result)["robustness"]
    entry = next(e for e in data["worst_over_draws"] if e["name"] == PHASE)
    assert entry["holds"] is False and entry["draws_missing"] == missed


def test_narrow_lag_interval_passes(tmp_path) -> None:
    result = _tune_on_fit(tmp_path, 0.00005)
    check = result.robust
    assert check.holds and check.passed == DRAWS, check.reasons
    worst = {c.name: c for c in check.worst}
    # ±2.5 standard errors of 50 µs move the margin by about ±0.7°
    assert worst[PHASE].holds
    assert worst[PHASE].value == pytest.approx(40.07, abs=1.0)
