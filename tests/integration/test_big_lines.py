"""Big lines cost in proportion (issue 22 item 7): beyond ``DETAILED_SPANS`` spans the report
draws summaries whose size does not grow with the spans, condenses its tables, and computes
no modes of a model beyond ``MAX_MODE_STATES`` states, saying so."""

from __future__ import annotations

import io
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image as PILImage

import webline
from webline.report.big_lines import DETAILED_SPANS, TABLE_ENDS, condensed
from webline.report.display import Display
from webline.report.figures import figure_jobs
from webline.report.tables import summary_tables
from webline.report.writer import MAX_MODE_STATES, analyse, write_report

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from long_line import long_line


def _pixels(result) -> dict[str, tuple[int, int]]:
    """Pixel size of each report figure of ``result`` at 40 dpi (small: fast to draw)."""
    sizes = {}
    for job in figure_jobs(result, Display("si", result.line.spec.web.width)):
        for fig in job():
            buffer = io.BytesIO()
            fig.figure.savefig(buffer, format="png", dpi=40)
            sizes[fig.key] = PILImage.open(buffer).size
    return sizes


@pytest.fixture(scope="module")
def runs():
    """0.2 s of a 30-span and of a 90-span line (both beyond DETAILED_SPANS)."""
    return [webline.simulate(long_line(pairs), 0.2) for pairs in (14, 44)]


def test_the_figures_of_a_long_line_do_not_grow_with_its_spans(runs) -> None:
    small, large = runs
    assert DETAILED_SPANS < small.line.n_spans < large.line.n_spans
    a, b = _pixels(small), _pixels(large)
    assert a.keys() == b.keys() and {"schematic", "tension", "speed", "torque"} <= a.keys()
    for key in a:  # the same pixels: the drawing's cost no longer scales with the spans
        assert a[key] == b[key], key
    # a per-span tension figure of 90 spans would be 1.6 in per span: 144 in at 40 dpi
    assert b["tension"][1] < 12 * 40


def test_a_short_line_keeps_a_figure_per_span() -> None:
    run = webline.simulate("hswl", 0.2)
    # hswl's 4 spans: one axes per span, 1.3 + 1.6 n inches tall (the detailed figure)
    assert _pixels(run)["tension"][1] == pytest.approx((1.3 + 1.6 * 4) * 40, abs=2)


def test_the_tables_of_a_long_line_keep_their_ends_and_count_the_rest(runs) -> None:
    large = runs[1]
    spans = next(t for t in summary_tables(large, Display()) if len(t.rows) == 90)
    short = condensed(spans)
    assert len(short.rows) == 2 * TABLE_ENDS + 1
    assert short.rows[:TABLE_ENDS] == spans.rows[:TABLE_ENDS]
    assert short.rows[-TABLE_ENDS:] == spans.rows[-TABLE_ENDS:]
    assert f"{90 - 2 * TABLE_ENDS} more rows" in short.rows[TABLE_ENDS][0]


def test_the_report_of_a_long_line_is_written_with_condensed_tables(runs, tmp_path) -> None:
    files = write_report(runs[1], tmp_path)
    html = files.report.read_text()
    assert f"the first and last {TABLE_ENDS} of 90" in html
    assert "span47" not in html.split("Resolved line file")[0]  # a middle span left out


def test_a_model_beyond_the_eigen_limit_gets_a_note_not_a_decomposition() -> None:
    line = long_line(149)  # 300 spans: a closed-loop model of about 1000 states
    analysis = analyse(line)
    assert analysis.point is not None and analysis.modes == () and analysis.zone_loops == ()
    assert f"limit of {MAX_MODE_STATES}" in analysis.modes_note
    states = int(analysis.modes_note.split(" states")[0].split()[-1])
    assert states > MAX_MODE_STATES
    # the run's verdict says its stability was not checked: a warning, never silence
    verdict = webline.simulate(line, 0.05).verdict
    unchecked = [f for f in verdict.findings if f.kind == "stability_unchecked"]
    assert verdict.status == "warning" and len(unchecked) == 1
    assert unchecked[0].details["states"] == states


def test_a_short_line_still_gets_its_modes() -> None:
    analysis = analyse(webline.load_line("hswl"))
    assert analysis.modes and not analysis.modes_note
    assert np.all([m.eigenvalue.real < 0 for m in analysis.modes])  # hswl is stable
