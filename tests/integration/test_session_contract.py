"""Session keeps a line file's contract (issue 34): its sample rate, sub-steps and references
pass the ranges and messages of the line file's keys (and ``simulate``'s); a snapshot is
restored only into the session it came from (or a copy); a session is copied and pickled with
its state, its records and its controllers' memory."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

import webline
from webline.errors import ArgumentError


class Integrating:
    """A controller with memory: the equilibrium command plus an integral of the tension
    error of its drive (a copy that lost this memory would part from the original)."""

    def reset(self, context: object) -> None:
        self.torque = context.drives[0].equilibrium_command  # type: ignore[attr-defined]
        self.sum = 0.0

    def __call__(self, t: float, m: np.ndarray, r: np.ndarray) -> float:
        self.sum += 1e-4 * (r[1] - m[1])
        return self.torque + self.sum


@pytest.mark.parametrize(
    ("options", "simulate_too"),
    [
        ({"sample_rate": -1000}, True),
        ({"sample_rate": 0}, True),
        ({"sample_rate": "fast"}, True),
        ({"sample_rate": "0.5 Hz"}, True),
        ({"substeps": 0}, True),
        ({"substeps": -3}, True),
        ({"substeps": 1.5}, True),
        ({"substeps": True}, True),
    ],
)
@pytest.mark.parametrize("line", ["hswl", "laminator"])
def test_settings_are_refused_as_simulate_refuses_them(
    options: dict, simulate_too: bool, line: str
) -> None:
    """The same one-line ArgumentError (the line file's ranges: control.sample_rate 1 Hz ..
    1 MHz) as ``simulate``, for a chain and a branched line."""
    with pytest.raises(ArgumentError) as session:
        webline.Session(line, **options)
    with pytest.raises(ArgumentError) as run:
        webline.simulate(line, 0.01, **options)
    assert str(session.value) == str(run.value) and "\n" not in str(session.value)


@pytest.mark.parametrize("line", ["hswl", "laminator"])
@pytest.mark.parametrize(
    ("name", "value", "says"),
    [
        ("tension", -500.0, "must be > 0"),
        ("tension", float("nan"), "finite"),
        ("tension", "2e9 N", "outside the physical range"),
        ("speed", -1.0, "must be >= 0"),
        ("speed", 300.0, "outside the physical range"),
    ],
)
def test_set_reference_keeps_the_line_files_ranges(
    line: str, name: str, value: object, says: str
) -> None:
    session = webline.Session(line)
    if name == "tension":  # (a zone's tension reference, by its loadcell span)
        name = _tension_references(session)[0]
    with pytest.raises(ArgumentError) as info:
        session.set_reference(name, value)  # type: ignore[arg-type]
    assert says in str(info.value) and name in str(info.value), str(info.value)
    assert "\n" not in str(info.value)


def _tension_references(session: object) -> list[str]:
    with pytest.raises(ArgumentError) as info:
        session.set_reference("nothing", 1.0)  # type: ignore[attr-defined]
    return [
        n.strip() for n in str(info.value).split("there are ")[1].split(",") if n.strip() != "speed"
    ]


def test_set_reference_takes_units() -> None:
    session = webline.Session("hswl")
    session.set_reference("speed", "100 m/min")
    session.step(2)
    speed = [v for k, v in session.measurements.items() if k.endswith("speed_reference")]
    assert speed == [] or all(v == pytest.approx(100 / 60) for v in speed)


def test_a_snapshot_is_restored_only_where_it_came_from(six: webline.Line) -> None:
    """Of another line of the same size (hswl with a stiffer web), of a line of another size
    and of the same line at another sample rate: refused in one line naming its line; of a
    copy of the session: restored."""
    hswl = webline.load_line("hswl")
    stiffer = hswl.replace({"web.ea": hswl.ea * 1.1})
    mine = webline.Session(hswl)
    for other in (
        webline.Session(stiffer),
        webline.Session(six),
        webline.Session(hswl, sample_rate=500),
    ):
        other.step(3)
        with pytest.raises(ArgumentError) as info:
            mine.restore(other.snapshot())
        message = str(info.value)
        assert f"of line {other.plan.line.name!r}" in message and "\n" not in message
        assert "identity" in message
    with pytest.raises(ArgumentError, match="expected a Snapshot"):
        mine.restore("tick 3")  # type: ignore[arg-type]
    mine.step(5)
    snap = mine.snapshot()
    twin = copy.deepcopy(mine)
    twin.step(7)
    twin.restore(snap)
    assert twin.t == pytest.approx(mine.t)
    branched = webline.Session("laminator")
    with pytest.raises(ArgumentError, match="expected a BranchSnapshot"):
        branched.restore(mine.snapshot())  # type: ignore[arg-type]


@pytest.mark.parametrize("line", ["hswl", "laminator"])
@pytest.mark.parametrize("how", ["deepcopy", "pickle"])
def test_copies_go_on_as_the_original_does(line: str, how: str) -> None:
    """After 150 ticks, a copy (deepcopy, or a pickle round trip) and the original, each
    stepped 250 more, give the same records to the bit: state, records and the controller's
    integral all came along; stepping the copy leaves the original where it was."""
    session = webline.Session(line, controller={"rewind": Integrating()})
    session.step(150)
    twin = copy.deepcopy(session) if how == "deepcopy" else pickle.loads(pickle.dumps(session))
    assert twin.t == session.t
    before = session.result().to_xarray() if line == "laminator" else None
    twin.step(250)
    if before is not None:
        assert session.t == pytest.approx(150 * session.plan.dt)
    session.step(250)
    a, b = session.result(), twin.result()
    if line == "hswl":
        assert np.array_equal(a.states, b.states) and len(a.time) == 400  # ticks 0..399
    else:
        assert a.to_xarray().equals(b.to_xarray())
