"""Web slip over a roller: capstan limit, slip arc, traction law and web speed (thesis Ch. 5,
5.9-5.13, 5.35-5.47, re-derived; docs/errata.md).

Conventions. The web arrives at the roller from the upstream span with tension ``t_in`` [N]
and leaves into the downstream span with ``t_out`` [N]; the wrap angle is ``wrap`` [rad]. The
web is massless in the contact (as in 5.35-5.39), so the friction force the roller exerts on
the web, positive in the direction of travel, is always

    F = t_in - t_out                                                     (5.39)

and the roller receives -F at its surface: its torque balance keeps R (t_out - t_in) whether
the web sticks or slips. The *slip velocity* is s = v_r - v [m/s]: roller surface speed minus
the web speed where the web meets the roller (at the strain of the upstream span, the speed
(5.33) uses). s > 0: the roller runs faster and drags the web forward (F > 0, t_in > t_out);
s < 0: the web overruns a roller that holds it back (F < 0, t_out > t_in).

Centrifugal force lowers the contact pressure: the normal force per radian is T - t_c with
t_c = ρA v² (5.10), so every law below works with T - t_c (``t_c`` [N] from
``centrifugal_tension``; pass 0 to drop it as 5.40-5.47 do). A web with T <= t_c lifts off
and the contact transmits nothing but the viscous term.

Traction law (5.42-5.43, made set-valued and sign-general). With the tension along the wrap
following the capstan from the entry in the direction of slip (5.40, generalised), the
normal force is N± = (t_in - t_c)(1 - e^{∓μα})/(±μ) (5.41) and

    stick:  s = 0 and  -Fs⁻ <= F <= Fs⁺,  Fs⁺ = (t_in - t_c)(1 - e^{-μα}) = μ N⁺,
                                          Fs⁻ = (t_in - t_c)(e^{μα} - 1)  = μ N⁻,
    slip:   F = ±Fc± + b s  (sign of s),  Fc± = (μ'/μ) Fs±,

μ (= μ0, the thesis's static coefficient) >= μ' (Coulomb) >= 0, b [N·s/m] > 0 the viscous
slope. The stick band is exactly the capstan relation e^{-μα} <= (t_out - t_c)/(t_in - t_c)
<= e^{μα} in both directions. A traction nip on the roller (docs/winder.md, Nip) presses the
web with a load N_n between the roller and a pressure roller: its two faces add a static
capacity 2μ_n N_n to both Fs± and a Coulomb force 2μ_n' N_n to both Fc± (``nip``, ``nip_k``
below; 0 without a nip), independent of the tensions. Inverting the slip branch gives s as
an explicit, continuous, monotone function of F (a dead zone of width Fc± divided by b):
the general-sign form of (5.44)/(5.47),

    s = (t_in/b)[1 - p (1 - e^{-σμα}) - t_out/t_in] if it has the sign σ, else 0, p = μ'/μ,

which is the printed (5.47) for σ = +1 only (E-5.3). Because F and s never have opposite
signs, the power F·s dissipated by slip is never negative.

Stick-slip with μ > μ' is a hysteresis: ``slip_state`` is the rule that carries it, evaluated
once per sample (controller tick) and held while the integrator takes its stages; within the
held state ``slip_velocity`` is continuous in the tensions, so a fixed-step RK4 never sees a
switch inside a step and a switch needs F to cross the whole band between Fc and Fs, which
the dynamics, not the step, decide (no chattering; see docs/slip.md).

Plain scalar maths with no calls between functions, so numba compiles each one alone.
"""

from __future__ import annotations

import math


def centrifugal_tension(mass_per_length: float, speed: float) -> float:
    """Centrifugal tension t_c = ρA v² [N] of a web of ``mass_per_length`` ρA [kg/m] moving at
    ``speed`` [m/s] round a roller (the ρA R² ω² of 5.10-5.13)."""
    return mass_per_length * speed * speed


