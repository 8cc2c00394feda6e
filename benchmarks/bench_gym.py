"""Time of 10 000 steps of the Gymnasium environment webline/Line-v0 (issue 25).

    python benchmarks/bench_gym.py [--steps 10000] [--ticks-per-step 10]

``hswl`` with its three tension drives commanded by a random policy (uniform actions from a
seeded generator, small: ±0.05 so the line keeps running), episodes of 5 s; the environment
is reset whenever an episode ends. Compilation is excluded (one warm-up episode).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from webline.extras import require

gymnasium = require("gymnasium")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=10_000)
    parser.add_argument("--ticks-per-step", type=int, default=10)
    args = parser.parse_args()
    import webline.gym  # noqa: F401 - registers webline/Line-v0

    env = gymnasium.make("webline/Line-v0", line="hswl", duration=5.0,
                         ticks_per_step=args.ticks_per_step)
    rng = np.random.default_rng(0)
    env.reset(seed=0)
    env.step(np.zeros(env.action_space.shape))  # warm-up: compiles the step
    env.reset(seed=0)
    episodes = 1
    start = time.perf_counter()
    for _ in range(args.steps):
        action = rng.uniform(-0.05, 0.05, env.action_space.shape)
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
            episodes += 1
    seconds = time.perf_counter() - start
    ticks = args.steps * args.ticks_per_step
    print(f"{args.steps} steps of webline/Line-v0 (hswl, {args.ticks_per_step} ticks each, "
          f"{episodes} episodes): {seconds:.2f} s, {seconds / args.steps * 1e6:.0f} us/step, "
          f"{seconds / ticks * 1e6:.1f} us/tick")


if __name__ == "__main__":
    main()
