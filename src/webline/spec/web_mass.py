"""The web's mass in the span: where the momentum flux ρA v² that the span equation leaves
out is a share of the tension worth saying (docs/nonlinear-web.md); ``Line.warnings`` lists
it and ``webline validate`` prints it."""

from __future__ import annotations

from webline.spec.check import profile_values
from webline.spec.schema import LineSpec, UnwindSpec

#: share of the lowest tension reference above which the web's momentum flux ρA v², which the
#: span equation leaves out, is worth a warning: a loadcell's accuracy class is ~1 %
MOMENTUM_SHARE = 0.01


def web_mass_warnings(spec: LineSpec) -> list[str]:
    """'key: problem' where the web's momentum flux ρA v² at the line's top speed (its base
    ``speed`` profile) exceeds ``MOMENTUM_SHARE`` of the lowest tension it runs at (the zones'
    references and the wound-in tension): the spans neglect it (docs/nonlinear-web.md)."""
    web = spec.web
    top = max(abs(v) for v in profile_values(spec.speed))
    tensions = [v for s in spec.spans if s.tension is not None
                for v in profile_values(s.tension) if v > 0.0]
    tensions += [r.wound_in_tension for r in spec.rollers if isinstance(r, UnwindSpec)]
    if not tensions:
        return []
    flux = web.density * web.thickness * web.width * top * top
    lowest = min(tensions)
    if flux <= MOMENTUM_SHARE * lowest:
        return []
    return [f"speed: at {top:.4g} m/s the web's momentum flux ρA v² = {flux:.4g} N is "
            f"{100 * flux / lowest:.3g} % of its lowest tension ({lowest:.4g} N); the span "
            "model leaves it out (docs/nonlinear-web.md)"]