def capstan_ratio(mu: float, wrap: float) -> float:
    """Largest tension ratio e^{μα} [-] friction ``mu`` [-] holds over ``wrap`` α [rad] (5.12
    at θ = α without the centrifugal term: the capstan relation T_h/T_l = e^{μα})."""
    return math.exp(mu * wrap)


def capstan_limit(t_low: float, mu: float, wrap: float, t_c: float) -> float:
    """Largest tension [N] on one side of the wrap that friction holds against ``t_low`` [N] on
    the other, without the web sliding over the whole wrap (5.12 at θ = α):
    t_c + (t_low - t_c) e^{μα}; ``mu`` [-], ``wrap`` [rad], ``t_c`` [N] (centrifugal tension).
    A web at or below t_c lifts off and holds only t_low."""
    u = t_low - t_c
    if u <= 0.0:
        return t_low
    return t_c + u * math.exp(mu * wrap)


def arc_tension(theta: float, t_start: float, mu: float, t_c: float, direction: float) -> float:
    """Tension [N] at ``theta`` [rad] into a slip arc that starts with ``t_start`` [N] (5.12):
    t_c + (t_start - t_c) e^{direction·μθ}; ``direction`` +1 where tension rises along the
    arc, -1 where it falls; ``mu`` [-], ``t_c`` [N]."""
    return t_c + (t_start - t_c) * math.exp(direction * mu * theta)


def slip_arc(t_in: float, t_out: float, mu: float, t_c: float) -> float:
    """Slip-arc angle φ [rad] (5.13) between ``t_in`` and ``t_out`` [N], either larger:
    φ = |ln((t_out - t_c)/(t_in - t_c))| / μ, with ``mu`` [-] and centrifugal tension ``t_c``
    [N]. The web adheres over the rest of the wrap and slips on an arc φ at the exit (Sec. 5.2,
    E-5.1); φ > wrap means it slides over the whole wrap (the capstan limit is exceeded).
    Infinite where a side is at or below t_c (lift-off) and the tensions differ, or mu = 0."""
    if t_in == t_out:
        return 0.0
    a = t_in - t_c
    b = t_out - t_c
    if a <= 0.0 or b <= 0.0 or mu <= 0.0:
        return math.inf
    return abs(math.log(b / a)) / mu


def normal_force(t_in: float, wrap: float, mu: float, t_c: float, direction: float) -> float:
    """Resultant normal force N [N] of the wrap when the tension follows the capstan from the
    entry tension ``t_in`` [N] (5.40-5.41, generalised): N = (t_in - t_c)(1 - e^{-σμα})/(σμ)
    with σ = ``direction`` (+1: tension falls along the wrap, the thesis's case; -1: it rises),
    ``wrap`` α [rad], ``mu`` [-], ``t_c`` [N]. Tends to (t_in - t_c) α as μ -> 0."""
    u = t_in - t_c
    if u <= 0.0:
        return 0.0
    x = direction * mu * wrap
    if abs(x) < 1e-8:
        return u * wrap * (1.0 - 0.5 * x)
    return u * wrap * (1.0 - math.exp(-x)) / x


def stiction_limit(t_in: float, wrap: float, mu: float, t_c: float, direction: float,
                   nip: float = 0.0) -> float:
    """Largest friction force magnitude [N] the wrap holds without slipping, μ N (5.43's
    c = μ0 F_n): forward (``direction`` +1, t_in > t_out) (t_in - t_c)(1 - e^{-μα}), backward
    (-1) (t_in - t_c)(e^{μα} - 1), plus a traction nip's static capacity ``nip`` 2μ_n N_n [N].
    |t_in - t_out| within it is the capstan relation. Arguments as ``normal_force``; ``mu`` is
    the static coefficient μ0."""
    u = t_in - t_c
    if u <= 0.0:
        return nip
    if direction > 0.0:
        return u * (1.0 - math.exp(-mu * wrap)) + nip
    return u * (math.exp(mu * wrap) - 1.0) + nip


