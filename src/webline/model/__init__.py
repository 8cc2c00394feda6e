"""The model layer: operating point and equilibrium inputs of a line (above line and physics,
below control)."""
