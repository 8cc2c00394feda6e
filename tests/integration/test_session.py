"""``webline.Session`` (issue 25, item 3): a line driven tick by tick."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import ArgumentError


def test_session_steps_are_the_run() -> None:
    """1000 single steps give the states simulate records at the same ticks (both run the
    same compiled tick; the session one at a time): equal to round-off (1e-9 of each
    state's range, the bound of the user-controller path's tests)."""
    line = webline.load_line("hswl")
    run = webline.simulate(line, 1.0)
    session = webline.Session(line)
    for _ in range(1000):
        session.step()
    assert session.t == pytest.approx(1.0)
    got = session.result()
    scale = np.max(np.abs(run.states), axis=0)
    assert np.max(np.abs(got.states - run.states[:1000]) / scale) < 1e-9
    final = np.array(list(session.state.values()))
    assert np.max(np.abs(final - run.states[-1]) / scale) < 1e-9


def test_snapshot_restore_replays_exactly() -> None:
    """After restore the same steps give the same state, bit for bit (deterministic loop,
    the same arrays)."""
    session = webline.Session("hswl")
    session.step(100)
    snap = session.snapshot()
    session.apply({"span2.stretch": 50.0})
    session.step(200)
    kicked = session.state
    session.restore(snap)
    session.step(200)
    plain = session.state
    session.restore(snap)
    session.apply({"span2.stretch": 50.0})
    session.step(200)
    assert session.state == kicked
    assert plain != kicked
    assert session.t == pytest.approx(0.3)


def test_set_reference_moves_the_tension() -> None:
    """A zone's tension reference raised by 20 % is tracked: 3 s later the loadcell span's
    tension is within 2 % of it (the tension loop's 8 rad/s bandwidth settles in < 1 s)."""
    session = webline.Session("hswl")
    line = session.plan.line
    zone = line.zones[1]
    name = f"{line.span_name(zone.loadcell)}.tension"
    before = session.measurements[name]
    session.set_reference(name, 1.2 * before)
    session.step(3000)
    assert session.measurements[name] == pytest.approx(1.2 * before, rel=0.02)


def test_bad_names_are_argument_errors() -> None:
    session = webline.Session("hswl")
    with pytest.raises(ArgumentError, match="no reference"):
        session.set_reference("nope", 1.0)
    with pytest.raises(ArgumentError, match="no state"):
        session.apply({"nope": 1.0})
