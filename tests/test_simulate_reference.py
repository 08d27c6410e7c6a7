"""The default `simulate` against an independent stiff scipy reference.

The reference is written here in plain numpy (one LuGre segment, the joint, a velocity PI), solved
with LSODA at rtol 1e-11 piece by piece between the reference's discontinuities, which is how a
careful scipy user handles a discontinuous input. The library's default stepping must agree to
1e-6 deg in position and 1e-4 N*m in actuator torque at every sample, with no options passed.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lugre_jax as lj

SEG = dict(Fc=None, Fs=None, vs=None, sigma0=None, sigma1=None, sigma2=None)
J, KP, KI = 0.128, 8.0, 60.0
POS_TOL_DEG, TORQUE_TOL_NM = 1e-6, 1e-4


def _segment():
    m = lj.paper_segment(1)
    return {k: float(getattr(m, k)) for k in SEG}


def _steps(levels, dwell):
    def ref(t):
        k = min(int(math.floor(t / dwell + 1e-12)), len(levels) - 1)
        theta = sum(levels[:k]) * dwell + levels[k] * (t - k * dwell)
        return theta, levels[k]
    return ref, [k * dwell for k in range(1, len(levels))]


def _ramp(v_final, ramp_s):
    def ref(t):
        r = v_final / ramp_s
        tr = min(t, ramp_s)
        return 0.5 * r * tr * tr + v_final * max(t - ramp_s, 0.0), r * tr
    return ref, [ramp_s]


def _sine(a, f):
    w = 2 * math.pi * f
    return (lambda t: (a * math.sin(w * t), a * w * math.cos(w * t))), []


def _table(ts, vs):
    """Piecewise-linear velocity through (ts, vs), right-continuous at a repeated time (a step)."""
    def ref(t):
        theta, v = vs[0] * min(t, ts[0]), vs[0] if t < ts[0] else vs[-1]
        for a, b, va, vb in zip(ts[:-1], ts[1:], vs[:-1], vs[1:]):
            if b > a and t >= a:
                u = min(t, b)
                slope = (vb - va) / (b - a)
                theta += (u - a) * (va + 0.5 * slope * (u - a))
                if t < b:
                    v = va + slope * (t - a)
        return theta + vs[-1] * max(t - ts[-1], 0.0), v
    return ref, sorted(set(x for x in ts if x > 0))


def scipy_reference(ref, jumps, duration, hz):
    p = _segment()

    def rhs(t, y):
        theta, omega, z, xi = y
        _, v_ref = ref(t)
        g = p["Fc"] + (p["Fs"] - p["Fc"]) * math.exp(-(omega / p["vs"]) ** 2)
        dz = omega - p["sigma0"] * abs(omega) * z / g
        f = p["sigma0"] * z + p["sigma1"] * dz + p["sigma2"] * omega
        tau = KP * (v_ref - omega) + KI * xi
        return [omega, (tau - f) / J, dz, v_ref - omega]

    ts = np.arange(int(round(duration * hz)) + 1) / hz
    edges = [0.0] + sorted(set(j for j in jumps if 0 < j < duration)) + [duration]
    ys, y = np.zeros((len(ts), 4)), np.zeros(4)
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (ts >= a) & ((ts < b) | (b == duration))
        r = solve_ivp(rhs, (a, b), y, method="LSODA", rtol=1e-11, atol=1e-13, max_step=1e-3,
                      t_eval=ts[sel], first_step=1e-6)
        assert r.success, r.message
        ys[sel] = r.y.T
        y = solve_ivp(rhs, (a, b), y, method="LSODA", rtol=1e-11, atol=1e-13, max_step=1e-3,
                      first_step=1e-6).y[:, -1]
    torque = np.array([KP * (ref(t)[1] - yy[1]) + KI * yy[3] for t, yy in zip(ts, ys)])
    return ys[:, 0], torque


CASES = {
    # the staircase: sharp steps on the sample grid
    "staircase_on_grid": (lj.VelocitySteps([0.02, 0.1, -0.05, 0.5], dwell_s=5.0),
                          _steps([0.02, 0.1, -0.05, 0.5], 5.0), 20.0, 100.0),
    # steps off the sample grid
    "staircase_off_grid": (lj.VelocitySteps([0.05, -0.03, 0.3, 0.0, -1.0], dwell_s=1.2345),
                           _steps([0.05, -0.03, 0.3, 0.0, -1.0], 1.2345), 6.2, 100.0),
    "ramp": (lj.VelocityRamp(1.5, 4.0), _ramp(1.5, 4.0), 6.0, 100.0),
    "sine": (lj.PositionSine(0.05, 0.4), _sine(0.05, 0.4), 5.0, 200.0),
    "table": (lj.VelocityTable([0.0, 0.7, 0.7, 2.13, 3.0], [0.0, 0.2, -0.1, 0.4, 0.01]),
              _table([0.0, 0.7, 0.7, 2.13, 3.0], [0.0, 0.2, -0.1, 0.4, 0.01]), 4.0, 50.0),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_default_simulate_matches_stiff_scipy(name):
    reference, (ref_fn, jumps), duration, hz = CASES[name]
    system = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=J),
                       controller=lj.VelocityPID(kp=KP, ki=KI), reference=reference)
    sol = lj.simulate(system, duration, hz)  # the default stepping, nothing chosen
    assert int(sol.result) == lj.RESULT_OK
    theta, torque = scipy_reference(ref_fn, jumps, duration, hz)
    assert np.max(np.abs(np.asarray(sol.theta) - theta)) <= POS_TOL_DEG
    assert np.max(np.abs(np.asarray(sol.torque_nm) - torque)) <= TORQUE_TOL_NM


def test_fixed_step_check_reports_the_coarse_step():
    # The case: Tsit5 at 2.5 ms across a sharp velocity step is far from the reference; the
    # batched self-check says so, and a fine step passes it.
    import diffrax

    system = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=J), controller=lj.VelocityPID(kp=KP, ki=KI),
                       reference=lj.VelocitySteps([0.02, 0.1, -0.05, 0.5], dwell_s=5.0))
    swarm = lj.broadcast_system(system, 3)
    coarse = lj.check_stepping(swarm, 20.0, 100.0, lj.FixedStep(diffrax.Bosh3(), dt=0.02), batched=True)
    assert coarse.torque_nm > 0.1 and coarse.lanes == (0, 1, 2) and coarse.failed_lanes == ()
    fine = lj.check_stepping(system, 20.0, 100.0, lj.FixedStep(diffrax.Tsit5(), dt=2.5e-4))
    assert fine.torque_nm < 0.1 * coarse.torque_nm
