"""Ctrl-C during ``simulate``: seen within a chunk, the partial result kept (issue 11, item 4)."""

from __future__ import annotations

import os
import signal
import threading
import time

import pytest

import webline
from webline.sim.simulate import CHUNK_SECONDS

# serial: the signal must arrive within LATENCY, which a busy neighbour worker would stretch
pytestmark = [pytest.mark.skipif(os.name != "posix", reason="sends SIGINT to itself"),
              pytest.mark.serial]

#: Wall time allowed between the signal and simulate's return [s]: one chunk (~0.1 s) plus
#: assembling the result, with room for a machine shared by several processes.
LATENCY = 1.0


def _interrupt_after(seconds: float, sent: list[float]) -> threading.Timer:
    def send() -> None:
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(seconds, send)
    timer.start()
    return timer


def test_sigint_returns_the_partial_result_soon():
    """Two hours of the HSWL (~1.7 s of wall time or more) interrupted after 0.3 s: returned within
    ``LATENCY`` with status interrupted, fewer records than asked, times increasing."""
    webline.simulate("hswl", 0.01)  # compile (or load) the loop first
    sent: list[float] = []
    timer = _interrupt_after(0.3, sent)
    result = webline.simulate("hswl", 7200.0, raise_on_failure=False)
    returned = time.perf_counter()
    timer.join()
    assert sent, "the timer did not fire before the run ended"
    assert result.status == "interrupted"
    assert "interrupted" in result.message
    assert returned - sent[0] < LATENCY
    assert 0.0 < result.time[-1] < 7200.0
    assert (result.time[1:] > result.time[:-1]).all()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # handler restored
    assert CHUNK_SECONDS <= 0.5


def test_sigint_raises_simulation_interrupted_with_partial():
    """By default the interrupt propagates as a KeyboardInterrupt carrying the result."""
    webline.simulate("hswl", 0.01)
    sent: list[float] = []
    timer = _interrupt_after(0.3, sent)
    with pytest.raises(KeyboardInterrupt) as caught:
        webline.simulate("hswl", 7200.0)
    timer.join()
    assert isinstance(caught.value, webline.SimulationInterrupted)
    partial = caught.value.partial
    assert partial.status == "interrupted" and 0.0 < partial.time[-1] < 7200.0
    assert not isinstance(caught.value, webline.WeblineError)  # `except WeblineError` lets it by
