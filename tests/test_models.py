"""Friction and plant models: closed forms, the paper's parameter sets, bounds and units."""

import dataclasses
import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import lugre_jax as lj
from lugre_jax.plant import paper_inertia_per_segment


def test_paper_inertia_from_eq18_is_inconsistent_and_reported():
    J = paper_inertia_per_segment()
    assert J[1] == pytest.approx(0.1280, abs=5e-5)
    assert J[3] == pytest.approx(0.1280, abs=5e-5)
    assert J[2] == pytest.approx(0.1924, abs=5e-4)
    assert lj.PAPER_J == 0.128


def test_stribeck_closed_form_and_high_velocity_form():
    m = lj.Stribeck(Fc=0.86, Fs=2.357, vs=0.048, sigma2=3.0502)
    v = np.array([-1.0, -0.01, 0.01, 0.048, 1.0])
    expect = np.sign(v) * (0.86 + (2.357 - 0.86) * np.exp(-(v / 0.048) ** 2)) + 3.0502 * v
    np.testing.assert_allclose(m.steady_state(v), expect, rtol=1e-14)
    hv = lj.Stribeck(Fc=4.5203, Fs=4.5203, vs=1.0, sigma2=0.0012)  # eq. (11)
    np.testing.assert_allclose(hv.steady_state(v), np.sign(v) * 4.5203 + 0.0012 * v, rtol=1e-14)
    cv = lj.CoulombViscous(Fc=4.5203, sigma2=0.0012)
    np.testing.assert_allclose(cv.steady_state(v), hv.steady_state(v), rtol=1e-14)


def test_traced_delta_equals_static_delta_and_is_differentiable():
    v = jnp.linspace(-0.2, 0.2, 41)
    a = lj.Stribeck(1.0, 2.0, 0.05, 0.1)  # delta = 2, a compile-time constant
    b = lj.Stribeck(1.0, 2.0, 0.05, 0.1, delta=jnp.asarray(2.0))
    np.testing.assert_allclose(a.steady_state(v), b.steady_state(v), rtol=1e-14, atol=1e-15)
    d = jax.grad(lambda dl: lj.Stribeck(1.0, 2.0, 0.05, 0.1, delta=dl).steady_state(v).sum())(2.0)
    assert np.isfinite(d)  # v = 0 is in the grid: the guarded power has a finite derivative there
    h = 1e-6
    fd = (lj.Stribeck(1.0, 2.0, 0.05, 0.1, delta=2.0 + h).steady_state(v).sum()
          - lj.Stribeck(1.0, 2.0, 0.05, 0.1, delta=2.0 - h).steady_state(v).sum()) / (2 * h)
    assert float(d) == pytest.approx(float(fd), rel=1e-6)


def test_paper_friction_is_table1_and_continuous():
    fr = lj.paper_friction()
    for k, v in [(1, 0.01), (2, 0.5), (3, 3.0)]:  # inside each segment, far from the blends
        assert float(fr.steady_state(v)) == pytest.approx(float(lj.paper_segment(k).steady_state(v)), rel=1e-12)
    # the curve is continuous across the edges (Table 1 was fitted that way): jumps < 1%
    for e in (0.05, 1.2):
        lo, hi = fr.steady_state(e * 0.999), fr.steady_state(e * 1.001)
        assert abs(float(hi - lo)) < 0.01 * float(lo)
    # hard switch (blend = 0) selects exactly one segment per side
    hard = lj.Segmented(fr.segments, fr.edges, blend=0.0)
    assert float(hard.steady_state(0.0499)) == pytest.approx(float(lj.paper_segment(1).steady_state(0.0499)))
    assert float(hard.steady_state(0.0501)) == pytest.approx(float(lj.paper_segment(2).steady_state(0.0501)))


def test_segmented_shares_bristle_force_across_edges():
    # A steady bristle of segment 1 carries the same force when read by segment 2: no torque jump.
    fr = lj.Segmented(lj.paper_friction().segments, lj.paper_friction().edges, blend=0.0)
    v = 0.05
    z = float(lj.paper_segment(1).g(v)) / float(lj.paper_segment(1).sigma0)  # segment-1 units
    below = fr.torque(z, v * 0.9999)
    above = fr.torque(z, v * 1.0001)
    # Only Table 1's own small mismatch at the edge remains (< 0.01 N*m, 0.2%) ...
    assert abs(float(above - below)) < 1e-2
    # ... where sharing the deflection z itself would drop the torque by ~1 N*m (0.98 measured).
    assert float(below - lj.paper_segment(2).torque(z, v * 1.0001)) > 0.9


def test_lugre_fixed_point_and_rest():
    m = lj.paper_segment(2)
    assert float(m.derivative(0.0, 0.0)) == 0.0 and float(m.torque(0.0, 0.0)) == 0.0
    # |v|*z, never v/|v|: gradients at rest are finite
    g = jax.grad(lambda v: m.torque(0.01, v))(0.0)
    assert np.isfinite(g)


