"""Pure scalar functions of the physics, one module per phenomenon.

They run unchanged in plain Python, on numpy arrays and inside numba-compiled loops. Each
docstring names the thesis equation it generalises and the unit of every argument.
"""

from typing import TypeVar

import numpy as np

#: A float, or an array of them: the physics functions work elementwise on both.
Real = TypeVar("Real", float, np.ndarray)
