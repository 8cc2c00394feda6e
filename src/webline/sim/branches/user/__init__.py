"""User controllers and ``Session`` on a branched line (docs/controllers.md, "On a branched
line"): the Python side of ``loop.user``."""
