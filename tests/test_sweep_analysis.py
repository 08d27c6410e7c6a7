"""Sampling and Sobol' analysis (no simulator) against SALib and the Ishigami function's analytic
indices."""

import numpy as np
import pytest
from SALib.analyze import sobol as salib_analyze
from SALib.sample import sobol as salib_sample
from SALib.test_functions import Ishigami

from lugre_jax.sweep import grid_sample, latin_hypercube, saltelli_sample, sobol_analyze

PROBLEM = {"num_vars": 3, "names": ["x1", "x2", "x3"], "bounds": [[-np.pi, np.pi]] * 3}


def ishigami_analytic(a=7.0, b=0.1):
    """Analytic S1 and ST of Ishigami's function (Saltelli et al. 2008, 'Global sensitivity analysis', §4)."""
    V1 = 0.5 * (1 + b * np.pi**4 / 5) ** 2
    V2 = a**2 / 8
    V13 = b**2 * np.pi**8 / 18 - b**2 * np.pi**8 / 50
    V = V1 + V2 + V13
    return np.array([V1, V2, 0.0]) / V, np.array([V1 + V13, V2, V13]) / V


@pytest.mark.parametrize("second", [False, True])
def test_samples_and_indices_equal_salib(second):
    X = saltelli_sample(PROBLEM, 256, seed=11, calc_second_order=second)
    np.testing.assert_array_equal(X, salib_sample.sample(dict(PROBLEM), 256, seed=11, calc_second_order=second))
    Y = Ishigami.evaluate(X)
    ours = sobol_analyze(PROBLEM, Y, seed=5, calc_second_order=second, num_resamples=50)
    ref = salib_analyze.analyze(dict(PROBLEM), Y, seed=5, calc_second_order=second, num_resamples=50)
    assert sorted(ours.keys()) == sorted(k for k in ref.keys())
    for k in ours.keys():
        # Same estimators, same bootstrap draw: equal to rounding (1e-12 absolute on indices O(1)).
        np.testing.assert_allclose(ours[k], ref[k], rtol=0, atol=1e-12, equal_nan=True, err_msg=k)


def test_ishigami_analytic():
    S1, ST = ishigami_analytic()
    X = saltelli_sample(PROBLEM, 2**13, seed=2, calc_second_order=False)
    res = sobol_analyze(PROBLEM, Ishigami.evaluate(X), seed=3, calc_second_order=False)
    # Monte Carlo error at N = 8192 base points is ~0.01; the intervals are ~0.02-0.04 wide.
    np.testing.assert_allclose(res.S1, S1, atol=0.03)
    np.testing.assert_allclose(res.ST, ST, atol=0.03)
    assert np.all(np.abs(res.ST - ST) <= res.ST_conf + 0.01)
    assert res.n_dropped == 0 and res.n_groups == 2**13
    js = res.to_json()
    assert set(js) >= {"S1", "S1_conf", "ST", "ST_conf", "n_dropped"} and "S2" not in js


def test_failed_runs_drop_whole_groups():
    X = saltelli_sample(PROBLEM, 128, seed=1, calc_second_order=False)
    Y = Ishigami.evaluate(X)
    step = 5  # D + 2 rows per base point
    Y[3 * step + 1] = np.nan  # an AB row of group 3
    ok = np.ones(Y.size, bool)
    ok[10 * step + 4] = False  # the B row of group 10
    res = sobol_analyze(PROBLEM, Y, seed=9, calc_second_order=False, ok=ok)
    assert res.n_dropped == 2 and res.n_groups == 126
    assert all(np.all(np.isfinite(res[k])) for k in res.keys())
    kept = np.delete(Y.reshape(-1, step), [3, 10], axis=0).ravel()
    ref = salib_analyze.analyze(dict(PROBLEM), kept, seed=9, calc_second_order=False)
    for k in ("S1", "S1_conf", "ST", "ST_conf"):
        np.testing.assert_allclose(res[k], ref[k], atol=1e-12, err_msg=k)


def test_lhs_and_grid():
    X = latin_hypercube(PROBLEM, 50, seed=4)
    u = (X + np.pi) / (2 * np.pi)
    for j in range(3):  # one point in each of the 50 strata of every coordinate
        np.testing.assert_array_equal(np.sort(np.floor(u[:, j] * 50)), np.arange(50))
    G = grid_sample({"names": ["a", "b"], "bounds": [[0, 1], [10, 20]]}, [3, 2])
    np.testing.assert_array_equal(G, [[0, 10], [0, 20], [0.5, 10], [0.5, 20], [1, 10], [1, 20]])


@pytest.mark.parametrize("problem,N,match", [
    (PROBLEM, 100, "power of two"),
    ({"names": ["a"], "bounds": [[1, 0]]}, 8, r"bounds\[0\] \(a\): expected lo < hi"),
    ({"names": ["a", "b"], "bounds": [[0, 1]]}, 8, "2 pairs"),
])
def test_bad_problem(problem, N, match):
    with pytest.raises(ValueError, match=match):
        saltelli_sample(problem, N, seed=0)


def test_constant_output_gives_zero_indices():
    X = saltelli_sample(PROBLEM, 16, seed=0, calc_second_order=False)
    res = sobol_analyze(PROBLEM, np.ones(len(X)), seed=1, calc_second_order=False)
    assert np.all(res.S1 == 0) and np.all(res.ST == 0) and np.all(res.S1_conf == 0)
