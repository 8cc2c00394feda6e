"""Event-located reference integration of a slip ``Chain`` (see ``slip_chain``): scipy's
``solve_ivp`` between stick/slip switches, each switch located as an event."""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from webline.physics import slip as sl
from webline.studies.slip_chain import Chain, Run, chain_layout, evaluate, record_run


def _event_margin(chain: Chain, r: int, t: float, y: np.ndarray, mode: int) -> float:
    """Signed distance [N] of F from the switching boundary of roller ``r`` in ``mode``:
    positive while the mode holds (stuck: inside the stiction band; slipping: outside the
    Coulomb band)."""
    modes = np.zeros(len(chain.rollers), dtype=int)
    point = evaluate(chain, t, y, modes)
    c = chain.rollers[r].contact
    assert c is not None
    t_in, t_out = point.t_up[r], point.t_down[r]
    t_c = sl.centrifugal_tension(c.mass_per_length, point.surface[r])
    f = t_in - t_out
    fs_fwd = sl.stiction_limit(t_in, c.wrap, c.mu, t_c, 1.0)
    fs_back = sl.stiction_limit(t_in, c.wrap, c.mu, t_c, -1.0)
    if mode == 0:
        return min(fs_fwd - f, fs_back + f)
    ratio = c.mu_k / c.mu
    return max(f - ratio * fs_fwd, -ratio * fs_back - f)


def simulate_events(chain: Chain, y0: np.ndarray, modes0: np.ndarray, duration: float,
                    t_eval: np.ndarray, *, method: str = "DOP853", rtol: float = 1e-10,
                    atol: float = 1e-9, max_step: float = 0.01, t0: float = 0.0) -> Run:
    """Adaptive reference: ``solve_ivp`` between stick/slip switches located as events
    (break-away when F leaves the stiction band, re-stick when it enters the Coulomb band).
    Rollers with μ' = μ0 have no hysteresis and are kept in the slipping state (their slip
    velocity is already continuous and zero inside the band). Samples at ``t_eval`` [s]."""
    lay = chain_layout(chain)
    hysteresis = [r for r, roller in enumerate(chain.rollers)
                  if roller.contact is not None and roller.contact.law == "webline"
                  and roller.contact.mu_k < roller.contact.mu]
    modes = np.asarray(modes0, dtype=int).copy()
    for r, roller in enumerate(chain.rollers):
        if roller.contact is not None and r not in hysteresis and roller.contact.law == "webline":
            modes[r] = 1
    t_end = t0 + duration
    t, y = t0, y0.copy()
    times: list[float] = []
    states: list[np.ndarray] = []
    mode_rec: list[np.ndarray] = []
    switch_times: list[list[float]] = [[] for _ in chain.rollers]
    while True:
        events = []
        for r in hysteresis:
            def event(tt: float, yy: np.ndarray, r: int = r, m: int = int(modes[r])) -> float:
                return _event_margin(chain, r, tt, yy, m)

            event.terminal = True  # type: ignore[attr-defined]
            event.direction = -1  # type: ignore[attr-defined]
            events.append(event)

        def rhs(tt: float, yy: np.ndarray, modes: np.ndarray = modes) -> np.ndarray:
            dy = np.empty(lay.size)
            evaluate(chain, tt, yy, modes, dy)
            return dy

        mask = (t_eval >= t) & (t_eval <= t_end)
        sol = solve_ivp(rhs, (t, t_end), y, method=method, t_eval=t_eval[mask], events=events,
                        rtol=rtol, atol=atol, max_step=max_step)
        for tt, yy in zip(sol.t, sol.y.T, strict=True):
            if times and tt <= times[-1]:
                continue
            times.append(float(tt))
            states.append(yy.copy())
            mode_rec.append(modes.copy())
        if sol.status != 1:
            break
        # the first event that fired ends this segment
        hits = [(ev[0], j) for j, ev in enumerate(sol.t_events) if len(ev)]
        t_hit, j = min(hits)
        r = hysteresis[j]
        y = sol.y_events[j][0].copy()
        t = float(t_hit)
        modes = modes.copy()
        modes[r] = 1 - modes[r]
        switch_times[r].append(t)
        if t >= t_end:
            break
    return record_run(chain, times, states, mode_rec, y0, switch_times)
