"""Linear models of a plan: the linearization, its closed-loop modes and stability, the fastest
mode and the step and work bounds drawn from it."""
