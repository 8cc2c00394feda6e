"""Cost of the user controller paths against the built-in loop (issue 25).

    python benchmarks/bench_user_controller.py [--seconds 6] [--line hswl laminator]

Runs ``hswl`` and the branched ``laminator`` (or the ``--line`` lines) for the given time
with their built-in controllers (the compiled loop), then with a user controller that only
returns held torques for every drive (the Python path's own cost: one compiled call per
tick, the measurement pass, the Python call),
then with the built-in cascaded PI written in Python (examples/user_pi.py: the path plus a
controller's own arithmetic), then with that PI as a compiled law
(examples/user_pi_numba.py: in the loop, on a single-path and a branched line alike).
Each run is timed after a warm-up (compilation excluded); the per-tick numbers are (user
run - built-in run) / ticks, the ratios user run / built-in run, all from this one process.
Times are the process's CPU time, best of five (built-in and compiled: best of 15, the two
alternating); the load average is printed with them.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import time
from pathlib import Path
from typing import Any

import numpy as np

import webline


class Hold:
    """Returns the same torques every tick: the cheapest controller there is."""

    def reset(self, context: object) -> None:
        self.torques = np.array([d.equilibrium_command for d in context.drives])  # type: ignore[attr-defined]

    def __call__(self, t: float, measurements: np.ndarray, references: np.ndarray) -> object:
        return self.torques


def _example(name: str) -> Any:
    path = Path(__file__).resolve().parents[1] / "examples" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def best(run: object, repeat: int = 5) -> float:
    """Least CPU time [s] of this process over ``repeat`` calls of ``run`` (CPU time, not
    wall time: on a shared machine the wall time counts other processes' turns)."""
    times = []
    for _ in range(repeat):
        start = time.process_time()
        run()  # type: ignore[operator]
        times.append(time.process_time() - start)
    return min(times)


def interleaved(first: object, second: object, repeat: int = 15) -> tuple[float, float]:
    """Least CPU time [s] of ``first`` and of ``second`` over ``repeat`` alternating calls:
    on a shared machine the load drifts, and alternating gives both sides the same."""
    a, b = [], []
    for _ in range(repeat):
        for run, times in ((first, a), (second, b)):
            start = time.process_time()
            run()  # type: ignore[operator]
            times.append(time.process_time() - start)
    return min(a), min(b)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=6.0)
    parser.add_argument("--line", nargs="+", default=["hswl", "laminator"],
                        help="built-in lines or line files")
    args = parser.parse_args()
    met = [measure(webline.load_line(name), args.seconds) for name in args.line]
    print(f"compiled user PI / built-in PI <= 1.5 on every line: "
          f"{'met' if all(met) else 'NOT met'}")


def measure(line: Any, seconds: float) -> bool:
    """Print ``line``'s costs (module docstring); whether the compiled law's run is within
    1.5x of the built-in run."""
    pi = _example("user_pi").CascadedPI
    compiled_pi = _example("user_pi_numba").cascaded_pi
    for controller in (None, Hold(), pi(), compiled_pi()):  # warm-up: compile every path
        webline.simulate(line, 0.01, controller=controller)
    dt = webline.simulate(line, 0.01).settings["dt"]
    ticks = round(seconds / dt) + 1
    hold = best(lambda: webline.simulate(line, seconds, controller=Hold()))
    python_pi = best(lambda: webline.simulate(line, seconds, controller=pi()))
    builtin, compiled = interleaved(  # the ratio's two sides, alternately: the same load
        lambda: webline.simulate(line, seconds),
        lambda: webline.simulate(line, seconds, controller=compiled_pi()))
    load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
    print(f"{line.name}, {seconds:g} s, {ticks} ticks, {len(line.drives)} drives; "
          f"load average {load}")
    print(f"built-in (compiled loop)      {builtin * 1e3:8.1f} ms  {builtin / ticks * 1e6:6.2f} "
          f"us/tick")
    for name, cost in (("user: held torques", hold), ("user: PI in Python", python_pi),
                       ("user: PI compiled (numba)", compiled)):
        extra = (cost - builtin) / ticks * 1e6
        print(f"{name:29s} {cost * 1e3:8.1f} ms  {cost / ticks * 1e6:6.2f} us/tick  "
              f"+{extra:5.2f} us/tick above the compiled loop ({cost / builtin:5.2f}x)")
    ratio = compiled / builtin
    print(f"compiled user PI / built-in PI: {ratio:.2f} (must show: <= 1.5: "
          f"{'met' if ratio <= 1.5 else 'NOT met'})")
    return ratio <= 1.5


if __name__ == "__main__":
    main()
