"""Measured traces in: reading and resampling logs, the signals they may hold, a line driven by
them (replay) and its residuals."""
