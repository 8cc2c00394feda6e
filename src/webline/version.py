"""The version of webline, in the lowest layer so that every module may embed it."""

__version__ = "0.1.0"
