"""The package's one bounded least-squares fit and covariance (lugre_jax._fit) against scipy."""

import jax.numpy as jnp
import numpy as np
import optimistix as optx
import pytest
from scipy.optimize import curve_fit

from lugre_jax._fit import BoxTransform, LogTransform, at_bounds, covariance, fit, least_squares, result_name

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
