"""webline/Line-v0 keeps its contract (issue 34): actions are checked against the action
space (shape, dtype, finite), rewards and observations are always finite (or the episode
ends with the documented terminal reward), and an environment copies, pickles and runs in
gymnasium's process-based vector environment as a lone one does."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import webline.gym  # noqa: E402,F401 - registers webline/Line-v0
from webline.errors import ArgumentError  # noqa: E402


def make(**options: object) -> object:
    return gymnasium.make("webline/Line-v0", line="hswl", duration=0.1, ticks_per_step=5, **options)


def actions(n: int, count: int) -> list[np.ndarray]:
    rng = np.random.default_rng(3)
    return [rng.uniform(-0.3, 0.3, n).astype(np.float32) for _ in range(count)]


def rollout(env: object, steps: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    obs, rewards = [], []
    for a in steps:
        o, r, *_ = env.step(a)  # type: ignore[attr-defined]
        obs.append(o)
        rewards.append(r)
    return np.array(obs), np.array(rewards)


@pytest.mark.parametrize("how", ["deepcopy", "pickle"])
def test_a_copy_goes_on_as_the_original(how: str) -> None:
    """After 4 steps, a copy and the original given the same 6 actions give the same
    observations and rewards to the bit; the original was not moved by the copy's steps."""
    env = make().unwrapped
    env.reset(seed=5)
    n = env.action_space.shape[0]
    rollout(env, actions(n, 4))
    twin = copy.deepcopy(env) if how == "deepcopy" else pickle.loads(pickle.dumps(env))
    t = env.session.t
    later = actions(n, 6)
    obs_b, rew_b = rollout(twin, later)
    assert env.session.t == t
    obs_a, rew_a = rollout(env, later)
    assert np.array_equal(obs_a, obs_b) and np.array_equal(rew_a, rew_b)


def test_two_process_vector_env_matches_lone_envs() -> None:
    """gymnasium's AsyncVectorEnv (two worker processes) of webline/Line-v0 gives, per env,
    the trajectories of a lone environment with the same seed and actions (to the bit)."""
    from gymnasium.vector import AsyncVectorEnv

    vector = AsyncVectorEnv([make, make])
    try:
        obs, _ = vector.reset(seed=[11, 12])
        n = vector.single_action_space.shape[0]
        steps = actions(2 * n, 8)
        got = [vector.step(a.reshape(2, n)) for a in steps]
    finally:
        vector.close()
    for k, seed in enumerate((11, 12)):
        lone = make()
        first, _ = lone.reset(seed=seed)
        assert np.array_equal(first, obs[k])
        o, r = rollout(lone, [a.reshape(2, n)[k] for a in steps])
        assert np.array_equal(o, np.array([g[0][k] for g in got]))
        assert np.array_equal(r, np.array([g[1][k] for g in got]))


@pytest.mark.parametrize(
    ("kind", "says"),
    [
        ("nan", "must be finite"),
        ("inf", "must be finite"),
        ("long", "shape (3,)"),
        ("scalar", "shape (3,)"),
        ("column", "shape (3,)"),
        ("text", "real numbers"),
    ],
)
def test_bad_actions_are_one_clear_error(kind: str, says: str) -> None:
    """hswl's three tension drives: another shape names the expected shape (3,); NaN and inf
    are refused (never a NaN torque, never a NaN reward); the environment goes on."""
    env = make()
    env.reset(seed=0)
    n = env.action_space.shape[0]
    assert n == 3
    action = {
        "nan": np.array([np.nan, 0.0, 0.0]),
        "inf": np.array([0.0, np.inf, 0.0]),
        "long": np.zeros(n + 1),
        "scalar": 0.0,
        "column": np.zeros((n, 1)),
        "text": np.array(["a"] * n),
    }[kind]
    with pytest.raises(ArgumentError) as info:
        env.step(action)
    assert says in str(info.value) and "\n" not in str(info.value)
    obs, reward, terminated, _, _ = env.step(np.zeros(n))
    assert np.isfinite(reward) and np.isfinite(obs).all() and not terminated


def test_non_finite_readings_end_the_episode_with_the_terminal_reward() -> None:
    """A NaN forced into the plant: the episode ends (terminated) with failure_reward, a
    finite observation and verdict failed."""
    env = make(failure_reward=-55.0).unwrapped
    env.reset(seed=0)
    name = next(k for k in env.session.state if k.endswith(".stretch"))
    env.session.apply({name: float("nan")})
    obs, reward, terminated, truncated, info = env.step(np.zeros(env.action_space.shape))
    assert terminated and not truncated and reward == -55.0
    assert np.isfinite(obs).all() and info["verdict"] == "failed"
    with pytest.raises(ArgumentError, match="failure_reward"):
        make(failure_reward=float("nan"))
