"""Time of a five-parameter fit to 60 s of ``converter`` traces (issue 24: goal <= 30 s on the
2-core machine), with the number of simulations it used and the machine's load.

    python benchmarks/fit_speed.py [--duration 60] [--seed 1]

The traces: the converter's start-up (0 to 300 m/min from 1 s to 21 s, then steady) with
five parameters changed (``TRUTH``), logged at 200 Hz with sensor noise and a 3.7 s clock
offset (``webline.twin.traces.synthetic``). The compiled loop is loaded (and a first simulation
run) before the clock starts: the fit's own time is measured.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

TRUTH = {"rollers.infeed.inertia": 0.7, "rollers.chill.inertia": 2.4,
         "rollers.drum.friction": 0.09, "web.modulus": 3.3e9,
         "rollers.dancer.dancer.damping": 700.0}
FREE = {"rollers.infeed.inertia": "0.1 .. 2 kg*m**2", "rollers.chill.inertia": "0.5 .. 8 kg*m**2",
        "rollers.drum.friction": "0.005 .. 0.5 N*m*s", "web.modulus": "2 .. 6 GPa",
        "rollers.dancer.dancer.damping": "100 .. 3000 N*s/m"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=1,
                        help="threads for the Jacobian's cases (0: every core)")
    args = parser.parse_args()
    import webline
    from webline.twin.fitting.fit import fit
    from webline.twin.traces.synthetic import synthetic_csv

    with tempfile.TemporaryDirectory() as folder:
        path = synthetic_csv(Path(folder) / "log.csv", "converter", changes=TRUTH,
                             duration=args.duration, scenario="startup", offset=3.7,
                             seed=args.seed)
        webline.simulate("converter", 0.1)  # load the compiled loop
        load = os.getloadavg()
        started, cpu = time.perf_counter(), time.process_time()
        result = fit("converter", path, FREE, scenario="startup",
                     workers=args.workers or None)
        seconds, cpu = time.perf_counter() - started, time.process_time() - cpu
    print(result)
    inside = sum(result.ci95[i, 0] <= TRUTH[p.path] <= result.ci95[i, 1]
                 for i, p in enumerate(result.parameters))
    print(f"fit of {len(FREE)} parameters to {args.duration:g} s of converter traces: "
          f"{seconds:.1f} s wall, {cpu:.1f} s of CPU, {result.simulations} simulations "
          f"({seconds / result.simulations * 1e3:.0f} ms each), {inside}/{len(FREE)} true "
          f"values inside their 95 % intervals, {args.workers or os.cpu_count()} thread(s)")
    print(f"machine: {os.cpu_count()} cores, load average before the fit "
          f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")


if __name__ == "__main__":
    main()