@pytest.mark.parametrize("cls", [lj.LuGre, lj.Stribeck, lj.CoulombViscous, lj.Joint, lj.DCMotor,
                                 lj.VelocityPID, lj.PositionPID])
def test_every_parameter_has_unit_and_bounds(cls):
    fields = [f for f in dataclasses.fields(cls) if f.name not in ("delta", "neglect_inductance")]
    assert fields
    for f in fields:
        assert "unit" in f.metadata and "bounds" in f.metadata, f"{cls.__name__}.{f.name}"
        lo, hi = f.metadata["bounds"]
        assert lo <= hi


def test_paper_identification_bounds():
    lo, hi = lj.bounds_of(lj.Stribeck(1.0, 2.0, 0.1, 1.0))
    np.testing.assert_array_equal(lo, [0, 0, 0, 0])
    np.testing.assert_array_equal(hi, [10, 10, 1, 10])
    assert lj.units_of(lj.LuGre(1, 2, 0.1, 1, 100, 1))["sigma0"] == "N*m/deg"


def test_motor_time_constants_match_eq6():
    m = lj.DCMotor()
    Te, Tm = m.time_constants(lj.PAPER_J)
    assert float(Te) == pytest.approx(5e-4 / 2.0)
    J_si = lj.PAPER_J * 180 / np.pi
    assert float(Tm) == pytest.approx(J_si * 2.0 / ((160 * 0.05) * (160 * 0.05)))
    assert float(Te) < 0.01 * float(Tm)  # the paper's eq. (8) premise holds for these constants


def test_benchmark_scipy_rhs_is_the_same_system():
    # The scipy baseline uses a hand-written RHS; it must be the simulator's vector field.
    # Both of them: the scalar one and the numpy-style one.
    from lugre_jax._cli._bench import _array_rhs, _numpy_rhs, bench_system, lane_factors

    f = lane_factors(1, seed=9)[0]
    sys1 = jax.tree.map(lambda x: x[0] if eqx.is_array(x) else x, bench_system(f[None]))
    rng = np.random.default_rng(0)
    for rhs in (_numpy_rhs(f), _array_rhs(f)):
        for v in [0.0, 0.003, 0.049, 0.052, 0.3, 1.19, 1.25, -0.05]:
            y = np.zeros(8)
            y[:3] = [rng.normal(), v, rng.normal() * 0.01]
            y[4] = rng.normal() * 0.01
            full = np.asarray(lj.vector_field(0.3, jnp.asarray(y), sys1))
            np.testing.assert_allclose(rhs(0.3, [y[0], y[1], y[2], y[4]]), full[[0, 1, 2, 4]],
                                       rtol=1e-12, atol=1e-12)


# ---------------------------------------------------------------- parameter checks at construction

PASSIVE = dict(Fc=1.0, Fs=1.5, vs=0.1, sigma2=1.0, sigma0=100.0, sigma1=2.0)  # 2*0.5/1 = 1 <= sigma2


@pytest.mark.parametrize("cls, kw, name", [
    (lj.LuGre, dict(PASSIVE, sigma1=-5.0), "sigma1"),
    (lj.LuGre, dict(PASSIVE, Fc=-0.1), "Fc"),
    (lj.Stribeck, dict(Fc=1.0, Fs=2.0, vs=-0.1, sigma2=0.0), "vs"),
    (lj.CoulombViscous, dict(Fc=1.0, sigma2=-1e-9), "sigma2"),
    (lj.Joint, dict(J=0.0), "J"),
    (lj.DCMotor, dict(R=-2.0), "R"),
    (lj.VelocityPID, dict(kp=-1.0), "kp"),
])
def test_wrong_sign_is_one_line_naming_the_parameter(cls, kw, name):
    with pytest.raises(ValueError) as e:
        cls(**kw)
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith(f"{cls.__name__}({name}=") and f"{name} must be" in msg


def test_non_passive_lugre_is_refused_when_passivity_is_required():
    # A stiff set: stiff bristles (1e4), sigma1 50, a small viscous term; passivity needs
    # sigma2 >= sigma1*(Fs - Fc)/Fc = 50*0.3/0.9 = 16.67.
    bad = dict(Fc=0.9, Fs=1.2, vs=0.1, sigma2=0.01, sigma0=1e4, sigma1=50.0)
    strict = dict(require_passive=True)
    with pytest.raises(ValueError, match=r"^LuGre\(sigma2=0\.01\): not passive; sigma2 must be >= .* = 16\.6667"):
        lj.LuGre(**bad, **strict)
    with pytest.warns(lj.friction.NonPassiveWarning, match=r"^LuGre\(sigma2=0\.01\): not passive; sigma2 must be >= .* = 16\.6667") as rec:
        assert float(lj.LuGre(**bad).sigma2) == 0.01  # the default builds it, with a warning
    assert rec[0].filename == __file__  # pointing at the caller's line
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lj.LuGre(**bad, require_passive=False)  # silent on request
    lj.LuGre(**dict(bad, sigma2=50.0 * 0.3 / 0.9), **strict)  # on the boundary: passive
    lj.LuGre(**dict(bad, Fs=0.9), **strict)  # no Stribeck drop: any sigma2 >= 0 is passive
    with pytest.raises(ValueError, match="not passive"):  # Fs < Fc: the rise counts the same way
        lj.LuGre(**dict(bad, Fs=0.6, sigma2=1.0), **strict)
    # the sign is reported before the passivity it implies
    with pytest.raises(ValueError, match=r"sigma1 must be >= 0"):
        lj.LuGre(**dict(PASSIVE, sigma1=-5.0), **strict)
    # the paper's Table 2 segment 1 is not passive
    s1 = lj.paper_segment(1)
    with pytest.raises(ValueError, match="not passive"):
        lj.LuGre(**{n: float(getattr(s1, n)) for n in lj.names_of(s1)}, **strict)


