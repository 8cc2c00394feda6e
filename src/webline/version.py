"""The version of webline, in the lowest layer so that every module may embed it.

PEP 440, read by the build too (``pyproject.toml``'s dynamic version): ``0.3.0.dev0`` is the
third development wave in progress, a pre-release of 0.3.0 (0.1: the foundation, 0.2: the
second wave; CHANGELOG.md). A 0.x version says the line-file format and the API may still
change between minor versions.
"""

__version__ = "0.3.0.dev0"
