"""Measured traces in, a line replayed against them, parameters fitted with intervals
(issue 24): ``load_measurements``, ``replay``, ``fit``; identification experiments
(``experiment``) and controllers tuned on the (fitted) line (``tune``). Sits above
``report`` (its reports and figures use it) and below the CLI."""

from __future__ import annotations

from webline.twin.measurements import Measurements, load_measurements
from webline.twin.read import MeasurementError

__all__ = ["MeasurementError", "Measurements", "load_measurements"]
