"""Drive-train analyses of thesis Chapters 2-3 (and 4.9-4.10): equivalent inertia and PI tuning,
belt-drive transfer functions and sensitivities, singular perturbation, natural frequencies,
solid-motion analysis of backlash, backlash error bounds and output-statistics shifts.

Modules: ``params`` (parameter sets, data files), ``equivalent`` (2.1-2.9), ``belt``
(2.10-2.25, 2.35-2.41), ``singular_perturbation`` (Appendix A), ``belt_singular_perturbation``
(2.26-2.34), ``backlash`` (3.1-3.10), ``backlash_bounds`` (3.33-3.66, 4.7-4.10).
See docs/drivetrain.md.
"""

from webline.analysis.drivetrain.params import (
    BacklashDrive,
    BeltDrive,
    SpeedPI,
    ecp_rectilinear_plant,
    hswl_unwind_belt_drive,
    load_parameter_set,
)

__all__ = [
    "BacklashDrive",
    "BeltDrive",
    "SpeedPI",
    "ecp_rectilinear_plant",
    "hswl_unwind_belt_drive",
    "load_parameter_set",
]
