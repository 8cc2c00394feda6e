"""The fastest mode of a plan: a rigorous upper bound of max |λ| of its linear models, cheap
for long lines, that sets the RK4 step (``webline.sim.simulate.choose_substeps``).

The step only needs an upper bound ρ̄ ≥ max|λ(A)| that is tight enough not to add sub-steps;
a dense eigenvalue solve of A costs O(n³) (40 ms for the 230 states of a 64-span line, five
times its 1 s simulation). The bound is built in two steps:

1. A is permuted to block-triangular form (the strongly connected components of its sparsity
   graph): its eigenvalues are those of the diagonal blocks. In open loop every torque lag is
   a 1x1 block, so its eigenvalue -1/lag comes out exactly.
2. A block of up to ``DENSE_STATES`` states gets its eigenvalues (exact; all of the built-in
   lines' blocks are this small; so does a whole model that small, without step 1). A
   larger block B is bounded by Gelfand's formula with Perron-Frobenius:
   ρ(B) = ρ(B^k)^{1/k} ≤ ρ(|B^k|)^{1/k}, and for any positive vector x,
   ρ(|B^k|) ≤ max_i (|B^k| x)_i / x_i (Collatz-Wielandt); a few sparse power iterations make x
   close to |B^k|'s Perron vector. With k = ``POWER`` the signs that cancel in the oscillatory
   span-roller and controller couplings cancel in B^k too, so the bound is within about 10 %
   of max|λ| on the lines measured (ρ(|B|) alone is 30-40 % above it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.line import Line
from webline.profiles import breakpoints

if TYPE_CHECKING:
    import scipy.sparse as sp

#: Blocks up to this many states get their exact eigenvalues (a dense solve: < 1 ms).
DENSE_STATES = 40
#: The power k of the Gelfand bound on larger blocks.
POWER = 8
#: Power iterations of the Collatz-Wielandt vector.
ITERATIONS = 10
#: Relative allowance for the rounding of the bound's own arithmetic.
ROUNDING = 1e-9


def spectral_radius_bound(a: np.ndarray) -> float:
    """Upper bound of max |λ(A)| [unit of A], exact (up to rounding) for blocks of up to
    ``DENSE_STATES`` states of A's block-triangular form (module docstring)."""
    a = np.asarray(a, dtype=float)
    if a.shape[0] == 0:
        return 0.0
    if a.shape[0] <= DENSE_STATES:  # one dense solve is cheaper than finding the blocks
        return float(np.abs(np.linalg.eigvals(a)).max())
    import scipy.sparse as sp  # here: long lines only (the main job does not import scipy)
    from scipy.sparse.csgraph import connected_components

    graph = sp.csr_matrix(a)
    n_blocks, label = connected_components(graph, directed=True, connection="strong")
    bound = 0.0
    for block in range(n_blocks):
        idx = np.flatnonzero(label == block)
        if len(idx) == 1:
            bound = max(bound, abs(float(a[idx[0], idx[0]])))
        elif len(idx) <= DENSE_STATES:
            bound = max(bound, float(np.abs(np.linalg.eigvals(a[np.ix_(idx, idx)])).max()))
        else:
            bound = max(bound, _gelfand_bound(graph[idx][:, idx]))
    return bound


def _gelfand_bound(block: sp.csr_matrix) -> float:
    """ρ(|B^k|)^{1/k} ≥ ρ(B) by Collatz-Wielandt on |B^k| (module docstring), k = ``POWER``."""
    scale = float(abs(block).max())
    if scale == 0.0:
        return 0.0
    power = block / scale
    k = 1
    while k < POWER:
        power = power @ power
        k *= 2
    m = abs(power).tocsr()
    x = np.ones(m.shape[0])
    floor = 1e-12
    for _ in range(ITERATIONS):  # stays positive: the floor keeps every entry > 0
        x = m @ x
        x = x / x.max() + floor
    ratio = float(np.max((m @ x) / x))
    return scale * ratio ** (1.0 / k) * (1.0 + ROUNDING)


def slip_rates(line: Line) -> list[tuple[int, float, str]]:
    """(node, fastest rate [1/s], key) of the two spans round each roller that may slip."""
    from webline.physics.slip import slip_rate

    top_speed = float(np.max(breakpoints(line.spec.speed)[1]))
    out = []
    for i, roller in enumerate(line.spec.rollers):
        contact = getattr(roller, "contact", None)
        if contact is None or contact.type != "traction":
            continue
        kinetic = contact.friction if contact.kinetic_friction is None else contact.kinetic_friction
        wrap = float(getattr(roller, "wrap", 0.0))  # check_spec: a traction contact has a wrap
        rate = slip_rate(line.ea, contact.viscous, line.spec.spans[i - 1].length,
                         line.spec.spans[i].length, contact.friction, kinetic, wrap,
                         1.1 * top_speed)
        out.append((i, rate, f"rollers[{i}].contact.viscous"))
    return out
