"""The python-control system ``webline.linearize`` returns: a ``StateSpace`` in every respect
but its ``repr``, a few lines instead of python-control's every matrix (13 kB for the HSWL);
``print(system)`` still lists the signals, ``.A`` ... ``.D`` hold the matrices."""

from __future__ import annotations

import control


class LinearSystem(control.StateSpace):
    """A python-control ``StateSpace`` with named signals and a short ``repr``."""

    def __repr__(self) -> str:
        def few(names: list[str]) -> str:
            return ", ".join(names[:4]) + (", ..." if len(names) > 4 else "")

        return (f"<webline LinearSystem {self.name!r}: {self.nstates} states, "
                f"{self.ninputs} inputs ({few(self.input_labels)}), "
                f"{self.noutputs} outputs ({few(self.output_labels)})>")
