"""Web span tension from conservation of web mass (thesis 5.33, 6.8, 6.10, 6.12), elastic or
Kelvin-Voigt (docs/winder.md, Viscoelastic span)."""

from __future__ import annotations


def tension(stretch: float) -> float:
    """Tension [N] of a span whose stretch force AE·strain is ``stretch`` [N].

    A negative stretch is a slack span: the web is longer than the span by
    ``-stretch * length / EA`` and carries no tension (it cannot push).
    """
    return stretch if stretch > 0.0 else 0.0


def stretch_rate(length: float, ea: float, v_in: float, v_out: float,
                 tension_in: float, tension_out: float) -> float:
    """d(stretch)/dt [N/s] of a span of ``length`` [m] and web stiffness ``ea`` [N].

    Web enters at ``v_in`` [m/s] carrying the upstream tension ``tension_in`` [N] and leaves at
    ``v_out`` [m/s] with this span's tension ``tension_out`` [N]. From mass conservation of the
    unstrained web, d/dt[L(1 - e)] = v_in(1 - e_in) - v_out(1 - e_out), e = T/EA, which is
    L dT/dt = EA (v_out - v_in) + T_in v_in - T v_out (thesis 6.8). A slack span leaves
    unstrained, so ``tension_out`` is ``tension(stretch)``: slack is taken up before tension
    builds again.
    """
    return (ea * (v_out - v_in) + tension_in * v_in - tension_out * v_out) / length


def unstrained_length(length: float, ea: float, stretch: float) -> float:
    """Unstrained web stored in a span [m] (to first order in strain, as 6.8 assumes)."""
    return length * (1.0 - stretch / ea)


def kelvin_voigt_tension(stretch: float, stretch_rate: float, retardation: float) -> float:
    """Tension [N] the rollers feel from a Kelvin-Voigt span: T = EA (ε + τ dε/dt) with
    ``stretch`` = EA ε [N], ``stretch_rate`` = EA dε/dt [N/s] (from ``stretch_rate``, the same
    mass balance as an elastic span) and ``retardation`` τ = η/E [s].

    A slack span (stretch <= 0) carries nothing, its damper included; a taut one cannot push
    (T >= 0, the web buckles rather than carry compression). τ = 0 is ``tension(stretch)``.
    """
    if stretch <= 0.0:
        return 0.0
    felt = stretch + retardation * stretch_rate
    return felt if felt > 0.0 else 0.0
