"""FMU export of a line with its controllers: the general loop compiled to a shared library
with an FMI 2.0 / 3.0 co-simulation wrapper, no Python inside (docs/fmu.md)."""
