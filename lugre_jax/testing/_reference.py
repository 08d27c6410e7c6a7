"""An independent reference for the project's simulator: the rigid joint with LuGre friction
(Stribeck exponent 2) under a velocity PI following a velocity staircase, solved by scipy's
``solve_ivp`` as a careful user would, restarted at each step of the reference so that no solve
crosses a discontinuity. Nothing here imports the rest of the package."""

from __future__ import annotations

import math

import numpy as np

_EPS = 1e-12  # a sample this close to a reference step belongs to the step that starts there


def velocity_staircase(J: float, Fc: float, Fs: float, vs: float, sigma0: float, sigma1: float, sigma2: float,
                       kp: float, ki: float, levels, dwell: float, duration: float, hz: float, *,
                       method: str = "Radau", rtol: float = 1e-10, atol: float = 1e-13,
                       first_step: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Sample times ``ts = arange(round(duration*hz) + 1)/hz`` [s] and the states there (n x 4:
    theta [deg], omega [deg/s], bristle z [deg], the PI's integral xi [deg]); each level is held
    ``dwell`` s, the last one to ``duration``. Raises ``RuntimeError`` if a solve fails.

    Paper units: torque ``kp*(v_ref - omega) + ki*xi`` [N*m] drives ``J*domega/dt = torque - F``,
    ``F = sigma0*z + sigma1*dz/dt + sigma2*omega``, ``dz/dt = omega - sigma0*|omega|*z/g``,
    ``g = Fc + (Fs - Fc)*exp(-(omega/vs)^2)``."""
    from scipy.integrate import solve_ivp

    def rhs_for(v_ref):
        def rhs(t, y):
            theta, omega, z, xi = y
            g = Fc + (Fs - Fc) * math.exp(-(omega / vs) ** 2)
            dz = omega - sigma0 * abs(omega) * z / g
            f = sigma0 * z + sigma1 * dz + sigma2 * omega
            return [omega, (kp * (v_ref - omega) + ki * xi - f) / J, dz, v_ref - omega]
        return rhs

    ts = np.arange(int(round(duration * hz)) + 1) / hz
    states, y = np.zeros((len(ts), 4)), np.zeros(4)
    options = {} if first_step is None else {"first_step": first_step}
    for k, v in enumerate(levels):
        a = k * dwell
        if a >= duration:
            break
        last = k == len(levels) - 1 or (k + 1) * dwell >= duration
        b = duration if last else (k + 1) * dwell
        sel = (ts >= a - _EPS) & ((ts < b - _EPS) | last)
        te = ts[sel] if ts[sel][-1] >= b - _EPS else np.append(ts[sel], b)
        r = solve_ivp(rhs_for(v), (a, b), y, method=method, rtol=rtol, atol=atol, t_eval=te, **options)
        if not r.success:
            raise RuntimeError(f"velocity_staircase: {method} failed on step {k} ({a}-{b} s): {r.message}")
        states[sel] = r.y[:, :int(sel.sum())].T
        y = r.y[:, -1]
        if last:
            break
    return ts, states
