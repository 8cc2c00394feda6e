"""``webline taper`` on a branched line (docs/wound-roll.md, "Branched lines"): the slitter's
shaft taper designed for lane_1's roll (``--roll``) meets the roll's limits in the simulated
lane's roll, a smaller taper breaks them; designed for the shaft (no ``--roll``) with its
lanes at 100 and 90 N, it meets the limits on both lanes in the run, and the less loaded
lane's own taper breaks them on the other lane; rolls on several rewinds need ``--roll``."""

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
ROLL_TABLE = {"k1": "1.5 kPa", "k2": 120, "core": {"modulus": "3 GPa", "inner_radius": "70 mm"},
              "min_hoop": "-0.4 MPa", "diameter": "0.4 m"}
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


# lane_2 set 10 % below lane_1 (90 N against 100 N: the shaft's drive holds their sum, 190 N)
LESS = "webs.lane_2.spans.0.tension=90 N"


@pytest.fixture(scope="module")
def shaft(tmp_path_factory: pytest.TempPathFactory) -> tuple[object, str]:
    out = str(tmp_path_factory.mktemp("shaft") / "slitter-shaft.toml")
    return _taper(out, "--set", LESS), out  # no --roll: the shaft, both its lanes


def test_shaft_taper_meets_every_lanes_limits(shaft) -> None:
    """One taper for the shaft: lane_1 (100 N, the more loaded) binds, as alone (0.797, as
    the lane_1 design above); lane_2 (90 N) keeps a margin; both checked in the run."""
    run, out = shaft
    assert run.exit_code == 0, run.output
    assert "rewind_shaft/lane_2: roll 76.2-200 mm of 50 um web at 90 N" in run.output
    assert "hyperbolic: taper 0.797" in run.output
    assert "rewind_shaft/lane_1: alone 0.797; hoop margin" in run.output
    assert "(binds)" in run.output.split("rewind_shaft/lane_1: alone")[1].split("\n")[0]
    lane_2 = run.output.split("rewind_shaft/lane_2: alone ")[1].split("\n")[0]
    assert float(lane_2.split(";")[0]) < 0.797 and "(binds)" not in lane_2
    for lane in ("rewind_shaft/lane_1", "rewind_shaft/lane_2"):
        assert f"{lane}: min hoop" in run.output
    assert "breaks them" not in run.output
    line = webline.load_line(out)
    result = webline.simulate(line, 2.0)
    for lane in ("rewind_shaft/lane_1", "rewind_shaft/lane_2"):
        roll = result.wound_rolls[lane]
        assert roll.stress.hoop.min() >= -0.4e6, lane
        assert not [f for f in roll.findings() if f.kind in ("roll_hoop", "roll_pressure")]


def test_the_less_loaded_lanes_own_taper_breaks_the_other_lane(shaft) -> None:
    """The taper designed for lane_2 alone (the least loaded lane) winds lane_1 too soft:
    hoop below -0.4 MPa in lane_1's simulated roll (a ``roll_hoop``), well below lane_2's."""
    from webline.analysis.roll_taper import design_taper, with_taper

    _, out = shaft
    line = webline.load_line(out)
    alone = design_taper(line, roll="rewind_shaft/lane_2")[0]
    assert alone.taper is not None and alone.taper < 0.797 - 0.1
    result = webline.simulate(with_taper(line, alone, roll="rewind_shaft/lane_2"), 2.0)
    rolls = result.wound_rolls
    (hoop,) = [f for f in rolls["rewind_shaft/lane_1"].findings() if f.kind == "roll_hoop"]
    assert hoop.details["min_hoop_Pa"] < -0.4e6
    # lane_2 sits on its own limit (its binding taper; the run's layers, wound at the
    # shaft's common 95 N, may tip it by a few %), lane_1 well past it
    assert hoop.details["min_hoop_Pa"] < rolls["rewind_shaft/lane_2"].stress.hoop.min() - 0.03e6


def test_shaft_taper_is_the_largest_lane_taper() -> None:
    """The design's rule on the steady rolls, without a run: the shaft's taper is the larger
    of the lanes' own, the binding lane's hoop margin is the smaller (at or above zero),
    and 0.05 less taper breaks the binding lane's limit, not the other's."""
    from webline.analysis.roll_taper import design_rolls, least_taper

    line = webline.load_line("slitter").replace({
        "rollers.rewind_shaft.roll_stress": ROLL_TABLE,
        "webs.lane_2.spans.0.tension": "90 N"})
    designs = design_rolls(line)
    assert [d.roll_name for d in designs] == ["rewind_shaft/lane_1", "rewind_shaft/lane_2"]
    both = least_taper(designs, "hyperbolic")
    one = [least_taper(d, "hyperbolic").taper for d in designs]
    assert both.taper == max(one) and both.binding == "rewind_shaft/lane_1"
    lane_1, lane_2 = both.lanes
    assert 0.0 <= lane_1.margins["hoop"] < lane_2.margins["hoop"]
    less = both.taper - 0.05  # a smaller shaft taper breaks lane_1's hoop limit only
    assert [bool(d.limits.violations(d.roll("hyperbolic", less))) for d in designs] == [
        True, False]


@pytest.mark.parametrize(("roll", "says"), [
    (["--set", "rollers.rewind_3.roll_stress={k1 = \"1.5 kPa\", k2 = 120}"],
     "slitter winds rolls on several rewinds (rewind_shaft/lane_1, rewind_shaft/lane_2, "
     "rewind_3/lane_3): choose one with --roll REWIND (all its lanes) or --roll ROLLER/WEB"),
    (["--roll", "rewind_9"], "--roll 'rewind_9': no rewound roll of slitter by that name"),
    (["--roll", "rewind_3"], "rollers.rewind_3.roll_stress: the rewind needs a roll_stress"),
])
def test_which_roll_is_one_clear_line(roll: list[str], says: str, tmp_path) -> None:
    run = _taper(str(tmp_path / "x.toml"), "--no-check", *roll)
    assert run.exit_code == 2, run.output
    assert says in run.output and "Traceback" not in run.output


def test_naming_the_shaft_designs_for_its_lanes_and_one_lane_beyond_reach_fails_it(
        tmp_path) -> None:
    """``--roll rewind_shaft`` is the shaft (both lanes, as without --roll); with lane_2 at
    130 N no hyperbolic taper up to 0.9 keeps lane_2's hoop above -0.4 MPa, though lane_1
    alone has one (0.797): the shaft has none, lane_2 named as the one breaking, exit 1."""
    run = _taper(str(tmp_path / "x.toml"), "--no-check", "--roll", "rewind_shaft",
                 "--set", "webs.lane_2.spans.0.tension=130 N")
    assert run.exit_code == 1, run.output
    assert "rewind_shaft/lane_1: roll" in run.output and "rewind_shaft/lane_2: roll" in run.output
    (hyperbolic,) = [x for x in run.output.splitlines() if x.startswith("hyperbolic:")]
    assert "no taper up to 0.9" in hyperbolic and "rewind_shaft/lane_2: hoop" in hyperbolic
    assert "rewind_shaft/lane_1" not in hyperbolic
    assert not (tmp_path / "x.toml").exists()
