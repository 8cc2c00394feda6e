"""Study ``wound-roll-band`` (issue 38, Build item 5): a transient in the line is a band in the
roll, at the radius the simulated rewind roll had while the transient lasted."""

from __future__ import annotations

import pytest

from webline.studies import STUDIES


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    return STUDIES["wound-roll-band"](tmp_path_factory.mktemp("wound-roll-band"), quick=True)


def test_each_transient_leaves_a_band_inside_the_radius_wound_during_it(study):
    runs = {row["run"] for row in study.table}
    assert runs == {"tension step 150-200-150 N", "speed change 300-150 m/min"}
    for row in study.table:
        assert row["band"] in ("hard", "soft")
        assert row["band_inside_transient"], row
        # wound while the transient lasted (its times from the rewind tension, not the roll)
        assert row["transient_from_s"] <= row["wound_from_s"] <= row["transient_to_s"] + 1e-3
    step = [row for row in study.table if row["run"].startswith("tension step")]
    # the step raises the tension: the band it leaves is hard (hoop above the steady roll's)
    assert [row["band"] for row in step] == ["hard"]
    assert step[0]["wound_from_s"] == pytest.approx(4.0, abs=0.2)


def test_the_summary_says_what_the_table_says(study):
    assert study.summary.count("inside the radius") == len(study.table)
    assert "OUTSIDE" not in study.summary
    assert len(study.figures) == 2 and all(path.exists() for path in study.figures)
