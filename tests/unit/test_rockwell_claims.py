"""The thesis-claim sentences of ``rockwell-rewind`` state only what their rows show: the
explanation of a "not reproduced" follows the numbers it quotes (studies.rockwell_claims)."""

from __future__ import annotations

from webline.studies.rockwell_claims import claims


def _mean_rows(share: float) -> list[dict]:
    row = {"part": "mean_tension", "speed_fpm": 300.0, "disturbance": "none",
           "tension_std_lbf": 0.1, "speed_std_fpm": 1.0, "speed_mean_fpm": 300.0,
           "motor_torque_min_N_m": 3.9}
    return [{**row, "backlash_mm": 0.0, "tension_mean_lbf": 10.0, "gap_open_fraction": 0.0},
            {**row, "backlash_mm": 0.5, "tension_mean_lbf": 10.001, "gap_open_fraction": share}]


def test_the_gap_is_said_never_to_open_only_when_it_never_did() -> None:
    (shut,) = [c for c in claims(_mean_rows(0.0)) if c.startswith("mean tension shift")]
    assert "not reproduced because the gap never opened" in shut
    (opened,) = [c for c in claims(_mean_rows(0.02)) if c.startswith("mean tension shift")]
    assert "never opened" not in opened and "the gap was open 2.0% of the time" in opened


def test_the_brake_is_said_to_close_the_gap_only_when_it_did() -> None:
    def brake(lbf_ft: float, share: float, amplification: float) -> dict:
        return {"part": "gap_brake", "brake_lbf_ft": lbf_ft, "gap_open_fraction": share,
                "amplification": amplification, "multiple_of_threshold": 1.25,
                "mean_shift_pct": 0.1, "mean_shift_pct_4_9": 0.1,
                "amplification_4_10": amplification}

    for share, said in ((0.0, "the brake closes the gap"), (0.01, "the brake narrows")):
        text = next(c for c in claims([brake(0.0, 0.1, 1.06), brake(10.0, share, 1.05)])
                if c.startswith("10 lbf ft brake"))
        assert said in text
