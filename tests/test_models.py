"""Friction and plant models: closed forms, the paper's parameter sets, bounds and units."""

import dataclasses

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
