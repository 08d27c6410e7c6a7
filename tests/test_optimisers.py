"""Optimisers of lugre_jax.identify on textbook functions with known minima (no plant, no simulator)."""

import sys
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from lugre_jax.identify import GA, GAPSO, PSO, Refine, minimise, optimise, paper_fitness, result_name
from lugre_jax.identify._fitness import evaluate  # internals under test
from lugre_jax.identify._ga import decode, encode
from lugre_jax.identify._pso import hash_uniform

SHIFT3 = jnp.array([1.0, -2.0, 0.5])
LO3, HI3 = -5.0 * jnp.ones(3), 5.0 * jnp.ones(3)


def shifted_sphere(x):
    return jnp.sum(jnp.square(x - SHIFT3[: x.shape[0]]))


def rosenbrock(x):
    return jnp.sum(100.0 * jnp.square(x[1:] - x[:-1] ** 2) + jnp.square(1.0 - x[:-1]))


def rosenbrock_residual(x):
    return jnp.concatenate([10.0 * (x[1:] - x[:-1] ** 2), 1.0 - x[:-1]])


KEY = jax.random.key(20200284)

# method, settings, problem, dim, tolerance on |x - x*|_inf (every seed)
CASES = [
    ("pso", {}, "sphere", 3, 1e-4),
    ("pso", {}, "rosenbrock", 2, 2e-2),
    ("gapso", {"ga_steps": 1}, "sphere", 3, 1e-4),
    pytest.param("gapso", {"pso": {"max_steps": 30}}, "rosenbrock", 2, 5e-2, marks=pytest.mark.slow),
    # The paper's GA (20 x 20) is too small to pin a 10-bit optimum; 60 x 80 finds it to ~1 LSB.
    ("ga", {"pop_size": 60, "max_steps": 80}, "sphere", 2, 0.05),
    ("ga_real", {"pop_size": 50, "max_steps": 150}, "sphere", 3, 1e-2),
    ("cmaes", {"max_steps": 300}, "rosenbrock", 4, 1e-4),
    pytest.param("de", {"pop_size": 30, "max_steps": 300}, "sphere", 3, 1e-4, marks=pytest.mark.slow),
    ("de", {"pop_size": 20, "max_steps": 150, "base": "best"}, "sphere", 2, 1e-4),
    ("lm", {"max_steps": 200}, "rosenbrock", 4, 1e-6),
    ("bfgs", {"max_steps": 300}, "rosenbrock", 3, 1e-5),
]


def _id(c):
    v = c.values if hasattr(c, "values") else c
    return f"{v[0]}-{v[2]}{v[3]}"


@pytest.mark.parametrize("method,settings,problem,dim,tol", CASES, ids=[_id(c) for c in CASES])
def test_known_minimum(method, settings, problem, dim, tol):
    lo, hi = -2.0 * jnp.ones(dim), 2.5 * jnp.ones(dim)
    if problem == "sphere":
        loss, xstar, res = shifted_sphere, np.asarray(SHIFT3[:dim]), None
        lo, hi = LO3[:dim], HI3[:dim]
    else:
        loss, xstar, res = rosenbrock, np.ones(dim), rosenbrock_residual
    n_seeds = 4
    x0 = {"x0": jnp.full(dim, -1.2).at[-1].set(1.0)} if method in ("lm", "bfgs") else {}
    r = optimise(method, loss, lo, hi, key=KEY, n_seeds=n_seeds, residual_fn=res, **settings, **x0)
    assert r.x.shape == (n_seeds, dim) and r.loss.shape == (n_seeds,)
    assert np.all(np.abs(r.x - xstar) <= tol), (r.x, r.loss)
    # history is best-so-far: monotone, ends at the reported loss, evaluations increase
    assert np.all(np.diff(r.history, axis=1) <= 0)
    np.testing.assert_allclose(r.history[:, -1], r.loss_global)
    assert np.all(np.diff(r.evals_history, axis=1) >= 0) and np.all(r.n_evals > 0)
    if method == "gapso":
        n_it, g = settings.get("pso", {}).get("max_steps", 100), settings.get("ga_steps") or 20
        assert r.history.shape == (n_seeds, n_it + 1)
        assert np.all(r.n_evals == 100 + n_it * (20 + g * 19 + 100))  # the paper's settings: 500 per iteration


