"""A short training-loop sketch on webline/Line-v0: random search of a linear policy.

No RL library: the policy is action = -K · observation (per agent drive, K on its speed
error [m/s] and tension error [N]), and a (1+1) random search keeps a perturbed K when its
episode earns more reward. Needs the optional extra: pip install 'webline[gym]'.

    python examples/gym_sketch.py
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

import webline.gym  # noqa: F401 - registers webline/Line-v0
from webline.gym import gymnasium


def episode(env: object, gains: np.ndarray, seed: int) -> float:
    """Total reward of one episode of the linear policy ``gains`` (2 per drive)."""
    obs, _ = env.reset(seed=seed)  # type: ignore[attr-defined]
    total, done = 0.0, False
    while not done:
        per_drive = obs.reshape(-1, 3)[:, :2]  # speed error, tension error (radius unused)
        action = np.clip(-(per_drive * gains.reshape(-1, 2)).sum(axis=1), -1.0, 1.0)
        obs, reward, terminated, truncated, _ = env.step(action)  # type: ignore[attr-defined]
        total += reward
        done = terminated or truncated
    return total


def main() -> None:
    env = gymnasium.make("webline/Line-v0", line="hswl", duration=0.5, ticks_per_step=10,
                         randomize={"web.ea": "normal(8.9 kN, 5 %)"})
    n = env.action_space.shape[0]
    rng = np.random.default_rng(0)
    best = np.zeros(2 * n)
    kept, rewards = 0, []
    for trial in range(8):  # candidate and incumbent on the same drawn line (seed)
        candidate = best + rng.normal(0.0, [2.0, 0.005] * n)
        tried, incumbent = episode(env, candidate, seed=trial), episode(env, best, seed=trial)
        if tried > incumbent:
            best, kept = candidate, kept + 1
        rewards.append((incumbent, tried))
    start, end = episode(env, np.zeros(2 * n), seed=99), episode(env, best, seed=99)
    print(f"random search, 8 trials, {kept} kept: reward on a new line {start:.4g} at K = 0, "
          f"{end:.4g} at the found K")
    _, ax = plt.subplots(figsize=(7, 3.2), layout="constrained")
    ax.plot([r[0] for r in rewards], "o-", label="incumbent K")
    ax.plot([r[1] for r in rewards], "x", label="candidate K")
    ax.set_xlabel("trial (each on its own drawn line)")
    ax.set_ylabel("episode reward")
    ax.set_title("random search of a linear policy on webline/Line-v0 (hswl)")
    ax.legend()
    ax.grid(alpha=0.3)
    plt.show()


if __name__ == "__main__":
    main()