def friction_force(slip: float, t_in: float, wrap: float, mu: float, mu_k: float,
                   viscous: float, t_c: float, nip_k: float = 0.0) -> float:
    """Friction force F [N] on the web while it slips at ``slip`` s = v_r - v [m/s] (5.42,
    slip branch): sign(s) Fc + b s, Fc = μ' N with N of ``normal_force`` in the direction of s,
    plus a traction nip's Coulomb force ``nip_k`` 2μ_n' N_n [N].

    ``t_in`` [N] entry tension, ``wrap`` [rad], ``mu`` μ0 [-] (sets the tension distribution,
    5.40), ``mu_k`` Coulomb μ' [-], ``viscous`` b [N·s/m], ``t_c`` [N]. At s = 0 the force is
    set-valued (any F in the stiction band; 5.42's c·δ(s) term) and 0.0 is returned.
    """
    if slip == 0.0:
        return 0.0
    u = t_in - t_c
    if u < 0.0:
        u = 0.0
    if mu > 0.0:
        if slip > 0.0:
            fc = (mu_k / mu) * u * (1.0 - math.exp(-mu * wrap))
        else:
            fc = (mu_k / mu) * u * (math.exp(mu * wrap) - 1.0)
    else:
        fc = mu_k * u * wrap
    fc += nip_k
    if slip > 0.0:
        return fc + viscous * slip
    return -fc + viscous * slip


def slip_velocity(t_in: float, t_out: float, wrap: float, mu: float, mu_k: float,
                  viscous: float, t_c: float, slipping: int, nip_k: float = 0.0) -> float:
    """Slip velocity s = v_r - v [m/s] of the web over a roller: the web speed is v_r - s.

    General-sign replacement of (5.44)/(5.47) (E-5.3). ``t_in``, ``t_out`` [N] the tensions of
    the upstream and downstream spans, ``wrap`` α [rad], ``mu`` μ0 [-] static coefficient,
    ``mu_k`` μ' <= μ0 [-] Coulomb coefficient, ``viscous`` b > 0 [N·s/m], ``t_c`` [N]
    centrifugal tension (``centrifugal_tension`` at the roller's surface speed, or 0).
    ``slipping`` is the held state of ``slip_state`` (0 stuck, 1 slipping); ``nip_k`` [N] a
    traction nip's Coulomb force 2μ_n' N_n, added to both Fc± (0: no nip).

    Stuck: 0.0 exactly, so a roller that never slips gives the no-slip model bit for bit.
    Slipping: with F = t_in - t_out and Fc± the Coulomb forces,
    s = (F - Fc⁺)/b for F > Fc⁺, (F + Fc⁻)/b for F < -Fc⁻, else 0: continuous, monotone
    (non-decreasing in t_in, non-increasing in t_out), and F·s >= 0.
    """
    if slipping == 0:
        return 0.0
    f = t_in - t_out
    u = t_in - t_c
    if u < 0.0:
        u = 0.0
    if mu > 0.0:
        e = math.exp(mu * wrap)
        fc_fwd = (mu_k / mu) * u * (1.0 - 1.0 / e)
        fc_back = (mu_k / mu) * u * (e - 1.0)
    else:
        fc_fwd = mu_k * u * wrap
        fc_back = fc_fwd
    fc_fwd += nip_k
    fc_back += nip_k
    if f > fc_fwd:
        return (f - fc_fwd) / viscous
    if f < -fc_back:
        return (f + fc_back) / viscous
    return 0.0


