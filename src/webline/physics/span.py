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


def exact_stretch_rate(length: float, ea: float, v_in: float, v_out: float,
                       tension_in: float, tension_out: float, stretch: float) -> float:
    """d(stretch)/dt [N/s] from exact conservation of web mass (docs/errata.md E-6.6).

    A span of ``length`` [m] stores L/(1 + ε) of unstrained web, ε = ``stretch``/``ea`` (a
    negative stretch: slack, more web than the span); web enters at ``v_in`` [m/s] with the
    strain ``tension_in``/EA and leaves at ``v_out`` [m/s] with ``tension_out``/EA (the
    span's clipped stretch, ``tension``), each carrying v/(1 + ε) of unstrained web:

        d/dt[L/(1 + ε)] = v_in/(1 + ε_in) - v_out/(1 + ε_out)
        ds/dt = (EA + s)² / L · [v_out/(EA + T_out) - v_in/(EA + T_in)].

    To first order in strain this is ``stretch_rate`` (thesis 6.8); at 3 % strain the
    first-order draw is 3 % off. [N/s]
    """
    grow = ea + stretch
    return grow * grow * (v_out / (ea + tension_out) - v_in / (ea + tension_in)) / length


def length_change_rate(ea: float, stretch: float, length_rate: float, length: float,
                       exact: bool) -> float:
    """d(stretch)/dt [N/s] a span of ``length`` [m] gains as it lengthens at ``length_rate``
    [m/s] (a dancer's, docs/winder.md D1), the web stored in it unchanged: (EA - s) L'/L to
    first order (d/dt[L (1 - ε)] = 0), (EA + s) L'/L exactly (d/dt[L/(1 + ε)] = 0)."""
    factor = ea + stretch if exact else ea - stretch
    return factor * length_rate / length


def unstrained_flow(speed: float, ea: float, stretch: float, exact: bool) -> float:
    """Unstrained web [m/s] carried by web moving at ``speed`` [m/s] with stretch
    ``stretch`` = EA·ε [N]: v/(1 + ε) exactly, v (1 - ε) to first order (thesis 6.8)."""
    if exact:
        return speed * ea / (ea + stretch)
    return speed * (1.0 - stretch / ea)


def stored_length(length: float, ea: float, stretch: float, exact: bool) -> float:
    """Unstrained web stored in a span of ``length`` [m] at ``stretch`` [N]: L/(1 + ε)
    exactly, L (1 - ε) to first order (``unstrained_length``). [m]"""
    if exact:
        return length * ea / (ea + stretch)
    return unstrained_length(length, ea, stretch)


def draw_ratio(ea: float, upstream: float, upstream_master: float, exact: bool) -> float:
    """Steady speed of a node over the master's [-]: the same unstrained web passes every
    node, the node's web carrying the stretch ``upstream`` [N] of the span entering it and
    the master's ``upstream_master`` [N]: (EA + s_i)/(EA + s_m) exactly, (EA - s_m)/(EA - s_i)
    to first order (thesis 6.22)."""
    if exact:
        return (ea + upstream) / (ea + upstream_master)
    return (ea - upstream_master) / (ea - upstream)
