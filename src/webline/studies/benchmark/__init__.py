"""``webline benchmark``: a versioned standard set of lines x scenarios x disturbances on
which the built-in controller families and the user's controllers are scored and ranked
(docs/benchmark.md).

``standard_set`` holds the cases and their version, ``scores`` each metric's definition,
``contenders`` the families and the user's controllers, ``run`` the benchmark, ``result`` the
table and ranking, ``markdown`` the report.
"""

from __future__ import annotations

from webline.studies.benchmark.result import BenchmarkResult
from webline.studies.benchmark.run import benchmark
from webline.studies.benchmark.standard_set import BENCHMARK_VERSION

__all__ = ["BENCHMARK_VERSION", "BenchmarkResult", "benchmark"]
