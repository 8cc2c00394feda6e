"""Study ``wound-roll-band`` (issue 38, Build item 5): a transient in the line is a band in the
roll, at the radius the simulated rewind roll had while the transient lasted; on the
converter and on a branched line, the laminator."""

from __future__ import annotations

import pytest

import webline
from webline.studies import STUDIES
from webline.studies.wound_roll_band import LAMINATE_ROLL, LAMINATE_STEP, LAMINATOR_RUN


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    return STUDIES["wound-roll-band"](tmp_path_factory.mktemp("wound-roll-band"), quick=True)


def test_each_transient_leaves_a_band_inside_the_radius_wound_during_it(study):
    runs = {row["run"] for row in study.table}
    assert runs == {"tension step 150-200-150 N", "speed change 300-150 m/min", LAMINATOR_RUN}
    for row in study.table:
        assert row["band"] in ("hard", "soft")
        assert row["peak_inside_transient"], row  # where it departs most: the transient's
        if row["run"] == LAMINATOR_RUN:  # (its hard band reaches below: the test below)
            continue
        assert row["band_inside_transient"], row  # the converter's film: the whole band
        # wound while the transient lasted (its times from the rewind tension, not the roll)
        assert row["transient_from_s"] <= row["wound_from_s"] <= row["transient_to_s"] + 1e-3
    step = [row for row in study.table if row["run"].startswith("tension step")]
    # the step raises the tension: the band it leaves is hard (hoop above the steady roll's)
    assert [row["band"] for row in step] == ["hard"]
    assert step[0]["wound_from_s"] == pytest.approx(4.0, abs=0.2)


def test_the_summary_says_what_the_table_says(study):
    assert study.summary.count("inside the radius") == len(study.table)
    assert "OUTSIDE" not in study.summary
    assert len(study.figures) == 3 and all(path.exists() for path in study.figures)


def test_the_laminates_band_reaches_below_the_step_as_its_stiffness_says(study):
    """On the laminator (a branched line) the laminate's step 180 -> 240 N at 4 s leaves a
    hard band at the radius wound during it (its peak), but the band reaches below that
    radius: the laminate's in-plane modulus (22.9 GPa, the foil's) makes the layers under the
    band lose hoop stress to its extra pressure by more than 5 % of their wound-on stress
    (each layer's hoop change under a pressure change scales with g = sqrt(E_t / E_r)). With
    the film's modulus (4.5 GPa, ``tangential_modulus``) the same run's band lies inside."""
    (hard,) = [r for r in study.table if r["run"] == LAMINATOR_RUN and r["band"] == "hard"]
    assert hard["wound_from_s"] < 4.0 - 1.0  # layers wound at the steady 180 N
    assert hard["band_from_mm"] < hard["transient_radius_from_mm"] - 0.2
    soft_film = webline.simulate(webline.load_line("laminator").replace({
        "rollers.rewind.roll_stress": {**LAMINATE_ROLL, "tangential_modulus": "4.5 GPa"},
        "webs.laminate.spans.laminate_zone.tension": LAMINATE_STEP}), 8.0)
    bands = [f for f in soft_film.wound_roll.findings() if f.kind == "roll_band"]
    film_hard = [f for f in bands if f.details["hoop_departure"] > 0]
    assert len(film_hard) == 1
    r0, r1 = film_hard[0].details["radius_m"]
    assert 1e3 * r0 >= hard["transient_radius_from_mm"] - 0.032  # one 32 um layer
    assert 1e3 * r1 <= hard["transient_radius_to_mm"] + 0.064
