"""The section observer of a branched line's decentralized drives (docs/branching.md,
"Section observer"): plan-side columns, start and linear rows (``section``); the tick is
``sim.branches.loop.observer``."""
