"""The line-file schema of a branched line (``[[webs]]``) and its checks (docs/branching.md)."""
