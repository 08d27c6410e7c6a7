"""The package's one bounded least-squares fit and covariance (lugre_jax._fit) against scipy."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
import pytest
from scipy.optimize import curve_fit

from lugre_jax._fit import (BoxTransform, LogBoxTransform, LogTransform, at_bounds, covariance, fit, least_squares,
                            result_name)

T = np.linspace(0.0, 4.0, 40)
TRUE = np.array([2.0, 1.3, 0.4])  # amplitude, rate, offset
Y = TRUE[0] * np.exp(-TRUE[1] * T) + TRUE[2] + 0.02 * np.random.default_rng(3).standard_normal(T.size)


def model_np(t, a, k, c):
    return a * np.exp(-k * t) + c


def residual(p):
    return p[0] * jnp.exp(-p[1] * jnp.asarray(T)) + p[2] - jnp.asarray(Y)


def test_fit_matches_scipy_curve_fit_estimate_and_standard_errors():
    popt, pcov = curve_fit(model_np, T, Y, p0=[1.0, 1.0, 0.0], xtol=1e-14, ftol=1e-14, gtol=1e-14)
    f = fit(residual, [1.0, 1.0, 0.0], [0.0, 0.0, -1.0], [10.0, 10.0, 1.0])
    assert f.successful and result_name(f.result) == "successful"
    np.testing.assert_allclose(f.params, popt, rtol=1e-8)
    # Gauss-Newton covariance with the residual variance |r|^2/(n - p), as curve_fit(absolute_sigma=False)
    np.testing.assert_allclose(f.standard_errors, np.sqrt(np.diag(pcov)), rtol=1e-6)
    assert f.covariance.dof == T.size - 3
    assert f.loss == pytest.approx(0.5 * np.sum((model_np(T, *popt) - Y) ** 2), rel=1e-10)


def test_a_parameter_on_its_bound_has_no_standard_error():
    f = fit(residual, [1.0, 1.0, 0.0], [0.0, 0.0, -1.0], [10.0, 1.0, 1.0])  # rate capped below its optimum
    assert f.params[1] == pytest.approx(1.0, abs=1e-6)
    assert np.isinf(f.standard_errors[1]) and np.all(np.isfinite(f.standard_errors[[0, 2]]))
    np.testing.assert_array_equal(at_bounds([0.0, 0.5, 1.0], [0.0] * 3, [1.0] * 3), [True, False, True])
    np.testing.assert_array_equal(at_bounds([5.0, 3.0, 1e-9], [-np.inf, 0.0, 0.0], [np.inf, np.inf, np.inf]),
                                  [False, False, True])  # a half-line's width is max(1, |x|)


def test_log_transform_and_an_uninformed_direction():
    f = fit(residual, [1.0, 1.0, 0.1], transform=LogTransform(), absolute_sigma=True)
    np.testing.assert_allclose(f.params, fit(residual, [1.0, 1.0, 0.0], [0.0, 0.0, -1.0], [10.0, 10.0, 1.0]).params,
                               rtol=1e-7)
    # two identical columns: their difference is not informed -> both infinite, the third finite
    J = np.column_stack([np.exp(-T), np.exp(-T), np.ones_like(T)])
    c = covariance(J, np.zeros(T.size), absolute_sigma=True)
    assert np.all(np.isinf(c.standard_errors[:2])) and np.isfinite(c.standard_errors[2])
    assert covariance(J[:3], np.zeros(3)).dof == 0 and np.all(np.isnan(covariance(J[:3], np.zeros(3)).standard_errors))


def test_least_squares_is_the_refine_solver_and_reports_failure_as_a_code():
    x, sol = least_squares(residual, jnp.asarray([1.0, 1.0, 0.0]), BoxTransform(jnp.zeros(3) - 1, jnp.full(3, 10.0)),
                           max_steps=2)
    assert sol.result != optx.RESULTS.successful and result_name(sol.result).startswith("nonlinear_max_steps")
    assert np.all(np.isfinite(np.asarray(x)))


def test_loss_stop_and_jacobian_scaling_reach_scipys_optimum_on_a_badly_scaled_fit():
    """The options the EMPS fits use: the same exponential with its rate in 1/ms and its amplitude
    in mN (scales 1e-3 and 1e3 apart). With ``jac_scale`` and the loss-decrease stop, LM ends at
    scipy's optimum within the stop's tolerance; the loss test ends it as a result
    ``successful``, and a looser ``ftol`` stops no later than a tighter one."""
    def scaled(p):
        return residual(jnp.array([p[0] * 1e-3, p[1] * 1e3, p[2]]))

    popt, _ = curve_fit(model_np, T, Y, p0=[1.0, 1.0, 0.0], xtol=1e-14, ftol=1e-14, gtol=1e-14)
    want = popt / np.array([1e-3, 1e3, 1.0])
    lo, hi = [0.0, 0.0, -1.0], [1e4, 1e-2, 1.0]
    x0 = [1e3, 1e-3, 0.0]
    tight = fit(scaled, x0, lo, hi, rtol=1e-10, atol=1e-12, ftol=1e-12, jac_scale=True)
    loose = fit(scaled, x0, lo, hi, rtol=1e-10, atol=1e-12, ftol=1e-5, jac_scale=True)
    assert tight.successful and loose.successful
    np.testing.assert_allclose(tight.params, want, rtol=1e-6)
    # a stop when the loss falls by less than ftol of it: the loss is within ~ftol of the optimum's
    assert loose.loss <= tight.loss * (1 + 1e-3)
    assert loose.n_steps <= tight.n_steps
    # standard errors do not depend on the parameters' units
    f = fit(residual, [1.0, 1.0, 0.0], [0.0, 0.0, -1.0], [10.0, 10.0, 1.0])
    np.testing.assert_allclose(tight.standard_errors * np.array([1e-3, 1e3, 1.0]), f.standard_errors, rtol=1e-5)


def test_log_box_transform_round_trips_and_pulls_a_start_inside():
    lo, hi, log = np.array([0.0, 1e-4, -2.0]), np.array([5.0, 10.0, 3.0]), np.array([False, True, False])
    t = LogBoxTransform(lo, hi, log, edge=1e-6)
    u = jnp.asarray(np.linspace(-8.0, 8.0, 9)[:, None] * np.ones(3))
    x = np.asarray(jax.vmap(t.to_box)(u))
    sig = 1.0 / (1.0 + np.exp(-np.asarray(u)))
    np.testing.assert_allclose(x[:, [0, 2]], lo[[0, 2]] + (hi - lo)[[0, 2]] * sig[:, [0, 2]], rtol=1e-14)
    np.testing.assert_allclose(x[:, 1], np.exp(np.log(1e-4) + np.log(1e5) * sig[:, 1]), rtol=1e-12)
    np.testing.assert_allclose(jax.vmap(t.from_box)(jnp.asarray(x)), u, atol=1e-9)
    # a start on a bound moves edge of the (log) box inside, and counts as saturated there
    inside = np.asarray(t.to_box(t.from_box(jnp.asarray(lo))))
    np.testing.assert_allclose((inside - lo)[[0, 2]], 1e-6 * (hi - lo)[[0, 2]], rtol=1e-6)
    np.testing.assert_allclose(np.log(inside[1] / lo[1]), 1e-6 * np.log(1e5), rtol=1e-6)
    np.testing.assert_array_equal(t.at_bounds(inside, 1e-4), [True] * 3)
    np.testing.assert_array_equal(t.at_bounds(x[4], 1e-4), [False] * 3)


def _stribeck_joint_problem():
    """A short Stribeck joint recording with its truth, for diagnose's fit."""
    from types import SimpleNamespace

    from lugre_jax.diagnose import _model as M
    from lugre_jax.friction import Stribeck

    tt = np.linspace(0.0, 4.0, 400)
    v = 2.0 * np.sin(2 * np.pi * 0.5 * tt) + 0.3
    a = 2.0 * np.pi * np.cos(2 * np.pi * 0.5 * tt)
    th = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(tt))])
    true = M.JointModel(jnp.asarray(0.05), Stribeck(Fc=0.4, Fs=0.7, vs=0.3, sigma2=0.2), jnp.asarray(0.05))
    kin = M.Kinematics(*(jnp.asarray(q) for q in (tt, th, v, a, np.diff(tt), np.diff(th))), jnp.asarray(0.0))
    tau = M.predict(true, kin) + 0.01 * np.random.default_rng(0).standard_normal(tt.size)
    rec = SimpleNamespace(time=tt, position=th, velocity=v, acceleration=a, torque=tau)
    start = M.JointModel(jnp.asarray(0.03), Stribeck(Fc=0.3, Fs=0.5, vs=0.1, sigma2=0.1), jnp.asarray(0.0))
    return M, rec, kin, tau, start