def test_passivity_condition_is_the_dissipation_inequality():
    # F*v - d/dt(sigma0*z^2/2) at the worst reachable state (bristles at their full deflection
    # Fs/sigma0 in the direction of a fast motion, where g = Fc) is negative just below the condition
    # and non-negative at it, from the model's own torque and dz/dt.
    base = dict(Fc=1.0, Fs=1.6, vs=0.2, sigma0=100.0, sigma1=2.0)
    need = 2.0 * 0.6 / 1.0
    v = jnp.asarray(1e3)  # g(v) = Fc to machine precision
    z = 1.6 / 100.0  # z = Fs/sigma0 (w = sigma0*z/g = Fs/Fc)
    for s2, ok in ((need * 0.99, False), (need, True)):
        m = lj.LuGre(**base, sigma2=s2, require_passive=False)
        F, dz = m.torque_and_derivative(z, v)
        supply = float(F * v - m.sigma0 * z * dz)
        assert (supply >= -1e-9 * abs(float(F * v))) == ok, (s2, supply)


def test_checks_skip_traced_values_and_check_batches_elementwise():
    bad = jnp.asarray([1.0, -1.0, 2.0])
    built = jax.vmap(lambda s: lj.LuGre(**dict(PASSIVE, sigma2=s)))(bad)  # traced: not checked
    assert built.sigma2.shape == (3,)
    jax.jit(lambda s: lj.LuGre(**dict(PASSIVE, sigma1=s)).sigma1)(-5.0)
    with pytest.raises(ValueError, match=r"LuGre\(sigma2\[1\]=-1\.0 \(batch of shape \(3,\)\)\)"):
        lj.LuGre(**dict(PASSIVE, sigma2=bad))
    with pytest.raises(ValueError, match=r"sigma2\[2\]=0\.5 .*not passive"):
        lj.LuGre(**dict(PASSIVE, sigma2=np.array([1.0, 2.0, 0.5])), require_passive=True)
    jax.vmap(lambda s: lj.LuGre(**dict(PASSIVE, sigma2=s), require_passive=True))(jnp.asarray([0.5]))
    lj.LuGre(**dict(PASSIVE, sigma1=np.nan))  # a failed estimate stays representable


def test_stribeck_curve_is_the_models_steady_state():
    v = np.array([-2.0, -0.03, 0.0, 0.001, 0.048, 1.5])
    Fc, Fs, vs, s2 = 0.86, 2.357, 0.048, 3.0502
    expect = np.sign(v) * (Fc + (Fs - Fc) * np.exp(-np.abs(v / vs) ** 1.5)) + s2 * v
    np.testing.assert_allclose(lj.friction.stribeck_curve(v, Fc, Fs, vs, s2, 1.5), expect, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(lj.friction.stribeck_g(0.0, Fc, Fs, vs), Fs, rtol=1e-15)
    m = lj.LuGre(Fc, Fs, vs, s2, 100.0, 0.5)
    np.testing.assert_array_equal(m.steady_state(v), lj.friction.stribeck_curve(v, Fc, Fs, vs, s2))


def test_bristle_step_is_exact_against_scipy():
    from scipy.integrate import quad, solve_ivp

    Fc, Fs, vs, s0 = 1.0, 1.6, 0.2, 100.0
    for v, h, z0 in [(0.05, 0.01, 0.0), (-3.0, 0.02, 0.012), (1e-9, 0.001, -0.01), (40.0, 0.05, -0.016)]:
        g = float(lj.friction.stribeck_g(v, Fc, Fs, vs))
        sol = solve_ivp(lambda t, z: v - s0 * abs(v) * z / g, (0.0, h), [z0], method="Radau", rtol=1e-12,
                        atol=1e-15, dense_output=True)
        z1, zm = lj.friction.bristle_step(jnp.asarray(z0), jnp.asarray(v * h), g, s0)
        assert float(z1) == pytest.approx(sol.y[0, -1], rel=1e-8, abs=1e-14)
        assert float(zm) == pytest.approx(quad(lambda t: sol.sol(t)[0], 0.0, h, epsabs=1e-16)[0] / h, rel=1e-7, abs=1e-14)
        e, c = lj.friction.bristle_coefficients(jnp.asarray(v * h), g, s0)
        assert float(e * z0 + c) == pytest.approx(float(z1), rel=1e-15, abs=1e-18)
