"""webline: model, simulate, analyse and control roll-to-roll (web handling) process lines."""

from webline.analysis.linearize import linearize
from webline.analysis.operating_point import OperatingPoint, operating_point
from webline.errors import LineFileError, SimulationError, SimulationInterrupted, WeblineError
from webline.line import Line, load_line
from webline.sim.reference import simulate_reference
from webline.sim.result import Result
from webline.sim.simulate import simulate

__version__ = "0.1.0"

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
    "operating_point",
    "simulate",
    "simulate_reference",
]
