"""Coverage of the fit's 95 % intervals over noise seeds (issue 24: between 85 and 100 % over
50 seeds; issue 36: at least 90 % on correct models with the honest intervals, and a second
figure on a record with a 3 % model error). Not a test: it runs about 50 fits.

    python benchmarks/fit_coverage.py [--seeds 50] [--duration 10] [--model-error] [--starts 1]

Each seed draws new sensor noise on the same changed converter (``fit_speed.TRUTH``, the
start-up ramp, 200 Hz, 3.7 s clock offset) and fits the five parameters from the line file;
the coverage of a parameter is the share of seeds whose interval holds its true value.
``--model-error``: the record is made with the drum's inertia 3 % above the line file's
(8.24 against 8 kg m²), which the fit does not free: the model the fit assumes is 3 % wrong
in one place. The widths are reported against the noise-only intervals ((JᵀJ)⁻¹, what the
fit reported before issue 36). ``--starts`` (default 1): the global stage does not change
the intervals of a fit that finds the truth's valley, and costs time here.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from fit_speed import FREE, TRUTH

#: the model error of ``--model-error``: a parameter the fit does not free, 3 % off
MODEL_ERROR = {"rollers.drum.inertia": 8.0 * 1.03}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--starts", type=int, default=1)
    parser.add_argument("--model-error", action="store_true")
    args = parser.parse_args()
    from webline.twin.fitting.fit import fit
    from webline.twin.traces.synthetic import synthetic_csv

    changes = {**TRUTH, **(MODEL_ERROR if args.model_error else {})}
    hits = {p: 0 for p in TRUTH}
    widths: list[float] = []
    verdicts: dict[str, int] = {}
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        for seed in range(args.seeds):
            path = synthetic_csv(Path(folder) / f"log{seed}.csv", "converter", changes=changes,
                                 duration=args.duration, scenario="startup", offset=3.7,
                                 seed=1000 + seed)
            result = fit("converter", path, FREE, scenario="startup", starts=args.starts)
            for i, p in enumerate(result.parameters):
                hits[p.path] += bool(result.ci95[i, 0] <= TRUTH[p.path] <= result.ci95[i, 1])
            widths.extend((result.stderr / result.stderr_noise).tolist())
            verdicts[result.verdict.status] = verdicts.get(result.verdict.status, 0) + 1
            print(f"seed {seed}: {result.simulations} simulations, residuals "
                  f"{result.residual_scale:.3f} x noise, {result.effective_points} blocks, "
                  f"verdict {result.verdict.status}", flush=True)
    total = sum(hits.values())
    for path, n in hits.items():
        print(f"{path}: {n}/{args.seeds} = {100 * n / args.seeds:.0f} %")
    print(f"all parameters: {total}/{args.seeds * len(hits)} = "
          f"{100 * total / (args.seeds * len(hits)):.1f} % "
          f"({time.perf_counter() - started:.0f} s)"
          + (" on records with a 3 % model error" if args.model_error else ""))
    print(f"interval width over the noise-only width: median {np.median(widths):.2f}, "
          f"range {np.min(widths):.2f} .. {np.max(widths):.2f}; verdicts {verdicts}")


if __name__ == "__main__":
    main()
