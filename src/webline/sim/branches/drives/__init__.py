"""The drives of a branched line, plan side (docs/branching.md): the decentralized families'
sections and designs (``decentral``), the section observer (``observer``) and the compliant
drive trains and brakes (``drive_trains``); their ticks are in ``sim.branches.loop``."""
