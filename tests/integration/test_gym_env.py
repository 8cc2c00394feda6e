"""The Gymnasium environment webline/Line-v0 (issue 25, item 4)."""

from __future__ import annotations

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")


def test_env_checker_passes() -> None:
    """Must show: gymnasium's own checker accepts the environment (spaces, seeding,
    reset/step signatures, determinism of a seeded reset)."""
    from gymnasium.utils.env_checker import check_env

    import webline.gym  # noqa: F401 - registers webline/Line-v0

    env = gymnasium.make("webline/Line-v0", line="hswl", duration=0.2)
    check_env(env.unwrapped, skip_render_check=True)


def test_hold_at_equilibrium_earns_near_zero_reward_and_truncates() -> None:
    """Action 0 holds the agent drives at their equilibrium commands: the line stays near its
    operating point, so the reward (relative tension error², effort²) stays small, and the
    episode is truncated at its duration with the run's verdict."""
    import webline.gym  # noqa: F401

    env = gymnasium.make("webline/Line-v0", line="hswl", duration=0.1, ticks_per_step=10)
    obs, info = env.reset(seed=1)
    assert obs.shape == env.observation_space.shape
    total, done, steps = 0.0, False, 0
    while not done:
        obs, reward, terminated, truncated, info = env.step(np.zeros(env.action_space.shape))
        total += reward
        steps += 1
        done = terminated or truncated
    assert steps == 10 and truncated and not terminated
    assert "verdict" in info
    assert total < 0.0


def test_randomize_draws_from_the_distribution_with_the_seed() -> None:
    """Domain randomisation: each reset draws the path anew; the same seed draws the same."""
    import webline.gym  # noqa: F401

    env = gymnasium.make("webline/Line-v0", line="hswl", duration=0.05,
                         randomize={"web.ea": "normal(8.9 kN, 5 %)"})
    _, a = env.reset(seed=7)
    _, b = env.reset(seed=7)
    _, c = env.reset(seed=8)
    assert a["parameters"] == b["parameters"] != c["parameters"]


def test_a_branched_line_passes_the_checker_and_holding_the_equilibrium_costs_little() -> None:
    """The environment on the laminator (its three tension drives commanded, the nip on its
    compiled PI): gymnasium's checker passes; action 0 holds the equilibrium commands, so the
    tensions stay near their references and the reward per step is near 0 (each relative
    error below 1 %: -reward < 3 x 1e-4 + effort)."""
    from gymnasium.utils.env_checker import check_env

    import webline.gym  # noqa: F401

    env = gymnasium.make("webline/Line-v0", line="laminator", duration=0.05, ticks_per_step=5)
    check_env(env.unwrapped, skip_render_check=True)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (9,)  # speed error, tension error, radius per tension drive
    truncated = False
    while not truncated:
        obs, reward, terminated, truncated, info = env.step(np.zeros(3))
        assert not terminated
        effort = sum((d.equilibrium_command / d.torque_limit) ** 2 for d in (
            a.context.drives[0] for a in env.unwrapped.agents.values()))
        assert -reward <= 3e-4 + 0.01 * effort + 1e-12
    assert info["verdict"] in ("ok", "warning") and info["t"] == pytest.approx(0.05)


def test_randomize_on_a_branched_line_reaches_the_simulated_web() -> None:
    """Domain randomisation on the laminator (issue 33): each reset draws the film's EA by
    its path; the same seed draws the same; the drawn value is the stiffness of every film
    span the session's loop integrates (SI, to the bit)."""
    import webline.gym  # noqa: F401
    from webline.sim.branches.loop import layout as B

    env = gymnasium.make("webline/Line-v0", line="laminator", duration=0.01,
                         randomize={"webs.film.web.ea": "normal(103.5 kN, 5 %)"})
    _, a = env.reset(seed=7)
    plan = env.unwrapped.session.plan
    film = plan.line.web_spans(0)
    assert np.all(plan.sf[film, B.SF_EA] == a["parameters"]["webs.film.web.ea"])
    assert abs(a["parameters"]["webs.film.web.ea"] / 103.5e3 - 1.0) < 0.25  # 5 sigma
    _, b = env.reset(seed=7)
    _, c = env.reset(seed=8)
    assert a["parameters"] == b["parameters"] != c["parameters"]
    obs, *_ = env.step(np.zeros(3))
    assert np.all(np.isfinite(obs))
