"""The compiled loop of a branched line: its tables' columns (``layout``), the plant, the
drives' tick and the loop that steps them (docs/branching.md)."""
