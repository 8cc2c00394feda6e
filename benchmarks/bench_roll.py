"""Benchmark of the wound-roll stress model (issue 38): a 10 000-layer roll in well under 0.5 s.

Run:  python benchmarks/bench_roll.py      (options: --layers N, --repeat N, --peer-layers N)

The roll: 25 µm PET film (E_t = 4 GPa) on a 76.2 mm fibre core, Pfeiffer's law with K1 =
1.5 kPa, K2 = 120 (the nonlinear model, E_r recomputed for every layer at every wrap: the
O(N²) work of Hakiel's accretion), wound with a 30 % linear taper. Printed: the layer count,
the compiled model's best and median wall and CPU time over ``--repeat`` runs (numba compiles
and caches once first, unmeasured), and, in the same run, the plain-Python peer (the same
loop uncompiled) on ``--peer-layers`` layers, scaled to the full count by (N/n)² (the work is
quadratic in the layers; timing the peer on the full roll would take many minutes). The
machine is shared: CPU time says more than wall time when other jobs run.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from webline.physics.roll_stress import core_modulus, roll_stress


def roll(layers: int, compiled: bool = True) -> float:
    """Solve one roll of ``layers`` layers; return its core pressure [Pa]."""
    h, rc = 25e-6, 0.0762
    r = rc + h * np.arange(layers)
    taper = 1.0 - 0.3 * (r - rc) / (r[-1] - rc + h)
    stress = 6e6 * taper  # 6 MPa at the core (1.5 N/cm on 25 µm)
    out = roll_stress(
        stress,
        rc,
        h,
        tangential_modulus=4e9,
        k1=1.5e3,
        k2=120.0,
        poisson=0.01,
        core_stiffness=core_modulus(3e9, 0.3, 0.066, rc),
        compiled=compiled,
    )
    return out.core_pressure


def timed(layers: int, compiled: bool) -> tuple[float, float]:
    """(wall, CPU) seconds of one roll."""
    w, c = time.perf_counter(), time.process_time()
    roll(layers, compiled)
    return time.perf_counter() - w, time.process_time() - c


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--layers", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--peer-layers", type=int, default=300)
    args = parser.parse_args()
    roll(50)  # compile (or load the cache)
    runs = [timed(args.layers, True) for _ in range(args.repeat)]
    wall = [w for w, _ in runs]
    cpu = [c for _, c in runs]
    print(f"layers: {args.layers}")
    print(
        f"compiled: best {min(wall):.3f} s wall, median {statistics.median(wall):.3f} s wall, "
        f"median {statistics.median(cpu):.3f} s CPU ({args.repeat} runs)"
    )
    n = args.peer_layers
    pw, _ = timed(n, False)
    scale = (args.layers / n) ** 2
    print(
        f"plain Python peer: {pw:.3f} s wall on {n} layers -> {pw * scale:.1f} s for "
        f"{args.layers} (x (N/n)^2); compiled is {pw * scale / min(wall):.0f}x faster"
    )
    print(f"core pressure: {roll(args.layers) / 1e6:.4g} MPa")


if __name__ == "__main__":
    main()
