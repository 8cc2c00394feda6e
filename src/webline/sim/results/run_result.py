"""What every run returns, whatever its line (``webline.RunResult``): one set of names and
methods for a single-path line's ``Result`` and a branched line's ``BranchResult``.

A subclass gives its records as named views (``time``, ``tension`` and its reference,
``torque``, ``drive_speed``, ``roll_radius``, the element names), its ``verdict`` with its
``events``, and its signals as an xarray Dataset (``to_xarray``); this base derives from them
the verdict's ``status`` and ``message``, the ``metrics`` a sweep gives each case, the quick
look (``plot``, ``repr``) and the labelled ``signals``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from webline.sim.results.metrics import by_element, metrics_table, run_metrics

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from webline.sim.results.events import EventStats
    from webline.sim.results.wound_roll import WoundRoll
    from webline.verdict import Verdict


class RunResult(ABC):
    """A run's records over ``time`` [s], its verdict and its signals by name (SI)."""

    time: np.ndarray  #: time of each record [s]

    # --- what each kind of run gives ---------------------------------------------------------

    @property
    @abstractmethod
    def line(self) -> Any:
        """The line that ran (its scenario applied)."""

    @property
    @abstractmethod
    def verdict(self) -> Verdict:
        """The run's findings and status (``webline.verdict``)."""

    @property
    @abstractmethod
    def events(self) -> list[EventStats]:
        """Intervals of slack, torque limit and slip per element (``sim.results.events``)."""

    @property
    @abstractmethod
    def failure_text(self) -> str:
        """Why the run stopped early ('' if it ran to its end)."""

    @property
    @abstractmethod
    def span_names(self) -> list[str]: ...

    @property
    @abstractmethod
    def drive_names(self) -> list[str]: ...

    @property
    @abstractmethod
    def node_names(self) -> list[str]: ...

    @property
    @abstractmethod
    def roll_names(self) -> list[str]:
        """The rolls (unwinds, rewinds; a shaft's lanes one each), as ``roll_radius``'s."""

    @property
    @abstractmethod
    def tension(self) -> np.ndarray:
        """Span tensions [N], records x spans."""

    @property
    def tension_measured(self) -> np.ndarray:
        """Span tensions [N] as the loadcells show them, records x spans: the true tensions
        where the line has no calibrated sensor (``spec.sensors``; a single-path run
        overrides this with the readings)."""
        return self.tension

    @property
    def speed_measured(self) -> np.ndarray:
        """Web speed at each node [m/s] as the encoders show it, records x nodes: the true
        speeds where the line has no calibrated sensor."""
        return np.asarray(self.signals["speed"].values)

    @property
    @abstractmethod
    def tension_ref(self) -> np.ndarray:
        """Each loadcell span's tension reference [N] (NaN on spans without a loadcell)."""

    @property
    @abstractmethod
    def torque(self) -> np.ndarray:
        """Motor torque of each drive [N·m], records x drives."""

    @property
    @abstractmethod
    def drive_speed(self) -> np.ndarray:
        """Web speed each drive measures [m/s], records x drives."""

    @property
    @abstractmethod
    def roll_radius(self) -> np.ndarray:
        """Wound radius of each roll [m], records x rolls."""

    @property
    @abstractmethod
    def wound_rolls(self) -> dict[str, WoundRoll]:
        """The wound roll of each rewind with a ``roll_stress`` table (a shaft's lanes one
        each), by roll name, at the end of the run (``sim.results.wound_roll``)."""

    @abstractmethod
    def to_xarray(self) -> xr.Dataset:
        """Every signal over time with element coordinates, units as attributes."""

    @abstractmethod
    def to_dataframe(self) -> Any:
        """One row per record indexed by ``time`` [s], one column per signal and element
        (``tension[span1]``), SI, each column's unit in ``.attrs["units"]``."""

    @abstractmethod
    def summary(self) -> dict[str, Any]:
        """Per span its tension statistics [N] (``spans``), per drive its speed and torque
        (``drives``); ``webline.sim.results.metrics.run_summary``."""

    # --- shared ------------------------------------------------------------------------------

    @property
    def wound_roll(self) -> WoundRoll | None:
        """The line's first wound roll (``wound_rolls``; a single-path line has at most one:
        its rewind's), or None where no rewind has a ``roll_stress`` table."""
        return next(iter(self.wound_rolls.values()), None)

    @property
    def status(self) -> str:
        """``verdict.status``: ok, warning, unstable, failed or interrupted."""
        return self.verdict.status

    @property
    def message(self) -> str:
        """Why the run failed ('' if it did not), else the verdict's headline if not ok."""
        if self.failure_text:
            return self.failure_text
        return "" if self.verdict.ok else self.verdict.headline

    @cached_property
    def signals(self) -> xr.Dataset:
        """Every signal labelled: ``result.signals.tension`` is an xarray DataArray over
        (time, span) with names as coordinates and units as attributes (``to_xarray()``,
        built once)."""
        return self.to_xarray()

    def element_names(self) -> dict[str, list[str]]:
        """The element names of each dimension of the metrics: span, drive and node."""
        return {"span": self.span_names, "drive": self.drive_names, "node": self.node_names}

    def metric_arrays(self) -> dict[str, np.ndarray]:
        """The metrics a sweep gives each of its cases (``sim.results.metrics.run_metrics``),
        each an array over spans, drives or nodes [N or s], NaN where it does not apply (an
        error without a loadcell), and ``status``."""
        totals = {(e.kind, e.where): e.total for e in self.events}
        return run_metrics(
            self.time, self.tension, self.tension_ref, totals, self.element_names()
        ) | {"status": np.array(self.status)}

    def metrics(self) -> Any:
        """``metric_arrays`` as a tidy ``pandas.DataFrame``: columns ``element``, ``metric``,
        ``value`` [``unit``], ``unit``; the verdict's status in ``.attrs["status"]``."""
        return metrics_table(self.metric_arrays(), self.element_names(), self.status)

    def metrics_by_element(self) -> dict[str, object]:
        """``metric_arrays`` by name: each metric as {element name: value} [N or s], and
        ``status``."""
        return {**by_element(self.metric_arrays(), self.element_names()), "status": self.status}

    def plot(self, signals: Sequence[str] = ("tension", "speed")) -> Figure:
        """A matplotlib figure of ``signals`` over time [s]: "tension" (with the references
        dashed), "speed", "torque", "radius"; long runs drawn as min/max envelopes, so peaks
        survive (``webline.sim.results.quicklook``)."""
        from webline.sim.results.quicklook import plot_result

        return plot_result(self, tuple(signals))

    def __repr__(self) -> str:
        """A few lines: line, time span, records, verdict (``sim.results.quicklook``)."""
        from webline.sim.results.quicklook import result_text

        return result_text(self)
