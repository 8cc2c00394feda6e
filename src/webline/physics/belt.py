"""Belt-pulley transmission: the tight side of the belt as a linear spring (thesis 2.10-2.12).

Sign convention (thesis Fig. 2.1): the motor pulley of radius r1 turns by θm, the load pulley of
radius r2 by θL, both positive in the driving direction. The tight side is stretched by
r1 θm - r2 θL [m] (for a rigid belt r1 θm = r2 θL); the slack side carries no change of force.
All functions are plain scalar maths that numba compiles as they stand.
"""

from __future__ import annotations


def stretch(theta_m: float, theta_l: float, r1: float, r2: float) -> float:
    """Elongation [m] of the tight side: r1 θm - r2 θL (thesis, text above 2.10).

    ``theta_m``, ``theta_l`` [rad] are the motor and load pulley angles, ``r1``, ``r2`` [m]
    their pitch radii.
    """
    return r1 * theta_m - r2 * theta_l


def tight_side_force(theta_m: float, theta_l: float, r1: float, r2: float, kb: float) -> float:
    """Change of tight-side force [N] from the angles (2.10): Kb (r1 θm - r2 θL).

    ``kb`` [N/m] is the stiffness of the tight side. The force pulls the motor pulley back with
    the torque -r1 F and drives the load pulley with +r2 F (2.10a, 2.10b). The linear model
    lets F go negative (the thesis's assumption: the change of force about a pre-tension).
    """
    return kb * (r1 * theta_m - r2 * theta_l)


def damped_tight_side_force(stretch_m: float, stretch_rate: float, kb: float,
                            cb: float) -> float:
    """Tight-side force [N] with material damping: Kb s + cb ds/dt (thesis remark after 2.34).

    ``stretch_m`` [m] and ``stretch_rate`` [m/s] are r1 θm - r2 θL and its rate, ``kb`` [N/m],
    ``cb`` [N·s/m]. With ``cb = 0`` this is ``tight_side_force``.
    """
    return kb * stretch_m + cb * stretch_rate


def strain_energy(theta_m: float, theta_l: float, r1: float, r2: float, kb: float) -> float:
    """Strain energy [J] stored in the tight side (2.12): ½ Kb (r1 θm - r2 θL)².

    Its partial derivatives are the belt torques: ∂V/∂θm = r1 F, ∂V/∂θL = -r2 F.
    """
    s = r1 * theta_m - r2 * theta_l
    return 0.5 * kb * s * s


def belt_torques(theta_m: float, theta_l: float, r1: float, r2: float,
                 kb: float) -> tuple[float, float]:
    """Torques [N·m] the belt applies to the (motor, load) pulleys (2.10): (-r1 F, +r2 F)."""
    force = kb * (r1 * theta_m - r2 * theta_l)
    return -r1 * force, r2 * force