def slip_state(t_in: float, t_out: float, wrap: float, mu: float, mu_k: float, t_c: float,
               slipping: int, nip: float = 0.0, nip_k: float = 0.0) -> int:
    """Stick/slip state (0 stuck, 1 slipping) for the next sample, from the current one.

    Evaluate once per sample (controller tick) on the sampled tensions and hold the result
    through the integrator's stages. A stuck web breaks away when F = ``t_in`` - ``t_out``
    leaves the stiction band [-Fs⁻, Fs⁺] (the capstan limit with μ0 = ``mu``); a slipping web
    sticks again once F is back inside the Coulomb band [-Fc⁻, Fc⁺] (where its slip velocity
    has reached 0). With μ' < μ0 the two bands differ: that is the hysteresis of stiction.
    A traction nip widens the stiction band by ``nip`` 2μ_n N_n [N] and the Coulomb band by
    ``nip_k`` 2μ_n' N_n [N] on both sides. Other arguments as ``slip_velocity`` ([N], [rad],
    [-], [-], [N]).
    """
    f = t_in - t_out
    u = t_in - t_c
    if u < 0.0:
        u = 0.0
    e = math.exp(mu * wrap)
    fs_fwd = u * (1.0 - 1.0 / e)
    fs_back = u * (e - 1.0)
    if slipping == 0:
        if f > fs_fwd + nip or f < -(fs_back + nip):
            return 1
        return 0
    if mu > 0.0:
        ratio = mu_k / mu
        if -(ratio * fs_back + nip_k) <= f <= ratio * fs_fwd + nip_k:
            return 0
        return 1
    if abs(f) <= nip_k:  # f == 0 without a nip
        return 0
    return 1


def slip_power(t_in: float, t_out: float, slip: float) -> float:
    """Power [W] dissipated by slip at the roller: F·s = (t_in - t_out)·``slip`` (forces [N],
    slip velocity [m/s]). Never negative for ``slip_velocity`` (the second law); the printed
    (5.47) makes it negative when 0 < t_in - t_out < Fc (E-5.3)."""
    return (t_in - t_out) * slip


def creep_power(t_in: float, t_out: float, web_speed: float, ea: float) -> float:
    """Power [W] dissipated where the strain changes from t_in/EA to t_out/EA on the roller
    (the exit slip arc, Sec. 5.2): v (t_in - t_out)² / (2 EA (1 + t_in/EA)), ``web_speed`` v
    [m/s] where the web meets the roller, ``ea`` [N]. Exact for a linearly elastic web in steady
    state (E-5.1); adhesion at the entry makes it >= 0 for either sign of t_in - t_out, the
    entry arc would make it <= 0, which is why the slip arc is at the exit."""
    d = t_in - t_out
    return web_speed * d * d / (2.0 * ea * (1.0 + t_in / ea))


def slip_rate(ea: float, viscous: float, length_in: float, length_out: float, mu: float,
              mu_k: float, wrap: float, speed: float) -> float:
    """Bound [1/s] on the fastest decay rate of the two spans round a slipping roller.

    With span tensions obeying (5.33), L dT/dt = EA (v_out - v_in) + T_in v_in - T v_out, and
    the web speed v_r - s of ``slip_velocity``, the Jacobian of (t_in, t_out) has trace
    -[(EA/b)(κ/L_in + 1/L_out) + v (1/L_in + 1/L_out)] to first order in strain, with
    κ = ∂(b s)/∂t_in <= 1 + (μ'/μ)(e^{μα} - 1) (backward slip). Both eigenvalues are real and
    negative, so |trace| bounds the fastest; the slip part alone is the first term. A fixed-step
    RK4 of step h is stable for h·rate < 2.78. ``ea`` [N], ``viscous`` b [N·s/m], lengths [m],
    ``mu``, ``mu_k`` [-], ``wrap`` [rad], ``speed`` [m/s] the web speed.
    """
    kappa = 1.0 + (mu_k / mu) * (math.exp(mu * wrap) - 1.0) if mu > 0.0 else 1.0 + mu_k * wrap
    return (ea / viscous * (kappa / length_in + 1.0 / length_out)
            + speed * (1.0 / length_in + 1.0 / length_out))
