"""Batched runs: sweeps and Monte Carlo studies, their cases, chunks, records and the Dask
path."""