def test_evaluation_counts_are_the_documented_ones():
    r = optimise("pso", shifted_sphere, LO3, HI3, key=KEY, n_particles=10, max_steps=5)
    assert r.n_evals[0] == 10 * 6
    r = optimise("ga", shifted_sphere, LO3, HI3, key=KEY, pop_size=20, max_steps=20)
    assert r.n_evals[0] == 20 + 20 * 19
    # GA-PSO: per iteration the GA encodes 20 particles (20 evaluations), runs its generations
    # (19 each, one elite kept) and the swarm moves (100); checked in test_known_minimum[gapso-sphere3]


SLOW = pytest.mark.slow


@pytest.mark.parametrize("method", ["pso", pytest.param("gapso", marks=SLOW), "ga", pytest.param("ga_real", marks=SLOW),
                                    "cmaes", pytest.param("de", marks=SLOW), "lm"])
def test_bounds_respected_when_minimum_is_outside(method):
    # Minimum at (3, -3), box [-1, 1]^2: the constrained minimum is the corner (1, -1).
    target = jnp.array([3.0, -3.0])
    res = lambda x: x - target  # noqa: E731
    loss = lambda x: 0.5 * jnp.sum(res(x) ** 2)  # noqa: E731
    lo, hi = -jnp.ones(2), jnp.ones(2)
    settings = {"pso": {"max_steps": 20}, "gapso": {"ga_steps": 1, "pso": {"max_steps": 20}},
                "ga": {"pop_size": 60, "max_steps": 80}, "ga_real": {}, "cmaes": {"max_steps": 60},
                "de": {"max_steps": 60}, "lm": {}}[method]
    r = optimise(method, loss, lo, hi, key=KEY, n_seeds=3, residual_fn=res, **settings)
    assert np.all(r.x >= -1.0) and np.all(r.x <= 1.0)
    tol = 0.05 if method in ("ga", "ga_real") else 1e-3
    np.testing.assert_allclose(r.x, np.tile([1.0, -1.0], (3, 1)), atol=tol)


def test_hash_uniform_moments_and_pso_with_it():

    u = np.asarray(hash_uniform(KEY, (400, 500))).ravel()
    assert u.min() >= 0.0 and u.max() < 1.0
    # 200k draws: mean and variance within ~5 standard errors of U(0, 1)'s; lag-1 correlation ~0
    assert abs(u.mean() - 0.5) < 5 * np.sqrt(1 / 12 / u.size)
    assert abs(u.var() - 1 / 12) < 5 * 0.0745 / np.sqrt(u.size)
    assert abs(np.corrcoef(u[:-1], u[1:])[0, 1]) < 5 / np.sqrt(u.size)
    v = np.asarray(hash_uniform(jax.random.split(KEY)[0], (400, 500))).ravel()
    assert abs(np.corrcoef(u, v)[0, 1]) < 5 / np.sqrt(u.size)
    r = optimise("pso", shifted_sphere, LO3, HI3, key=KEY, n_seeds=2, rng="hash")
    assert np.all(np.abs(r.x - np.asarray(SHIFT3)) < 1e-4)


def test_pso_swarm_stays_in_box():
    lo, hi = jnp.array([0.0, -1.0]), jnp.array([1.0, 3.0])
    out = minimise(PSO(n_particles=30, max_steps=25), lambda x: -jnp.sum(x**2), (lo, hi), KEY)
    x = out.state.x
    assert bool(jnp.all((x >= lo) & (x <= hi)))
    assert bool(jnp.all((out.state.pbest >= lo) & (out.state.pbest <= hi)))


