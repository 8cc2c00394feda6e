"""Line-file keys of a nip (docs/winder.md, "Nip"): a pressure roller loaded against a driven
or idle roller, the web between them, and what the nip adds to that roller."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Annotated, Any, Literal

from webline.spec.quantities import Damping, Force, Inertia, Length, Strict, TorqueNonNeg, si

Coefficient = Annotated[float, si("dimensionless", ">0")]


class NipSpec(Strict):
    """A pressure roller of ``radius`` R_n [m] and ``inertia`` J_n [kg·m²] pressed with ``load``
    N [N] on the roller that carries the table (radius R), the web between them.

    The pressure roller rolls on the roller without slip (web thickness neglected), so it turns
    at ω R/R_n: its inertia and its bearing friction (``bearing_friction`` b_n [N·m·s],
    ``bearing_coulomb`` c_n [N·m]) act on the roller as J_n (R/R_n)², b_n (R/R_n)² and
    c_n R/R_n (``reflected``). ``grip``: ``"gripped"`` - the web moves with the roller surface
    (the nip isolates the tensions on its two sides); ``"traction"`` - the nip adds the
    friction of its two faces, 2 ``friction`` N (static μ_n) and 2 ``kinetic_friction`` N
    (Coulomb μ_n', default μ_n) while slipping, to the roller's traction contact (Ch. 5).
    """

    load: Force
    radius: Length
    inertia: Inertia
    grip: Literal["gripped", "traction"] = "gripped"
    friction: Coefficient | None = None
    kinetic_friction: Annotated[float, si("dimensionless", ">=0")] | None = None
    bearing_friction: Damping = 0.0
    bearing_coulomb: TorqueNonNeg = 0.0

    def reflected(self, radius: float) -> tuple[float, float, float]:
        """(inertia [kg·m²], viscous [N·m·s], Coulomb [N·m] friction) of the pressure roller
        seen at the shaft of a roller of ``radius`` R [m]: J_n (R/R_n)², b_n (R/R_n)²,
        c_n R/R_n (kinetic energy and dissipated power kept: ω_n = ω R/R_n)."""
        ratio = radius / self.radius
        return (self.inertia * ratio * ratio, self.bearing_friction * ratio * ratio,
                self.bearing_coulomb * ratio)

    def capacity(self) -> tuple[float, float]:
        """(static, Coulomb) friction force [N] the nip adds on the web while it grips by
        traction: 2 μ_n N and 2 μ_n' N (two faces); (0, 0) for a gripped nip, whose web never
        slips."""
        if self.grip != "traction" or self.friction is None:
            return 0.0, 0.0
        kinetic = self.friction if self.kinetic_friction is None else self.kinetic_friction
        return 2.0 * self.friction * self.load, 2.0 * kinetic * self.load


def shaft_terms(roller: Any) -> tuple[float, float, float]:
    """(inertia [kg·m²], viscous [N·m·s], Coulomb [N·m] friction) of ``roller`` (a roller
    spec) at its shaft without its drive: its own, plus its nip's reflected (``NipSpec``)."""
    nip = getattr(roller, "nip", None)
    if nip is None:
        return roller.inertia, roller.friction, roller.coulomb_friction
    inertia, viscous, coulomb = nip.reflected(roller.radius)
    return (roller.inertia + inertia, roller.friction + viscous,
            roller.coulomb_friction + coulomb)


def check_nips(rollers: Sequence[Any], fail: Callable[[str, str], Any]) -> None:
    """Fail on a nip on a dancer, a traction nip without a friction coefficient or on a roller
    without a traction contact (it extends that contact's slip model), a gripped nip on a
    traction contact (contradictory), and a kinetic coefficient above the static one."""
    for i, roller in enumerate(rollers):
        nip = getattr(roller, "nip", None)
        if nip is None:
            continue
        key = f"rollers[{i}].nip"
        if getattr(roller, "dancer", None) is not None:
            fail(key, "a dancer carries no nip (put the nip on a driven or idle roller)")
        contact = roller.contact.type
        if nip.grip == "traction":
            if nip.friction is None:
                fail(f"{key}.friction", "a traction nip needs its friction coefficient μ_n")
            if contact != "traction":
                fail(f"{key}.grip", "a traction nip adds to the roller's slip model: give the "
                     "roller a traction contact (contact = { type = \"traction\", ... })")
            if nip.kinetic_friction is not None and nip.kinetic_friction > nip.friction:
                fail(f"{key}.kinetic_friction",
                     f"must not exceed the static friction {nip.friction:g}")
        elif contact != "adhered":
            fail(f"{key}.grip", "a gripped nip holds the web to the roller surface, which "
                 "contradicts the roller's traction contact: use grip = \"traction\"")
