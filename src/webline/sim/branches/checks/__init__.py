"""What a branched run's verdict checks beyond its webs' tensions: the winder states of the
line file's ``[checks]`` (docs/branching.md, "Winder states in the verdict")."""
