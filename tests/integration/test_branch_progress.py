"""``progress`` on a branched line (issue 33 item 3): called after each chunk of the run,
chunks of at most 1 % of the run (at least 1 000 ticks), as on a single-path line."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np
from typer.testing import CliRunner

import webline
from webline.cli import app


def test_progress_reports_each_chunk_and_leaves_the_run_unchanged():
    """3 s at 1 kHz: three chunks of 1 000 ticks, so 1/3, 2/3, 1. A chunk boundary only
    returns to Python with the state and controller memory in place, so the run is the
    same to the bit as one without ``progress`` (20 000-tick chunks)."""
    seen: list[float] = []
    with_bar = webline.simulate("laminator", 3.0, progress=seen.append)
    plain = webline.simulate("laminator", 3.0)
    assert np.allclose(seen, [1 / 3, 2 / 3, 1.0], rtol=0, atol=1e-15)
    assert np.array_equal(with_bar.rec, plain.rec)


def test_run_feeds_its_progress_bar_on_a_branched_line(tmp_path, monkeypatch):
    """``webline run`` on a branched line feeds the bar the fractions done, to 1 at its end
    (the bar itself is rich's, transient on stderr: what is checked is what it is fed)."""
    import webline.cli_branches as cli_branches

    fed: list[float] = []

    @contextmanager
    def recording(enabled: bool, label: str) -> Iterator[Callable[[float], None]]:
        assert enabled and label == "simulating laminator"
        yield fed.append

    monkeypatch.setattr(cli_branches, "progress_bar", recording)
    result = CliRunner().invoke(
        app, ["run", "laminator", "--duration", "2 s", "--out", str(tmp_path / "out")]
    )
    assert result.exit_code == 0, result.output
    assert fed == [0.5, 1.0]
