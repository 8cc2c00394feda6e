"""``webline/Line-v0``: a line whose chosen drives an agent commands (Gymnasium API).

Each environment step holds the agent's torques for ``ticks_per_step`` controller ticks of a
``webline.Session``; the other drives run their built-in controllers. Spaces (float32):

* action: one value in [-1, 1] per agent drive; the drive's torque command [N·m] is its
  equilibrium command + action x ``action_scale`` x its torque limit (then clipped at the
  limit, lagged and held as any command);
* observation: per agent drive, in ``context.drives`` order, its speed error v - v_ref
  [m/s], tension error T - T_ref [N] (0 for the master) and radius [m], the sampled
  measurements a drive sees (noise included).

Reward per step: -(``tension_weight`` x Σ ((T - T_ref) / T_ref)² + ``effort_weight`` x Σ
(τ / τ_limit)²) over the agent drives (tension relative to its reference, torque relative to
the limit). An episode ends (``terminated``) when the line leaves physical validity or fails,
with the run's verdict and message in ``info``, and is truncated at ``duration`` [s].

Nothing non-finite goes in or out. An action must have the action space's shape (one value
per agent drive; another shape is one ``ArgumentError`` naming the expected shape), be real
numbers and finite: a NaN or infinite action is refused (``ArgumentError``), never clipped
into a command, since it is a bug of the agent that a clip would hide. Where the plant's
readings (or, at a failure, its state) become non-finite, the observation is zeros there
and the episode ends (``terminated``) with the terminal reward ``failure_reward`` (default
-100, below what any finite step of a run near its references earns), ``info["verdict"]``
"failed".
An environment can be deep-copied and pickled with its state (``Session``), so gymnasium's
process-based ``AsyncVectorEnv`` works.
``randomize`` maps line paths to webline distributions (``"normal(9 kN, 5 %)"``,
docs/sweeps.md), drawn anew at each ``reset`` from the environment's seeded generator.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from webline.errors import ArgumentError, SimulationError
from webline.line import Line
from webline.model.lines import load_line
from webline.sim.session import Session
from webline.sim.sweeps.distributions import draw
from webline.sim.user_control import ControllerContext


class _Agent:
    """The controller of one agent drive: returns the torque the environment set."""

    def __init__(self) -> None:
        self.torque = 0.0
        self.context: ControllerContext | None = None
        self.measured = np.zeros(4)
        self.references = np.zeros(2)

    def reset(self, context: ControllerContext) -> None:
        self.context = context
        self.torque = context.drives[0].equilibrium_command

    def __call__(self, t: float, measurements: np.ndarray, references: np.ndarray) -> float:
        self.measured, self.references = measurements, references
        return self.torque


class LineEnv(gymnasium.Env):
    """A webline line as a Gymnasium environment (module docstring).

    ``line``: a built-in name, a file, a ``Line`` or a branched line (its drives' readings
    as a user controller's: a shaft of lanes reads the sum of its lanes; ``randomize`` by
    its paths, ``BranchedLine.replace``); ``drives``: the names the agent
    commands (default: every tension-controlling drive); ``scenario``; ``duration`` [s] of an
    episode; ``ticks_per_step``; ``action_scale`` [-]; ``tension_weight``, ``effort_weight``
    [-]; ``randomize``: {line path: distribution}; ``failure_reward``: the terminal reward
    of an episode whose readings became non-finite; ``allow_code``: consent to the Python
    code the line file names (docs/security.md).
    """

    metadata = {"render_modes": []}  # noqa: RUF012 (gymnasium declares it on Env)

    def __init__(self, line: Line | str = "hswl", *, drives: list[str] | None = None,
                 scenario: str | None = None, duration: float = 5.0,
                 ticks_per_step: int = 10, action_scale: float = 0.2,
                 tension_weight: float = 1.0, effort_weight: float = 0.01,
                 randomize: Mapping[str, Any] | None = None, failure_reward: float = -100.0,
                 allow_code: bool | None = None) -> None:
        self.base: Any
        loaded = load_line(line)
        if loaded.branched:  # docs/controllers.md, "On a branched line"
            self.base = loaded
            rollers = self.base.spec.rollers
            names = [rollers[i].name for i in self.base.drives]
            tension = [rollers[i].name for i in self.base.drives if i in self.base.zones]
        else:
            self.base = loaded
            names = [self.base.node_name(i) for i in self.base.drives]
            tension = [self.base.node_name(i) for i in self.base.drives
                       if self.base.controlled_zone(i) is not None]
        self.drive_names = list(drives) if drives is not None else tension
        for name in self.drive_names:
            if name not in names:
                raise ArgumentError(f"drives: no drive {name!r}; the drives are "
                                    f"{', '.join(names)}")
        if ticks_per_step < 1 or duration <= 0:
            raise ArgumentError("ticks_per_step must be >= 1 and duration > 0")
        self.scenario, self.duration, self.ticks = scenario, duration, ticks_per_step
        self.action_scale = action_scale
        self.weights = (tension_weight, effort_weight)
        self.randomize = dict(randomize or {})
        if not np.isfinite(failure_reward):
            raise ArgumentError(f"failure_reward: must be finite, got {failure_reward}")
        self.failure_reward, self.allow_code = float(failure_reward), allow_code
        draw(self.randomize, 1, 0)  # a bad distribution fails here, not at the first reset
        n = len(self.drive_names)
        self.action_space = spaces.Box(-1.0, 1.0, (n,), dtype=np.float32)
        self.observation_space = spaces.Box(-np.inf, np.inf, (3 * n,), dtype=np.float32)
        self.session: Any = None  # a Session (a BranchSession for a branched line)
        self.agents: dict[str, _Agent] = {}

    def reset(self, *, seed: int | None = None,
              options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        line = self.base
        drawn: dict[str, float] = {}
        if self.randomize:
            sample = draw(self.randomize, 1, int(self.np_random.integers(2**63 - 1)))
            drawn = {path: float(values[0]) for path, values in sample.items()}
            line = line.replace(drawn)
        self.agents = {name: _Agent() for name in self.drive_names}
        self.session = Session(line, controller=self.agents, scenario=self.scenario,
                               allow_code=self.allow_code)
        return self._observation(), {"parameters": drawn, "t": 0.0}

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool,
                                                dict[str, Any]]:
        assert self.session is not None, "call reset first"
        action = np.clip(self._checked(action), -1.0, 1.0)
        effort = 0.0
        for a, agent in zip(action, self.agents.values(), strict=True):
            assert agent.context is not None
            drive = agent.context.drives[0]
            agent.torque = min(max(drive.equilibrium_command + a * self.action_scale
                                   * drive.torque_limit, -drive.torque_limit),
                               drive.torque_limit)
            effort += (agent.torque / drive.torque_limit) ** 2
        info: dict[str, Any] = {}
        terminated = False
        try:
            self.session.step(self.ticks)
        except SimulationError as exc:
            terminated = True
            verdict = getattr(exc.partial, "verdict", None)
            info["verdict"] = verdict.status if verdict is not None else "failed"
            info["message"] = str(exc)
        error = 0.0
        for agent in self.agents.values():
            t_ref = agent.references[1]
            if np.isfinite(t_ref) and t_ref != 0.0:
                error += ((agent.measured[1] - t_ref) / t_ref) ** 2
        reward = -(self.weights[0] * error + self.weights[1] * effort)
        if not (np.isfinite(reward) and all(np.isfinite(a.measured).all()
                                            for a in self.agents.values())
                and (not terminated or np.isfinite(list(self.session.state.values())).all())):
            terminated, reward = True, self.failure_reward  # (documented: module docstring)
            info.setdefault("verdict", "failed")
            info.setdefault("message", "the readings became non-finite")
        truncated = not terminated and self.session.t >= self.duration - 1e-12
        if truncated:
            info["verdict"] = self.session.result().verdict.status
        info["t"] = self.session.t
        return self._observation(), float(reward), terminated, truncated, info

    def _checked(self, action: object) -> np.ndarray:
        """``action`` as floats of the action space's shape, finite; else ``ArgumentError``
        naming what was expected."""
        shape = self.action_space.shape
        expected = (f"one value in [-1, 1] per agent drive ({', '.join(self.drive_names)}), "
                    f"shape {shape}")
        try:
            values = np.asarray(action)
        except Exception:  # a ragged list: no array of it
            values = np.asarray(None)
        if values.shape != shape:
            got = (f"shape {values.shape}" if values.dtype != object
                   else type(action).__name__)
            raise ArgumentError(f"action: expected {expected}, got {got}")
        if values.dtype.kind not in "biuf":
            raise ArgumentError(f"action: expected real numbers ({expected}), got dtype "
                                f"{values.dtype}")
        values = values.astype(float)
        if not np.isfinite(values).all():
            raise ArgumentError(f"action: must be finite, got {values.tolist()} (a NaN or "
                                f"infinite action is the agent's bug: refused, not clipped)")
        return values

    def _observation(self) -> np.ndarray:
        out = []
        for agent in self.agents.values():
            speed, tension, radius, _ = agent.measured
            v_ref, t_ref = agent.references
            out += [speed - v_ref, tension - t_ref if np.isfinite(t_ref) else 0.0, radius]
        return np.nan_to_num(np.array(out, dtype=np.float32))
