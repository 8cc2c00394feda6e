"""Figures of a report: the schematic and every plot of a run, summarised for lines of many
spans."""
