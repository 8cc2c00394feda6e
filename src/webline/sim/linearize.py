"""``webline.linearize``: the linear model of a single-path line (``sim.linear.linearize``) or
of a branched one (``sim.branches.linear``; docs/branching.md, "Linear models")."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Literal

from webline.errors import ArgumentError
from webline.line import Line
from webline.model.lines import load_line

if TYPE_CHECKING:
    from webline.model.web_graph import BranchedLine
    from webline.sim.linear.linear_system import LinearSystem


def linearize(line: Line | BranchedLine | str | Path, t: float | str = 0.0, *,
              loop: Literal["open", "closed"] = "closed",
              unwind_radius: float | None = None,
              rewind_radius: float | None = None) -> LinearSystem:
    """Linear model of ``line`` at its operating point at time ``t`` [s], as a python-control
    ``StateSpace`` with named signals (``LinearSystem``).

    A single-path line: ``webline.sim.linear.linearize.linearize`` (roll radii [m] as given,
    default initial). A branched line (``[[webs]]``): ``sim.branches.linear``; ``unwind_radius``
    is every unwind's radius and ``rewind_radius`` every rewind's, as a scenario's keys of
    those names (default: the file's). ``loop="open"``: the plant, inputs the motor torque
    commands [N·m] and wound-in tensions [N]; ``"closed"``: with its continuous-time
    cascaded PI controllers, inputs the line speed reference [m/s], the tension references
    [N] and the wound-in tensions. Outputs: span tensions [N] and web speeds [m/s].
    """
    from webline.spec.ranges import argument

    loaded = load_line(line)
    if loaded.branched:
        t = argument(t, "time", "t", ">=0")
        if loop not in ("open", "closed"):
            raise ArgumentError(f"loop: must be 'open' or 'closed', got {loop!r}")
        from webline.sim.branches.linear import linearize_branched
        from webline.spec.branched.values import radius_changes

        branched = loaded.replace(radius_changes(loaded.spec, unwind_radius, rewind_radius))
        return linearize_branched(branched, t, loop=loop)
    from webline.sim.linear.linearize import linearize as linearize_chain

    return linearize_chain(loaded, t, loop=loop,
                           unwind_radius=unwind_radius, rewind_radius=rewind_radius)
