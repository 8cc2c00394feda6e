"""``webline.linearize``: the linear model of a single-path line (``sim.linear.linearize``) or
of a branched one (``sim.branches.linear``; docs/branching.md, "Linear models")."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Literal

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.web_graph import BranchedLine, source_is_branched

if TYPE_CHECKING:
    from webline.sim.linear.linear_system import LinearSystem


def linearize(line: Line | BranchedLine | str | Path, t: float | str = 0.0, *,
              loop: Literal["open", "closed"] = "closed",
              unwind_radius: float | None = None,
              rewind_radius: float | None = None) -> LinearSystem:
    """Linear model of ``line`` at its operating point at time ``t`` [s], as a python-control
    ``StateSpace`` with named signals (``LinearSystem``).

    A single-path line: ``webline.sim.linear.linearize.linearize`` (roll radii [m] as given,
    default initial). A branched line (``[[webs]]``): ``sim.branches.linear``, its roll radii
    those of the file. ``loop="open"``: the plant, inputs the motor torque commands [N·m] and
    wound-in tensions [N]; ``"closed"``: with its continuous-time cascaded PI controllers,
    inputs the line speed reference [m/s], the tension references [N] and the wound-in
    tensions. Outputs: span tensions [N] and web speeds [m/s].
    """
    from webline.spec.ranges import argument

    if isinstance(line, BranchedLine) or (not isinstance(line, Line)
                                          and source_is_branched(line)):
        t = argument(t, "time", "t", ">=0")
        if loop not in ("open", "closed"):
            raise ArgumentError(f"loop: must be 'open' or 'closed', got {loop!r}")
        if unwind_radius is not None or rewind_radius is not None:
            raise ArgumentError("unwind_radius, rewind_radius: not supported for a branched "
                                "line (its rolls' radii are the file's)")
        from webline.sim.branches.linear import linearize_branched

        return linearize_branched(line, t, loop=loop)  # type: ignore[arg-type]
    from webline.sim.linear.linearize import linearize as linearize_chain

    return linearize_chain(str(line) if isinstance(line, Path) else line, t, loop=loop,
                           unwind_radius=unwind_radius, rewind_radius=rewind_radius)
