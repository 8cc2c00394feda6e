"""Line-file keys of a rewind's wound-roll stress model (docs/wound-roll.md): the stack's
pressure-strain law, the core, the finished roll and the limits its verdict checks."""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, Any, Literal

from pydantic import Field

from webline.spec.quantities import Force, Length, Modulus, Strict, si

#: a stress that may be negative (a buckling limit on hoop compression)
Stress = Annotated[float, si("pressure")]


class RollCoreSpec(Strict):
    """The core as a hollow isotropic cylinder (Lamé): ``modulus`` [Pa] and ``poisson`` [-] of
    its material, ``inner_radius`` [m] (its outer radius is the roll's ``core_radius``)."""

    modulus: Modulus
    poisson: Annotated[float, Field(ge=0.0, lt=0.5)] = 0.3
    inner_radius: Annotated[float, si("length", ">=0")]


class RollStressSpec(Strict):
    """The wound roll's stresses at the end of a run (``webline.physics.roll_stress``).

    ``model``: ``"pfeiffer"``, the stack's radial modulus E_r = ``k2`` (P + ``k1``) from
    Pfeiffer's P = K1 (exp(K2 ε) − 1) (``k1`` [Pa], ``k2`` [-]); ``"constant"``: E_r =
    ``radial_modulus`` [Pa] (Altmann's linear model). ``tangential_modulus`` [Pa]: the web's
    in-plane modulus (default the web's ``modulus``); ``poisson`` [-]: Hakiel's ν_rt.
    ``core``: ``"rigid"`` or a ``RollCoreSpec``. ``diameter`` [m]: the finished roll (default
    the taper's ``max_diameter``, else the roll at the end of the run); the layers the run did
    not wind take the zone's set tension times the taper. ``nip_load`` [N, or per width] and
    ``nip_friction`` [-]: a lay-on nip's wound-in share μ N / h (Good, Wu & Fikes 1994; the
    nip is not part of the line's dynamics). Limits: ``min_hoop`` [Pa] (hoop stress below it:
    starring / telescoping risk; default 0), ``max_pressure`` [Pa] (interlayer pressure:
    crushing, blocking), ``core_rating`` [Pa] (pressure the core takes), ``band`` [-]: a band
    whose pressure departs from the steady-wound roll's by more than this fraction.
    ``at_radii`` [m]: radii at which the roll is also kept as it was when its surface passed
    them (snapshots during winding), each above the core and within the finished roll.
    """

    model: Literal["pfeiffer", "constant"] = "pfeiffer"
    k1: Modulus | None = None
    k2: Annotated[float, si("dimensionless", ">0")] | None = None
    radial_modulus: Modulus | None = None
    tangential_modulus: Modulus | None = None
    poisson: Annotated[float, Field(ge=0.0, lt=0.5)] = 0.01
    core: Literal["rigid"] | RollCoreSpec = "rigid"
    diameter: Length | None = None
    nip_load: Force | None = None
    nip_friction: Annotated[float, si("dimensionless", ">=0")] = 0.0
    min_hoop: Stress = 0.0
    max_pressure: Modulus | None = None
    core_rating: Modulus | None = None
    band: Annotated[float, Field(gt=0.0, le=1.0)] = 0.05
    at_radii: list[Length] = Field(default_factory=list)


def check_roll_stress(rewind: Any, key: str, fail: Callable[[str, str], Any]) -> None:
    """Fail on a roll-stress table that lacks its model's keys or does not fit its roll."""
    spec: RollStressSpec | None = getattr(rewind, "roll_stress", None)
    if spec is None:
        return
    need, other = (
        (("k1", "k2"), ("radial_modulus",))
        if spec.model == "pfeiffer"
        else (("radial_modulus",), ("k1", "k2"))
    )
    for name in need:
        if getattr(spec, name) is None:
            fail(f"{key}.{name}", f"the {spec.model} model needs it")
    for name in other:
        if getattr(spec, name) is not None:
            fail(f"{key}.{name}", f"not a key of the {spec.model} model")
    if not isinstance(spec.core, str) and spec.core.inner_radius >= rewind.core_radius:
        fail(
            f"{key}.core.inner_radius",
            f"must be below the core radius "
            f"{rewind.core_radius:g} m, got {spec.core.inner_radius:g} m",
        )
    if spec.diameter is not None and spec.diameter <= 2.0 * rewind.core_radius:
        fail(
            f"{key}.diameter",
            f"the finished roll must be larger than the core "
            f"({2.0 * rewind.core_radius:g} m), got {spec.diameter:g} m",
        )
    taper = getattr(rewind, "taper", None)
    diameter = spec.diameter or (taper.max_diameter if taper is not None else None)
    for i, r in enumerate(spec.at_radii):
        if r <= rewind.core_radius:
            fail(
                f"{key}.at_radii[{i}]",
                f"{r:g} m is inside the core (core radius {rewind.core_radius:g} m): a "
                "snapshot is taken as the roll's surface passes a radius above it",
            )
        if diameter is not None and r > 0.5 * diameter:
            fail(
                f"{key}.at_radii[{i}]",
                f"{r:g} m is beyond the finished roll (radius {0.5 * diameter:g} m)",
            )