def test_seeds_are_independent_and_reproducible():
    r = optimise("pso", rosenbrock, -2 * jnp.ones(2), 2 * jnp.ones(2), key=KEY, n_seeds=4, max_steps=5)
    # different seeds explore differently after 5 iterations
    assert len(np.unique(np.round(r.history[:, 1], 12))) == 4
    # seed i of a batch equals a single run with the i-th split key
    keys = jax.random.split(KEY, 4)
    single = minimise(PSO(max_steps=5), rosenbrock, (-2 * jnp.ones(2), 2 * jnp.ones(2)), keys[2])
    np.testing.assert_allclose(np.asarray(single.history_loss), r.history[2], rtol=1e-12)


def test_one_loop_for_objects_and_names_and_the_record(tmp_path):
    import json

    from lugre_jax.io import write_json

    a = optimise("pso", shifted_sphere, LO3, HI3, key=KEY, n_seeds=2, n_particles=10, max_steps=4)
    b = optimise(PSO(n_particles=10, max_steps=4), shifted_sphere, LO3, HI3, key=KEY, n_seeds=2)
    np.testing.assert_array_equal(a.history, b.history)
    assert a.steps == 4 and a.history.shape == (2, 5) and a.n_evals[0] == 10 * 5
    g = optimise("gapso", shifted_sphere, LO3, HI3, key=KEY, max_steps=2, ga_steps=1, pso={"n_particles": 20})
    assert g.steps == 2 and g.n_evals[0] == 20 + 2 * (20 + 19 + 20)  # max_steps is the swarm's
    write_json(tmp_path / "r.json", a.to_json())
    d = json.loads((tmp_path / "r.json").read_text())
    assert d["steps"] == 4 and d["settings"]["max_steps"] == 4 and d["method"] == "pso"
    np.testing.assert_array_equal(d["loss"], a.loss)
    np.testing.assert_array_equal(d["x"], a.x)


def test_evosax_hyperparameters_are_leaves():
    from lugre_jax.identify import DE

    des = eqx.filter_vmap(lambda F: DE(pop_size=8, max_steps=5, F=F))(jnp.array([0.3, 0.9]))
    out = eqx.filter_vmap(lambda d: minimise(d, shifted_sphere, (LO3, HI3), KEY))(des)
    assert out.best_loss.shape == (2,) and float(out.best_loss[0]) != float(out.best_loss[1])
    # lane i of the sweep is the optimiser built with that F alone
    one = minimise(DE(pop_size=8, max_steps=5, F=0.9), shifted_sphere, (LO3, HI3), KEY)
    np.testing.assert_allclose(np.asarray(one.history_loss), np.asarray(out.history_loss[1]), rtol=1e-12)


def test_hyperparameters_vmap():
    psos = eqx.filter_vmap(lambda w: PSO(n_particles=20, max_steps=10, w=w))(jnp.array([0.4, 0.62, 0.9]))
    out = eqx.filter_vmap(lambda p: minimise(p, shifted_sphere, (LO3, HI3), KEY))(psos)
    assert out.best_loss.shape == (3,)
    assert len(np.unique(np.asarray(out.best_loss))) == 3


@pytest.mark.parametrize("method", ["pso", pytest.param("gapso", marks=SLOW), "ga", pytest.param("ga_real", marks=SLOW),
                                    "cmaes", pytest.param("de", marks=SLOW)])
def test_nonfinite_losses_count_as_inf(method):
    # NaN on half the box, inf on a strip: the optimiser must still find the valid minimum at x=(0.5, 0.5)
    def loss(x):
        base = jnp.sum((x - 0.5) ** 2)
        return jnp.where(x[0] < 0.0, jnp.nan, jnp.where(x[1] < -0.5, jnp.inf, base))

    settings = {"pso": {"max_steps": 30}, "gapso": {"ga_steps": 1, "pso": {"max_steps": 20}}, "ga": {},
                "ga_real": {}, "cmaes": {"max_steps": 60}, "de": {"max_steps": 60}}[method]
    r = optimise(method, loss, -jnp.ones(2), jnp.ones(2), key=KEY, n_seeds=2, **settings)
    assert np.all(np.isfinite(r.loss)) and np.all(r.x[:, 0] >= 0.0)
    assert np.all(r.loss < 0.05)


