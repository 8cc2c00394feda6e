"""The plant's pieces in the compiled loop: the column layout of the plan's tables, signal
sources, the envelope a run must stay in, dancers, splices, brakes after a break, friction and
compliant transmissions; one numba-jitted function family per module, called every
right-hand side or every tick."""
