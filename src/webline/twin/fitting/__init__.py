"""Fitting a line's parameters to traces: free parameters, least squares with intervals,
identifiability, the fitted line and its report."""
