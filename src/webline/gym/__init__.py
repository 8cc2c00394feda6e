"""A Gymnasium environment of a webline line (optional extra ``webline[gym]``).

``import webline.gym`` registers ``webline/Line-v0`` with Gymnasium (``gymnasium.register``
on import), then ``gymnasium.make("webline/Line-v0", line="hswl", ...)``; the environment is
``webline.gym.env.LineEnv`` (docs/controllers.md, Gymnasium). Without Gymnasium installed the
import raises ``MissingExtra`` naming the extra.
"""

from __future__ import annotations

from webline.extras import require

gymnasium = require("gymnasium")

ENV_ID = "webline/Line-v0"

if ENV_ID not in gymnasium.registry:
    gymnasium.register(id=ENV_ID, entry_point="webline.gym.env:LineEnv")