def test_all_failed_evaluations_give_inf_not_nan():
    r = optimise("pso", lambda x: jnp.nan * jnp.sum(x), LO3, HI3, key=KEY, n_particles=10, max_steps=3)
    assert np.all(np.isposinf(r.loss)) and not np.any(np.isnan(r.history))
    r = optimise("ga", lambda x: jnp.nan * jnp.sum(x), LO3, HI3, key=KEY, max_steps=3)
    assert np.all(np.isposinf(r.loss))


def test_evaluate_and_paper_fitness():
    losses = evaluate(lambda x: x[0], jnp.array([[1.0], [jnp.nan], [3.0], [-jnp.inf]]))
    np.testing.assert_array_equal(np.asarray(losses), [1.0, np.inf, 3.0, np.inf])
    f = paper_fitness(losses)
    np.testing.assert_array_equal(np.asarray(f), [2.0, 0.0, 0.0, 0.0])  # C_m = 3 (largest finite J)


def test_binary_encode_decode_round_trip_within_one_lsb():
    lo, hi = jnp.array([0.0, 0.0, 0.0, 0.0]), jnp.array([10.0, 10.0, 1.0, 10.0])
    x = lo + (hi - lo) * jax.random.uniform(KEY, (1000, 4))
    for bits in (4, 10, 16):
        g = jax.vmap(lambda xi: encode(xi, lo, hi, bits))(x)
        assert g.shape == (1000, 4 * bits) and g.dtype == jnp.bool_
        xd = jax.vmap(lambda gi: decode(gi, lo, hi, bits))(g)
        lsb = (hi - lo) / (2**bits - 1)
        assert bool(jnp.all(jnp.abs(xd - x) <= 0.5 * lsb * (1 + 1e-9)))
        # exact on the grid
        g2 = jax.vmap(lambda xi: encode(xi, lo, hi, bits))(xd)
        assert bool(jnp.all(g2 == g))
    # MSB first: the top level is all ones, the middle level 1000000000
    assert bool(jnp.all(encode(hi, lo, hi, 10)))
    np.testing.assert_array_equal(np.asarray(encode(jnp.array([512.0]), jnp.array([0.0]), jnp.array([1023.0]), 10)),
                                  [1, 0, 0, 0, 0, 0, 0, 0, 0, 0])


def _exp_fit_problem():
    t = jnp.linspace(0.0, 3.0, 40)
    truth = jnp.array([2.0, 1.3, 0.4])  # a, b, c of a*exp(-b*t) + c
    y = truth[0] * jnp.exp(-truth[1] * t) + truth[2]
    return (lambda p: p[0] * jnp.exp(-p[1] * t) + p[2] - y), truth


@pytest.mark.parametrize("method", ["lm", "bfgs"])
def test_refinement_recovers_least_squares_solution(method):
    res, truth = _exp_fit_problem()
    lo, hi = jnp.array([0.0, 0.0, -1.0]), jnp.array([5.0, 5.0, 1.0])
    out = jax.jit(lambda x0: Refine(method, max_steps=300)(x0, lo, hi, residual_fn=res))(truth + jnp.array([0.4, -0.3, 0.2]))
    assert result_name(out.result) == "successful"
    np.testing.assert_allclose(np.asarray(out.x), np.asarray(truth), atol=1e-6)
    assert float(out.loss) < 1e-12 < float(out.loss0)


