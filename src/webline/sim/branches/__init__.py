"""Branched lines (docs/branching.md): plan, compiled loop, operating point and results of
a line whose webs form a tree. Single-path lines run through ``sim.core`` unchanged."""
