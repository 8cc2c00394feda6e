"""Backlash in series with a compliance, as a continuous dead zone (thesis 3.22-3.32, 3.47-3.48,
3.65, Remark 3.3.1).

A gap lets the driving side d move ``gap_neg`` [m] one way and ``gap_pos`` [m] the other way
(measured from the rest position, where the spring is free) before the teeth touch. Past the
gap the spring of stiffness k is compressed by the overshoot, so the transmitted force is

    ψ = k · dz(d),   dz(d) = d - gap_pos  (d >= gap_pos),  d + gap_neg  (d <= -gap_neg),  0 else.

For the compliant shaft of Fig. 3.10, d = xm - xL (3.23); contact P of (3.17) is d <= -Δ and
contact Q of (3.19) is d >= Δ. For the belt and gear pair of Fig. 3.12, d = R1 θm - α1 θL is
in belt-stretch units and the gear gap Δ appears as α2 Δ (3.32), α1 = R2 Rg2/Rg1,
α2 = R2/Rg1. The thesis's symmetric gap is gap_neg = gap_pos = Δ; Remark 3.3.1's asymmetric gap
c1 = 2Δa, c2 = 2Δ(1 - a) is ``asymmetric_gaps``.

The "deviation" φ of (3.48) and (3.65) is what must be added to the linear compliant model to
obtain the backlash model; |φ| <= k·max(gap) is the bound the error bounds of Sec. 3.4 use.

Plain scalar maths, no calls between functions, so numba compiles each one alone. With zero
gaps every function reduces exactly (bit for bit) to the linear spring.
"""

from __future__ import annotations


def dead_zone(d: float, gap_neg: float, gap_pos: float) -> float:
    """Overshoot [m] of ``d`` [m] past the gap [-gap_neg, gap_pos] (both >= 0, [m]).

    Continuous, piecewise linear, zero inside the gap; ``dead_zone(d, 0, 0) == d`` exactly.
    """
    if d > gap_pos:
        return d - gap_pos
    if d < -gap_neg:
        return d + gap_neg
    return 0.0


def shaft_backlash_force(x_m: float, x_l: float, k: float, gap_neg: float,
                         gap_pos: float) -> float:
    """Spring force ψ [N] of the compliant shaft with backlash (3.23), d = x_m - x_l.

    ``x_m``, ``x_l`` [m] are the deviations of motor and load from rest (3.12), ``k`` [N/m] the
    spring stiffness, ``gap_neg``, ``gap_pos`` [m] the free travel either way (Δ, Δ in the
    thesis). ψ enters Mm ẍm + bm ẋm + ψ = Fm and ML ẍL + bL ẋL - ψ = FL (3.22).
    """
    d = x_m - x_l
    if d > gap_pos:
        return k * (d - gap_pos)
    if d < -gap_neg:
        return k * (d + gap_neg)
    return 0.0


def shaft_backlash_deviation(x_m: float, x_l: float, k: float, gap_neg: float,
                             gap_pos: float) -> float:
    """φ [N] of (3.48): k (x_m - x_l) - ψ, i.e. k times d clipped to [-gap_neg, gap_pos].

    With it the backlash model (3.22) is the linear model (3.46) plus φ:
    Mm ẍm + bm ẋm + k (xm - xL) - φ = Fm, ML ẍL + bL ẋL - k (xm - xL) + φ = FL (3.47);
    |φ| <= k·max(gap_neg, gap_pos). Arguments as ``shaft_backlash_force``.
    """
    d = x_m - x_l
    if d > gap_pos:
        return k * gap_pos
    if d < -gap_neg:
        return -k * gap_neg
    return k * d


def belt_gear_backlash_force(theta_m: float, theta_l: float, kb: float, r1: float,
                             alpha1: float, alpha2: float, gap_neg: float,
                             gap_pos: float) -> float:
    """Belt force ψ [N] of the belt and backlashed gear pair (3.32), d = r1 θm - α1 θL.

    ``theta_m``, ``theta_l`` [rad]: motor and load angles; ``kb`` [N/m]: tight-side stiffness;
    ``r1`` [m]: motor pulley radius; ``alpha1`` = R2 Rg2/Rg1 [m] and ``alpha2`` = R2/Rg1 [-]
    (3.26); ``gap_neg``, ``gap_pos`` [m]: free travel at the gear pitch circle (Δ, Δ). ψ enters
    Jm θ̈m + bm θ̇m + r1 ψ = τm and JL θ̈L + bL θ̇L - α1 ψ = τL (3.31).
    """
    d = r1 * theta_m - alpha1 * theta_l
    if d > alpha2 * gap_pos:
        return kb * (d - alpha2 * gap_pos)
    if d < -alpha2 * gap_neg:
        return kb * (d + alpha2 * gap_neg)
    return 0.0


def belt_gear_backlash_deviation(theta_m: float, theta_l: float, kb: float, r1: float,
                                 alpha1: float, alpha2: float, gap_neg: float,
                                 gap_pos: float) -> float:
    """φ [N] of (3.65): ψ - kb (r1 θm - α1 θL), i.e. -kb times d clipped to the scaled gap.

    With it (3.31) is the linear model (Ap of 3.64) plus the input φ through
    Dp = [0, -r1/Jm, 0, α1/JL]ᵀ (3.63); |φ| <= kb α2 max(gap_neg, gap_pos).
    Arguments as ``belt_gear_backlash_force``.
    """
    d = r1 * theta_m - alpha1 * theta_l
    if d > alpha2 * gap_pos:
        return -kb * alpha2 * gap_pos
    if d < -alpha2 * gap_neg:
        return kb * alpha2 * gap_neg
    return -kb * d


def gear_lever_arms(r2: float, rg1: float, rg2: float) -> tuple[float, float]:
    """(α1 [m], α2 [-]) of (3.26) from the driven pulley radius ``r2`` [m] and the pitch radii
    ``rg1`` (on the pulley shaft) and ``rg2`` (on the load) [m]: α1 = r2 rg2/rg1, α2 = r2/rg1.
    """
    return r2 * rg2 / rg1, r2 / rg1


def asymmetric_gaps(half_gap: float, position: float) -> tuple[float, float]:
    """(gap_neg, gap_pos) [m] of Remark 3.3.1: c1 = 2Δa on the P side (d < 0) and
    c2 = 2Δ(1 - a) on the Q side (d > 0), for a total clearance 2 ``half_gap`` [m] and the rest
    position ``position`` = a in [0, 1] (a = 0.5 is the thesis's centred case).
    """
    return 2.0 * half_gap * position, 2.0 * half_gap * (1.0 - position)


def transmitted_torque(twist: float, twist_rate: float, stiffness: float, damping: float,
                       gap_neg: float, gap_pos: float) -> float:
    """Torque [N·m] a compliant transmission with backlash passes to the load shaft.

    ``twist`` [rad] = θm/n - θL and ``twist_rate`` [rad/s] at the load shaft; ``stiffness``
    [N·m/rad] and ``damping`` [N·m·s/rad] act only while the teeth touch, i.e. past the free
    travel [-gap_neg, gap_pos] [rad] (the rotary form of 3.22-3.23 and 3.31-3.32). With no gap
    the teeth always touch and this is the linear spring-damper exactly.
    """
    if twist > gap_pos:
        return stiffness * (twist - gap_pos) + damping * twist_rate
    if twist < -gap_neg:
        return stiffness * (twist + gap_neg) + damping * twist_rate
    if gap_pos + gap_neg > 0.0:
        return 0.0
    return stiffness * twist + damping * twist_rate
