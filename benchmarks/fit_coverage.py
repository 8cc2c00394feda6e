"""Coverage of the fit's 95 % intervals over noise seeds (issue 24, "Must show": between 85
and 100 % over 50 seeds). Not a test: it runs about 50 fits.

    python benchmarks/fit_coverage.py [--seeds 50] [--duration 10]

Each seed draws new sensor noise on the same changed converter (``fit_speed.TRUTH``, the
start-up ramp, 200 Hz, 3.7 s clock offset) and fits the five parameters from the line file;
the coverage of a parameter is the share of seeds whose interval holds its true value.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from fit_speed import FREE, TRUTH


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--duration", type=float, default=10.0)
    args = parser.parse_args()
    from webline.twin.fit import fit
    from webline.twin.synthetic import synthetic_csv

    hits = {p: 0 for p in TRUTH}
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        for seed in range(args.seeds):
            path = synthetic_csv(Path(folder) / f"log{seed}.csv", "converter", changes=TRUTH,
                                 duration=args.duration, scenario="startup", offset=3.7,
                                 seed=1000 + seed)
            result = fit("converter", path, FREE, scenario="startup")
            for i, p in enumerate(result.parameters):
                hits[p.path] += bool(result.ci95[i, 0] <= TRUTH[p.path] <= result.ci95[i, 1])
            print(f"seed {seed}: {result.simulations} simulations, residuals "
                  f"{result.residual_scale:.3f} x noise, converged {result.converged}",
                  flush=True)
    total = sum(hits.values())
    for path, n in hits.items():
        print(f"{path}: {n}/{args.seeds} = {100 * n / args.seeds:.0f} %")
    print(f"all parameters: {total}/{args.seeds * len(hits)} = "
          f"{100 * total / (args.seeds * len(hits)):.1f} % "
          f"({time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