def test_refine_after_global_optimiser():
    res, truth = _exp_fit_problem()
    lo, hi = jnp.array([0.0, 0.0, -1.0]), jnp.array([5.0, 5.0, 1.0])
    r = optimise("pso", None, lo, hi, key=KEY, n_seeds=3, residual_fn=res, refine=True, max_steps=20)
    assert r.refine_result is not None and np.all(r.refine_result == 0)
    np.testing.assert_allclose(r.x, np.tile(np.asarray(truth), (3, 1)), atol=1e-6)
    assert np.all(r.loss <= r.loss_global) and np.all(r.n_evals > r.evals_history[:, -1])


def test_refinement_reports_failure_instead_of_nan():
    res, truth = _exp_fit_problem()
    lo, hi = jnp.array([0.0, 0.0, -1.0]), jnp.array([5.0, 5.0, 1.0])
    out = Refine("lm", max_steps=2)(truth + 1.0, lo, hi, residual_fn=res)
    assert result_name(out.result) != "successful"
    assert bool(jnp.isfinite(out.loss)) and float(out.loss) <= float(out.loss0)


def test_gapso_is_a_composition():
    g = GAPSO()
    assert isinstance(g.ga, GA) and isinstance(g.pso, PSO)
    assert not issubclass(GAPSO, (GA, PSO))
    # the paper's settings are the defaults
    assert (g.ga.pop_size, g.ga.bits, g.ga.max_steps) == (20, 10, 20)
    assert float(g.ga.pc) == 0.9 and float(g.ga.pm) == 0.005
    assert (g.pso.n_particles, g.pso.max_steps, g.max_steps) == (100, 100, 100)
    assert (float(g.pso.w), float(g.pso.c1), float(g.pso.c2)) == (0.62, 2.0, 2.0)
    with pytest.raises(ValueError, match="GA population smaller"):
        GAPSO(ga=GA(pop_size=50), pso=PSO(n_particles=20))


def test_bad_input_raises_helpful_errors():
    with pytest.raises(ValueError, match="unknown method"):
        optimise("simplex", shifted_sphere, LO3, HI3, key=KEY)
    with pytest.raises(ValueError, match="residual_fn"):
        optimise("lm", shifted_sphere, LO3, HI3, key=KEY)
    with pytest.raises(ValueError, match="lower bound must be"):
        optimise("pso", shifted_sphere, HI3, LO3, key=KEY)
    with pytest.raises(ValueError, match="accepts settings"):
        optimise("pso", shifted_sphere, LO3, HI3, key=KEY, n_particle=3)
    with pytest.raises(ValueError, match=r"renamed: n_iterations -> max_steps"):
        optimise("pso", shifted_sphere, LO3, HI3, key=KEY, n_iterations=3)
    with pytest.raises(ValueError, match=r"renamed: generations -> max_steps"):
        optimise("gapso", shifted_sphere, LO3, HI3, key=KEY, ga={"generations": 3})
    with pytest.raises(ValueError, match="give max_steps once"):
        optimise("gapso", shifted_sphere, LO3, HI3, key=KEY, max_steps=3, pso={"max_steps": 4})
    with pytest.raises(ValueError, match="on the optimiser object"):
        optimise(PSO(), shifted_sphere, LO3, HI3, key=KEY, max_steps=3)
    with pytest.raises(ValueError, match="finite"):
        optimise("pso", shifted_sphere, LO3, jnp.full(3, jnp.inf), key=KEY)


def test_static_stribeck_loss_matches_package_model():
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments" / "optimiser_benchmark"))
    from static_problem import Problem, stribeck

    from lugre_jax import Stribeck

    p = Problem("whole")
    m = Stribeck(*p.truth)
    np.testing.assert_allclose(np.asarray(stribeck(jnp.asarray(p.truth), p.v)), np.asarray(m.steady_state(p.v)), rtol=1e-13)
    P = np.stack([p.truth, p.truth * 1.1])
    np.testing.assert_allclose(p.loss_np(P), [float(p.loss_fn(jnp.asarray(q))) for q in P], rtol=1e-12)
