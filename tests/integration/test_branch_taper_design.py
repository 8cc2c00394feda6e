"""``webline taper --roll`` on a branched line (docs/wound-roll.md, "Branched lines"): the
slitter's shaft taper designed for lane_1's roll meets the roll's limits in the simulated
lane's roll, a smaller taper breaks them; a line of several rolls needs ``--roll``."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app

# PET film stack (Pfeiffer K1, K2 as the chain's test), fibre core, a 0.4 m roll and a
# stated hoop compression limit of 0.4 MPa (50 um film on a 76 mm core needs it: no taper
# up to 0.9 keeps 0.2 MPa)
ROLL = (
    '{k1 = "1.5 kPa", k2 = 120, core = {modulus = "3 GPa", inner_radius = "70 mm"}, '
    'min_hoop = "-0.4 MPa", diameter = "0.4 m"}'
)
LANE = "rewind_shaft/lane_1"


def _taper(out: str, *more: str) -> object:
    return CliRunner().invoke(app, ["taper", "slitter", "--set",
                                    f"rollers.rewind_shaft.roll_stress={ROLL}", "-o", out,
                                    "--duration", "2 s", *more])


@pytest.fixture(scope="module")
def designed(tmp_path_factory: pytest.TempPathFactory) -> tuple[object, str]:
    out = str(tmp_path_factory.mktemp("taper") / "slitter-taper.toml")
    return _taper(out, "--roll", LANE), out


def test_designed_shaft_taper_meets_the_lanes_limits(designed) -> None:
    run, out = designed
    assert run.exit_code == 0, run.output
    assert run.output.startswith(f"{LANE}: roll 76.2-200 mm of 50 um web at 100 N")
    assert "meets the limits" in run.output
    line = webline.load_line(out)  # the file runs as it is, a branched line
    assert line.branched
    taper = line.spec.rollers[line.node_index["rewind_shaft"]].taper
    assert taper is not None and 0.0 < taper.taper < 0.9
    roll = webline.simulate(line, 2.0).wound_rolls[LANE]
    assert not [f for f in roll.findings() if f.kind in ("roll_hoop", "roll_pressure")]
    assert roll.stress.hoop.min() >= -0.4e6


def test_a_smaller_shaft_taper_breaks_them(designed) -> None:
    _, out = designed
    line = webline.load_line(out)
    less = line.replace({"rollers.rewind_shaft.taper.taper":
                         line.spec.rollers[line.node_index["rewind_shaft"]].taper.taper - 0.05})
    result = webline.simulate(less, 2.0)
    (hoop,) = [f for f in result.wound_rolls[LANE].findings() if f.kind == "roll_hoop"]
    assert hoop.details["min_hoop_Pa"] < -0.4e6
    assert any(f.kind == "roll_hoop" and f.where == "lane_1" for f in result.verdict.findings)


@pytest.mark.parametrize(("roll", "says"), [
    ([], "slitter winds several rolls (rewind_shaft/lane_1, rewind_shaft/lane_2, "
         "rewind_3/lane_3): choose one with --roll ROLLER/WEB"),
    (["--roll", "rewind_9"], "--roll 'rewind_9': no rewound roll of slitter by that name"),
    (["--roll", "rewind_shaft"], "choose one with --roll"),  # a shaft of two lanes
    (["--roll", "rewind_3"], "rollers.rewind_3.roll_stress: the rewind needs a roll_stress"),
])
def test_which_roll_is_one_clear_line(roll: list[str], says: str, tmp_path) -> None:
    run = _taper(str(tmp_path / "x.toml"), "--no-check", *roll)
    assert run.exit_code == 2, run.output
    assert says in run.output and "Traceback" not in run.output
