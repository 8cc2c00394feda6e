"""webline: model, simulate, analyse and control roll-to-roll (web handling) process lines."""

from webline.errors import LineFileError, SimulationError, SimulationInterrupted, WeblineError
from webline.line import Line, load_line
from webline.model.operating_point import OperatingPoint, operating_point
from webline.sim.linearize import linearize
from webline.sim.reference import simulate_reference
from webline.sim.result import Result
from webline.sim.simulate import simulate
from webline.sim.sweep import monte_carlo, sweep
from webline.version import __version__

__all__ = [
    "Line",
    "LineFileError",
    "OperatingPoint",
    "Result",
    "SimulationError",
    "SimulationInterrupted",
    "WeblineError",
    "__version__",
    "linearize",
    "load_line",
    "monte_carlo",
    "operating_point",
    "simulate",
    "simulate_reference",
    "sweep",
]
