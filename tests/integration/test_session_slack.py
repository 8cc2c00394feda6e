"""``Session.measurements`` reads a slack span's tension as 0, as ``Result.tension`` does
(issue 35 item 5): a web cannot push, its negative stretch is slack, not a tension."""

from __future__ import annotations

import pytest

import webline


def test_a_slack_span_reads_zero_tension():
    session = webline.Session("hswl")
    before = session.measurements["span2.tension"]
    assert before > 0.0
    session.apply({"span2.stretch": -(before + 70.0)})  # 70 N of slack: more web than span
    assert session.state["span2.stretch"] == pytest.approx(-70.0)
    reading = session.measurements
    assert reading["span2.tension"] == 0.0
    assert reading["span1.tension"] == pytest.approx(session.state["span1.stretch"])
