"""webline: model, simulate, analyse and control roll-to-roll (web handling) process lines.

The front door: ``load_line`` (any line file: one web, or webs that branch), ``simulate``,
``Session``, ``CompiledController``, ``sweep``, ``monte_carlo``, ``linearize``,
``operating_point`` and their types; and, from the layers above it (``webline.twin`` and
``webline.studies``, imported only when one of them is first used, never by this module's
code), ``load_measurements``, ``replay``, ``fit``, ``tune`` and ``benchmark``. Each is
imported on first use (PEP 562), so ``import webline`` and the command line start fast;
python-control, scipy and numba load only when a model or a run needs them.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

from webline.errors import (
    ArgumentError,
    ControllerError,
    LineFileError,
    SimulationError,
    SimulationInterrupted,
    WeblineError,
)
from webline.version import __version__

if TYPE_CHECKING:
    from webline.compile_ahead import warm
    from webline.line import Line
    from webline.model.lines import load_line
    from webline.model.operating_point import OperatingPoint, operating_point
    from webline.model.web_graph import BranchedLine
    from webline.sim.compiled_control import CompiledController
    from webline.sim.linearize import linearize
    from webline.sim.reference import simulate_reference
    from webline.sim.results.result import Result
    from webline.sim.results.run_result import RunResult
    from webline.sim.session import Session
    from webline.sim.simulate import simulate
    from webline.sim.sweeps.sweep import monte_carlo, sweep

#: where each lazily imported name lives
_LAZY = {
    "Line": "webline.line",
    "CompiledController": "webline.sim.compiled_control",
    "load_line": "webline.model.lines",
    "BranchedLine": "webline.model.web_graph",
    "OperatingPoint": "webline.model.operating_point",
    "operating_point": "webline.model.operating_point",
    "linearize": "webline.sim.linearize",
    "simulate_reference": "webline.sim.reference",
    "Result": "webline.sim.results.result",
    "RunResult": "webline.sim.results.run_result",
    "simulate": "webline.sim.simulate",
    "Session": "webline.sim.session",
    "sweep": "webline.sim.sweeps.sweep",
    "monte_carlo": "webline.sim.sweeps.sweep",
    "warm": "webline.compile_ahead",
}
#: names of the twin and studies layers (above this one): looked up on first use only, so
#: importing ``webline`` never imports the layers above it (docs/architecture.md)
_LAZY_ABOVE = {
    "load_measurements": "webline.twin.traces.measurements",
    "Measurements": "webline.twin.traces.measurements",
    "replay": "webline.twin.traces.replay",
    "fit": "webline.twin.fitting.fit",
    "tune": "webline.twin.tuning.tune",
    "benchmark": "webline.studies.benchmark.run",
    "export_fmu": "webline.fmu.export",
}

__all__ = [
    "ArgumentError",
    "BranchedLine",
    "CompiledController",
    "ControllerError",
    "Line",
    "LineFileError",
    "Measurements",
    "OperatingPoint",
    "Result",
    "RunResult",
    "Session",
    "SimulationError",
    "SimulationInterrupted",
    "WeblineError",
    "__version__",
    "benchmark",
    "export_fmu",
    "fit",
    "linearize",
    "load_line",
    "load_measurements",
    "monte_carlo",
    "operating_point",
    "replay",
    "simulate",
    "simulate_reference",
    "sweep",
    "tune",
    "warm",
]


def __getattr__(name: str) -> object:
    if name in _LAZY or name in _LAZY_ABOVE:
        value = getattr(importlib.import_module({**_LAZY, **_LAZY_ABOVE}[name]), name)
        globals()[name] = value  # later look-ups skip this function
        return value
    raise AttributeError(f"module 'webline' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