def test_diagnose_fit_is_least_squares_on_the_joint_model():
    """diagnose's fit and standard errors agree with a fit of the same joint model written out by hand
    (same transform and tolerances), with scipy's bounded optimum, and a parameter the data cannot
    separate from another (a second constant offset) gets no standard error."""
    from scipy.optimize import least_squares as scipy_ls

    from lugre_jax.diagnose._physics import Asymmetry

    M, rec, kin, tau, start = _stribeck_joint_problem()
    space = M.FitSpace(M.baseline_specs(start, M.data_scales(rec), fit_offset=True))
    assert space.names == ["J", "Fc", "Fs", "vs", "sigma2", "offset"]
    w = np.ones(tau.size)
    fitted, info = M.fit(M.clip_into(space, start), space, kin, tau, w)
    assert info["result"] == "successful" and info["steps"] > 0
    got = np.array(list(space.as_dict(fitted).values()))

    v, a = np.asarray(kin.v), np.asarray(kin.a)

    def by_hand(p):
        J, Fc, Fs, vs, s2, off = (p[i] for i in range(6))
        pred = J * a + jnp.sign(v) * (Fc + (Fs - Fc) * jnp.exp(-((v / vs) ** 2))) + s2 * v + off
        return (pred - tau) / np.std(tau)

    lo, hi = np.array([s.lo for s in space.specs]), np.array([s.hi for s in space.specs])
    transform = LogBoxTransform(lo, hi, [s.log for s in space.specs], edge=1e-6)
    ref = fit(by_hand, space.values(M.clip_into(space, start)), lo, hi, transform=transform, rtol=1e-7, atol=1e-9)
    assert ref.successful
    np.testing.assert_allclose(got, ref.params, rtol=1e-6)
    sp = scipy_ls(lambda p: np.asarray(by_hand(jnp.asarray(p))), ref.params, bounds=(lo, hi), xtol=1e-15,
                  ftol=1e-15, gtol=1e-15)
    np.testing.assert_allclose(got, sp.x, rtol=1e-5)
    se = M.standard_errors(fitted, space, kin, tau, w)
    np.testing.assert_allclose([se[n][1] for n in space.names], ref.standard_errors, rtol=1e-5)
    # the long-run variance factor scales the variance
    se4 = M.standard_errors(fitted, space, kin, tau, w, kappa=4.0)
    np.testing.assert_allclose([se4[n][1] for n in space.names], 2 * ref.standard_errors, rtol=1e-5)

    # nuisance columns fitted alongside: one the data cannot tell from the inertia's torque leaves
    # the inertia uninformed; one unrelated to the data (white, seeded) leaves value and error as
    # they were, within its chance correlation (|r| ~ 1/sqrt(n) moves them by well under 5 %)
    se_a = M.standard_errors(fitted, space, kin, tau, w, nuisance=np.asarray(kin.a))
    assert se_a["J"][1] > 1e3 * se["J"][1]
    white = np.random.default_rng(3).standard_normal(tau.size)
    se_w = M.standard_errors(fitted, space, kin, tau, w, nuisance=white)
    for n in space.names:
        np.testing.assert_allclose(se_w[n], se[n], rtol=0.05)

    # Asymmetry's offset is a constant torque, as the baseline's offset is: only their sum is informed
    joint = eqx.tree_at(lambda m: m.candidates, fitted, (Asymmetry(0.0, 0.0),))
    scales = M.data_scales(rec)
    both = M.FitSpace(space.specs + M.candidate_specs(joint, 0, scales))
    se = M.standard_errors(M.clip_into(both, joint), both, kin, tau, w)
    assert np.isinf(se["offset"][1]) and np.isinf(se["asymmetry.offset"][1])
    assert np.isfinite(se["asymmetry.dsigma2"][1]) and np.isfinite(se["Fc"][1])
