"""Speed benchmark of the batched simulator (``lugre-jax bench``), all ratios measured in one run.

An application of the library, beside the CLI that runs it: it uses the public API, except
:func:`rhs_floor`, which times the time loop's own right-hand side (``_simulation._system.rates``
on the solver's tuple-of-arrays state), an internal layout that is deliberately not API.

Scenario: the paper's segmented LuGre joint (Tables 1-2, J = 0.128) under velocity PI (kp = 8,
ki = 60) commanded at 0.02 deg/s for 20 s, a stick-slip run. Each lane gets its own parameter set
(every friction parameter scaled by a lane-specific factor in [0.9, 1.1]).

Baselines: a plain Python loop of ``scipy.integrate.solve_ivp`` (LSODA) on a hand-written scalar
right-hand side (4 states, no JAX in the loop: the fastest plain scipy loop we could write); the
same loop on the right-hand side written numpy-style (arrays over the three segments, ufuncs: how
such code is usually written, the cost the core issue quotes); and the same loop
calling the jitted JAX vector field (what handing a JAX model to scipy costs). All three are
reported, each labelled. Accuracy is measured against a tight reference (LSODA, rtol 1e-11); for scipy at
rtol 1e-3 (its default) and 1e-4 we pick our cheapest fixed-step configuration whose position error
is no larger ("matched accuracy") and time that.

Jacobian: a one-segment joint under the same loop, loss = mean squared position tracking error,
its gradient w.r.t. the six LuGre parameters against the loss alone, both per lane through
``map_lanes`` (see :func:`jacobian_cost`).
"""

from __future__ import annotations

import functools
import json
import math
import os
import platform
import resource
import subprocess
import sys
import time

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from scipy.integrate import solve_ivp

from .. import FixedStep, Lanes, SaveAt, System, broadcast_system, map_lanes, vector_field
from .. import simulate as _simulate_api
from .._simulation._system import rates as _rates, split as _split  # rhs_floor only: see the docstring
from ..control import VelocityPID, VelocitySteps
from ..friction import LuGre, from_vector, to_vector
from ..scenario import FIXED_SOLVERS
from ..plant import PAPER_J, Joint, paper_friction, paper_segment


def _evals_per_step(solver: str) -> int:
    return FixedStep(FIXED_SOLVERS[solver]()).evals_per_step


@functools.lru_cache(maxsize=None)
def _options(solver, dt, reduce, sample_mean, chunk_size, shard):
    # Built once per configuration, as a user holds them: the timed loops measure the solve.
    return dict(stepping=FixedStep(FIXED_SOLVERS[solver](), dt=dt), saveat=SaveAt(reduce=reduce, mean=sample_mean),
                lanes=Lanes(chunk_size=chunk_size, shard=shard))


def simulate(system, duration, hz, *, solver="tsit5", dt=2.5e-3, batched=False, shard=None, chunk_size=None,
             reduce=None, sample_mean=None):
    """The benchmark's configurations (solver name, dt) as the simulator's objects."""
    return _simulate_api(system, duration, hz, batched=batched,
                         **_options(solver, dt, reduce, sample_mean, chunk_size, shard))


V_CMD, KP, KI, DURATION, HZ = 0.02, 8.0, 60.0, 20.0, 100.0
_SCALED = ("Fc", "Fs", "sigma0", "sigma1", "sigma2")


def bench_system(factors: np.ndarray | None = None) -> System:
    """The benchmark system; ``factors`` (n, 5) scale Fc, Fs, sigma0, sigma1, sigma2 per lane."""
    fr = paper_friction()
    base = System(friction=fr, joint=Joint(J=PAPER_J), controller=VelocityPID(kp=KP, ki=KI),
                  reference=VelocitySteps([V_CMD]))
    if factors is None:
        return base
    n = factors.shape[0]
    batch = broadcast_system(base, n)
    segs = []
    for seg in batch.friction.segments:
        for j, name in enumerate(_SCALED):
            seg = eqx.tree_at(lambda m: getattr(m, name), seg, getattr(seg, name) * factors[:, j])
        segs.append(seg)
    return eqx.tree_at(lambda s: s.friction.segments, batch, tuple(segs))


def lane_factors(n: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(0.9, 1.1, size=(n, len(_SCALED)))


def _numpy_rhs(factors):
    """Plain-Python right-hand side of the same closed loop, states (theta, omega, z, xi)."""
    segs = []
    for k in (1, 2, 3):
        m = paper_segment(k)
        p = {n: float(getattr(m, n)) for n in ("Fc", "Fs", "vs", "sigma0", "sigma1", "sigma2")}
        for j, name in enumerate(_SCALED):
            p[name] *= factors[j]
        segs.append(p)
    edges, blend = (0.05, 1.2), paper_friction().blend
    c = [s["sigma0"] / segs[0]["sigma0"] for s in segs]
    exp = math.exp

    def seg_out(p, ck, z, v):
        x = abs(v) / p["vs"]
        g = p["Fc"] + (p["Fs"] - p["Fc"]) * exp(-x * x)
        zk = z / ck
        dzk = v - p["sigma0"] * abs(v) * zk / g
        return ck * dzk, p["sigma0"] * zk + p["sigma1"] * dzk + p["sigma2"] * v

    def rhs(t, y):
        theta, omega, z, xi = y
        a = abs(omega)
        dz, F = seg_out(segs[0], c[0], z, omega)
        for k in (1, 2):
            e = edges[k - 1]
            xx = min(max((a - e * (1 - blend)) / (2 * blend * e), 0.0), 1.0)
            if xx > 0:
                w = xx * xx * (3 - 2 * xx)
                dz2, F2 = seg_out(segs[k], c[k], z, omega)
                dz, F = dz + w * (dz2 - dz), F + w * (F2 - F)
        err = V_CMD - omega
        tau = KP * err + KI * xi
        return [omega, (tau - F) / PAPER_J, dz, err]

    return rhs


def _array_rhs(factors):
    """The same right-hand side written the way numpy code usually is: parameters as arrays over
    the three segments, ufuncs on them, the state as an array. Each ufunc call on a 3-element array
    pays interpreter and dispatch overhead far above its arithmetic, which is what makes this the
    slower (and more common) plain-scipy baseline."""
    keys = ("Fc", "Fs", "vs", "sigma0", "sigma1", "sigma2")
    P = np.array([[float(getattr(paper_segment(k), n)) for n in keys] for k in (1, 2, 3)])
    for j, name in enumerate(_SCALED):
        P[:, keys.index(name)] *= factors[j]
    Fc, Fs, vs, s0, s1, s2 = P.T
    c = s0 / s0[0]
    edges, blend = np.array([0.05, 1.2]), paper_friction().blend

    def rhs(t, y):
        theta, omega, z, xi = y
        a = np.abs(omega)
        g = Fc + (Fs - Fc) * np.exp(-((a / vs) ** 2))
        zk = z / c
        dzk = omega - s0 * a * zk / g
        dz_k = c * dzk
        F_k = s0 * zk + s1 * dzk + s2 * omega
        xx = np.clip((a - edges * (1 - blend)) / (2 * blend * edges), 0.0, 1.0)
        w = xx * xx * (3 - 2 * xx)
        dz, F = dz_k[0], F_k[0]
        for k in (1, 2):
            dz = dz + w[k - 1] * (dz_k[k] - dz)
            F = F + w[k - 1] * (F_k[k] - F)
        err = V_CMD - omega
        tau = KP * err + KI * xi
        return np.array([omega, (tau - F) / PAPER_J, dz, err])

    return rhs


def scipy_solve(factors, rtol=1e-3, atol=1e-6, rhs=None):
    ts = np.arange(int(DURATION * HZ) + 1) / HZ
    r = solve_ivp((rhs or _numpy_rhs)(factors), (0.0, DURATION), [0.0, 0.0, 0.0, 0.0], method="LSODA",
                  t_eval=ts, rtol=rtol, atol=atol)
    return r.y.T


def _timeit(fn, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t)
    return best


def _err(a, b):
    return float(np.max(np.abs(a[:, 0] - b[:, 0]))), float(np.max(np.abs(a[:, 1] - b[:, 1])))


def accuracy_table(progress):
    """Error of each candidate fixed-step config and of scipy at several rtols, vs a tight reference."""
    f = lane_factors(1, seed=1)[0]
    ref = scipy_solve(f, rtol=1e-11, atol=1e-13)
    one = bench_system(f[None])
    one = jax.tree.map(lambda x: x[0] if eqx.is_array(x) else x, one)
    rows = []
    for solver, dt in [("tsit5", 2.5e-3), ("tsit5", 1e-2), ("bosh3", 5e-3), ("bosh3", 1e-2),
                       ("heun", 1e-2), ("ralston", 1e-2), ("bosh3", 2e-2), ("heun", 2e-2)]:
        sol = simulate(one, DURATION, HZ, solver=solver, dt=dt)
        e = _err(np.asarray(sol.ys[:, :2]), ref)
        rows.append(dict(solver=solver, dt_s=dt, theta_err_deg=e[0], omega_err_deg_s=e[1],
                         rhs_evals_per_sim=int(round(DURATION / dt)) * _evals_per_step(solver),
                         interpolated_samples=dt > 1.0 / HZ))
        progress.update()
    sc = []
    for rtol in (1e-3, 1e-4, 1e-5, 1e-6):
        y = scipy_solve(f, rtol=rtol, atol=rtol * 1e-3)
        e = _err(y, ref)
        sc.append(dict(rtol=rtol, atol=rtol * 1e-3, theta_err_deg=e[0], omega_err_deg_s=e[1]))
        progress.update()
    return rows, sc


def scipy_loop_time(n, rtol, atol, rhs=None, repeat=3):
    """Per-solve time of a loop of ``n`` scipy solves, best of ``repeat`` loops (as for our side:
    single loops vary from run to run, docs/performance.md)."""
    fs = lane_factors(n, seed=2)
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        for f in fs:
            scipy_solve(f, rtol=rtol, atol=atol, rhs=rhs)
        best = min(best, (time.perf_counter() - t) / n)
    return best


def jax_throughput(batch, shard, repeat=5, **cfg):
    system = bench_system(lane_factors(batch, seed=3))
    reduce = _tracking_errors

    def run():
        return simulate(system, DURATION, HZ, batched=True, shard=shard, reduce=reduce, **cfg)

    t0 = time.perf_counter()
    out = run()
    jax.block_until_ready(out)
    compile_s = time.perf_counter() - t0
    el = _timeit(run, repeat)
    ok = int(np.sum(np.asarray(out[1]) == 0))
    return dict(batch=batch, devices=len(jax.devices()) if shard else 1, seconds=el,
                sims_per_s=batch / el, first_call_s=compile_s, lanes_ok=ok)


def _tracking_errors(sol):
    """Per lane: mean squared position and velocity tracking errors, and the result code.

    This is what a swarm's fitness evaluation reads, and it reads every sample of theta and omega,
    so each lane computes and stores its whole sampled trajectory, as the scipy loop (t_eval) does.
    A reduction that read only the final state would let jit skip storing the trajectory and
    flatter our side."""
    err = (jnp.mean((sol.theta - sol.theta_ref) ** 2), jnp.mean((sol.omega - sol.v_ref) ** 2))
    return err, sol.result


def _tracking_mse(q):
    """Squared position tracking error of one sample [deg^2] (the Jacobian benchmark's loss term)."""
    return (q.theta - q.theta_ref) ** 2


def jacobian_cost(batch, *, loss_kind="sample_mean", devices=(1,), **cfg):
    """Full Jacobian of a trajectory loss w.r.t. the six LuGre parameters vs one forward solve.

    The loss of one lane is the mean squared position tracking error over all samples, computed
    either inside the time loop (``loss_kind="sample_mean"``, ``simulate(..., sample_mean=...)``)
    or from the stored trajectory (``"trajectory"``). Forward solves, forward-mode Jacobians and
    reverse-mode gradients all go through the public batching path, ``map_lanes(fn, P)`` with
    ``fn`` the loss, ``jax.jacfwd(loss)`` or ``jax.grad(loss)`` of one lane. Each is timed in chunks
    of 64 lanes (map_lanes' default: a reverse pass's stored states stay in cache) and of 200
    (simulate's default: fastest for forward solves) on one device and,
    for each entry of ``devices`` > 1, split across that many host devices; each is credited with
    its fastest configuration (all timings in the JSON). Forward mode is also timed with the six
    tangents outermost (one jvp per parameter over a whole chunk), one device."""
    base = System(friction=paper_segment(1), joint=Joint(J=PAPER_J),
                  controller=VelocityPID(kp=KP, ki=KI), reference=VelocitySteps([V_CMD]))
    p0 = to_vector(paper_segment(1))

    def loss(p):
        s = eqx.tree_at(lambda s: s.friction, base, from_vector(LuGre, p))
        if loss_kind == "sample_mean":
            return simulate(s, DURATION, HZ, sample_mean=_tracking_mse, **cfg).value
        sol = simulate(s, DURATION, HZ, **cfg)
        return jnp.mean((sol.theta - sol.theta_ref) ** 2)

    ps = jnp.asarray(p0) * jnp.asarray(np.random.default_rng(4).uniform(0.9, 1.1, (batch, 6)))
    g = jax.vmap(loss)

    def tangent_outer(c):
        # Tangent axis outermost: one jvp per parameter over a whole chunk, so each tangent is a
        # contiguous chunk-wide vector (vmap(jacfwd) puts the 6 tangents innermost, per lane).
        nc = -(-batch // c)
        E = jnp.broadcast_to(jnp.eye(6)[:, None, :], (6, c, 6))

        def run(P):
            P = jnp.concatenate([P, jnp.repeat(P[:1], nc * c - batch, 0)]).reshape(nc, c, 6)
            out = jax.lax.map(lambda Pc: jax.vmap(lambda e: jax.jvp(g, (Pc,), (e,))[1])(E), P)
            return jnp.moveaxis(out, 1, 0).reshape(6, nc * c)[:, :batch]
        return jax.jit(run)

    def lanes(f, c, ndev):
        return jax.jit(lambda P: map_lanes(f, P, chunk_size=c, shard=ndev > 1))

    timings = {}
    for ndev in sorted({1, *devices}):
        if ndev > len(jax.devices()):
            continue
        for c in sorted({min(batch, 64), min(batch, 200)}):
            fns = dict(forward=lanes(loss, c, ndev), reverse=lanes(jax.grad(loss), c, ndev))
            if ndev == 1:
                fns.update(jacfwd=lanes(jax.jacfwd(loss), c, ndev), tangent_outer=tangent_outer(c))
            for f in fns.values():
                jax.block_until_ready(f(ps))
            if ndev == 1:
                np.testing.assert_allclose(np.asarray(fns["tangent_outer"](ps)).T, np.asarray(fns["jacfwd"](ps)),
                                           rtol=1e-8, atol=1e-14)
                np.testing.assert_allclose(np.asarray(fns["reverse"](ps)), np.asarray(fns["jacfwd"](ps)),
                                           rtol=1e-7, atol=1e-14)
            timings[f"{ndev}dev_chunk{c}"] = {k: _timeit(lambda f=f: f(ps), repeat=7) for k, f in fns.items()}

    def best(mode, ndev=None):
        return min(t[mode] for k, t in timings.items() if mode in t and (ndev is None or k.startswith(f"{ndev}dev")))

    t_f, t_jf, t_jt, t_jr = best("forward", 1), best("jacfwd", 1), best("tangent_outer", 1), best("reverse", 1)
    # The loss is a scalar, so its full Jacobian is one gradient: reverse mode computes it in one
    # backward pass, forward mode in six tangents. Both are timed; the cheaper is the figure.
    modes = dict(forward=min(t_jf, t_jt), reverse=t_jr)
    mode = min(modes, key=modes.get)
    out = dict(batch=batch, loss=loss_kind, forward_s=t_f, jacfwd_s=t_jf, jvp_tangent_outer_s=t_jt,
               grad_reverse_s=t_jr, jacfwd_over_forward=t_jf / t_f,
               jvp_tangent_outer_over_forward=t_jt / t_f,
               best_forward_mode_over_forward=min(t_jf, t_jt) / t_f,
               reverse_over_forward=t_jr / t_f,
               jacobian_over_forward=modes[mode] / t_f, cheaper_mode=mode,
               seconds_by_configuration=timings)
    if any(k.startswith("2dev") for k in timings):
        # Wall time on this machine, each computation in its fastest configuration (device count
        # and chunk), which may differ between the forward solve and the Jacobian.
        t_f_any, t_j_any = best("forward"), min(best("reverse"), modes["forward"])
        out.update(forward_best_devices_s=t_f_any, jacobian_best_devices_s=t_j_any,
                   jacobian_over_forward_best_devices=t_j_any / t_f_any,
                   forward_two_devices_s=best("forward", 2), grad_reverse_two_devices_s=best("reverse", 2))
    return out


def rhs_floor(n=200, reps=20_000):
    """Time of one fused right-hand-side evaluation per lane, on a cache-resident batch of ``n``
    lanes evaluated ``reps`` times in a loop (one device): the arithmetic floor of a step stage.

    The state is the solver's tuple of 8 per-lane arrays (``_rates``), the layout the time loop
    uses; the stacked ``vector_field`` costs more per evaluation and so overstated the floor."""
    system = bench_system(lane_factors(n, seed=5))
    ys = _split(jnp.asarray(np.random.default_rng(6).normal(size=(n, 8)) * 1e-3))
    dyn, static = eqx.partition(system, eqx.is_array)
    field = jax.vmap(lambda d, y: _rates(0.5, y, eqx.combine(d, static)))

    @jax.jit
    def f(dyn, ys):
        # y <- y + 1e-12*f(y): each evaluation depends on the last, so none can be hoisted
        return jax.lax.fori_loop(0, reps, lambda i, y: jax.tree.map(
            lambda a, b: a + 1e-12 * b, y, field(dyn, y)), ys)

    one = jax.jit(field)
    jax.block_until_ready(f(dyn, ys))
    el = _timeit(lambda: f(dyn, ys), repeat=3)
    cost = one.lower(dyn, ys).compile().cost_analysis()
    cost = cost[0] if isinstance(cost, list) else cost
    return dict(lanes=n, evaluations=reps, ns_per_rhs_eval=el / (n * reps) * 1e9,
                flops_per_rhs_eval=float(cost.get("flops", float("nan"))) / n,
                transcendentals_per_rhs_eval=float(cost.get("transcendentals", float("nan"))) / n)


_MEM_SCRIPT = r"""
import os, sys, time, resource, json
os.environ["XLA_FLAGS"] = "--xla_force_host_platform_device_count=%d"
import lugre_jax; lugre_jax.configure()
import jax, numpy as np
from lugre_jax._cli._bench import bench_system, lane_factors, _tracking_errors, simulate, DURATION, HZ
n, chunk = %d, %r
FAST = dict(solver=%r, dt=%r)
s = bench_system(lane_factors(n, seed=7))
t = time.perf_counter()
out = simulate(s, DURATION, HZ, batched=True, chunk_size=chunk, reduce=_tracking_errors, **FAST)
jax.block_until_ready(out)
el = time.perf_counter() - t
print(json.dumps(dict(lanes=n, chunk_size=chunk, seconds_incl_compile=el,
      lanes_ok=int((np.asarray(out[1]) == 0).sum()),
      peak_rss_gb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2)))
"""


def memory_run(n, chunk, ndev, solver, dt):
    r = subprocess.run([sys.executable, "-c", _MEM_SCRIPT % (ndev, n, chunk, solver, dt)], capture_output=True,
                       text=True, timeout=3600)
    if r.returncode != 0:
        raise RuntimeError(f"memory run failed: {r.stderr[-2000:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def scipy_jaxrhs_loop_time(n, rtol, atol):
    """Per-solve time of scipy LSODA when the RHS is the jitted JAX vector field (8 states).

    This is what a JAX code base gets by handing its model to scipy: every RHS call pays JAX's
    dispatch, which dominates. Reported beside the pure-Python baseline, never instead.
    """
    fs = lane_factors(n, seed=2)
    ts = np.arange(int(DURATION * HZ) + 1) / HZ
    systems = [jax.tree.map(lambda x: x[0] if eqx.is_array(x) else x, bench_system(f[None])) for f in fs]
    fn = jax.jit(vector_field)
    jax.block_until_ready(fn(0.0, systems[0].y0, systems[0]))
    t = time.perf_counter()
    for s in systems:
        solve_ivp(lambda t_, y, s=s: np.asarray(fn(t_, y, s)), (0.0, DURATION), np.zeros(8),
                  method="LSODA", t_eval=ts, rtol=rtol, atol=atol)
    return (time.perf_counter() - t) / n


def _cheapest_within(rows, scipy_row, k=2):
    """Our ``k`` cheapest fixed-step configurations (by RHS evaluations) whose position *and*
    velocity errors are no larger than scipy's. Both are timed: fewer evaluations is not always
    faster (docs/performance.md)."""
    ok = [r for r in rows if r["theta_err_deg"] <= scipy_row["theta_err_deg"]
          and r["omega_err_deg_s"] <= scipy_row["omega_err_deg_s"]]
    if not ok:
        return [min(rows, key=lambda r: r["theta_err_deg"])]
    return sorted(ok, key=lambda r: r["rhs_evals_per_sim"])[:k]


def run_benchmark(quick: bool = False, progress=None) -> dict:
    """Every figure of the simulator benchmark, measured in this one run (see module docstring)."""
    from tqdm.auto import tqdm

    batches = [1, 100, 1000] if quick else [1, 100, 1000, 10_000]
    n_scipy = 10 if quick else 40
    two = len(jax.devices()) >= 2
    jac_batches = [1, 100] if quick else [1, 100, 1000]
    # accuracy table, scipy baselines, Jacobians + floor, baseline check + memory; throughput below
    total = 12 + 6 + len(jac_batches) + 1 + 2
    bar = progress or tqdm(total=total, desc="bench", unit="step")
    out: dict = dict(
        scenario=dict(description="paper segmented LuGre, velocity PI kp=8 ki=60, 0.02 deg/s step, "
                      "20 s sampled at 100 Hz; lane parameters scaled by U[0.9, 1.1]",
                      duration_s=DURATION, sample_hz=HZ, v_cmd_deg_s=V_CMD),
        machine=dict(cpu_count=os.cpu_count(), devices=len(jax.devices()), jax=jax.__version__,
                     python=platform.python_version(), processor=platform.processor(),
                     device=f"{jax.devices()[0].platform}: {getattr(jax.devices()[0], 'device_kind', '')}"),
        quick=quick,
    )
    rows, sc = accuracy_table(bar)
    out["accuracy_fixed_step"] = rows
    out["accuracy_scipy_lsoda"] = sc
    # the array-style RHS is the same ODE: its tight solution must agree with the scalar one
    f1 = lane_factors(1, seed=1)[0]
    d = np.max(np.abs(scipy_solve(f1, 1e-10, 1e-12, rhs=_array_rhs) - scipy_solve(f1, 1e-10, 1e-12)))
    if not d < 1e-6:
        raise RuntimeError(f"array-style and scalar baselines disagree by {d:g}")
    out["baselines_agree_max_abs_diff"] = float(d)
    bar.update()
    # Matched accuracy: for scipy at rtol 1e-3 (its default) and 1e-4, our two cheapest fixed-step
    # configurations whose position and velocity errors are no larger than scipy's; both are timed
    # and each speed-up uses the faster one at that batch.
    # The plain scipy loops: (result key, solves per loop, right-hand side). Timed here and again
    # after our throughput runs (see below).
    plain = (("scipy_python_rhs_s_per_sim", n_scipy, None),
             ("scipy_numpy_rhs_s_per_sim", max(3, n_scipy // 4), _array_rhs))
    pairs = {}
    for s_row in sc[:2]:
        tag = f"rtol{s_row['rtol']:.0e}"
        pairs[tag] = dict(scipy=s_row, candidates=_cheapest_within(rows, s_row))
        for key, n_loop, rhs in plain:
            pairs[tag][key] = scipy_loop_time(n_loop, s_row["rtol"], s_row["atol"], rhs=rhs)
            bar.update()
        pairs[tag]["scipy_jax_rhs_s_per_sim"] = scipy_jaxrhs_loop_time(max(3, n_scipy // 8), s_row["rtol"], s_row["atol"])
        bar.update()
    out["matched_pairs"] = pairs
    configs = {(c["solver"], c["dt_s"]) for p in pairs.values() for c in p["candidates"]}
    bar.total += len(configs) * len(batches) * (2 if two else 1)
    tp = []
    for solver, dt in sorted(configs):
        for b in batches:
            for shard in ((False, True) if two else (False,)):
                r = jax_throughput(b, shard, solver=solver, dt=dt)
                r.update(solver=solver, dt_s=dt)
                tp.append(r)
                bar.update()
    out["throughput"] = tp
    # Re-time the plain scipy loops now and keep the faster of the two timings. The scipy loop's
    # speed drifts between runs far more than our batched throughput (docs/paper_notes.md): a loop
    # timed minutes before our side can inflate the ratio, and the faster
    # timing is the conservative choice for our claims. Both timings are kept.
    for p in pairs.values():
        s_row = p["scipy"]
        for key, n_loop, rhs in plain:
            again = scipy_loop_time(n_loop, s_row["rtol"], s_row["atol"], rhs=rhs)
            p[key + "_timings"] = [p[key], again]
            p[key] = min(p[key], again)
    for solver, dt in sorted(configs):
        for b in batches:
            rs = {r["devices"]: r["sims_per_s"] for r in tp if (r["solver"], r["dt_s"]) == (solver, dt)
                  and r["batch"] == b}
            if len(rs) == 2:
                out[f"two_devices_over_one_{solver}_{dt * 1e3:g}ms_b{b}"] = rs[max(rs)] / rs[1]
    for tag, p in pairs.items():
        cfgs = {(c["solver"], c["dt_s"]) for c in p["candidates"]}
        for b in batches:
            best = max((r for r in tp if (r["solver"], r["dt_s"]) in cfgs and r["batch"] == b),
                       key=lambda r: r["sims_per_s"])
            out[f"best_config_{tag}_b{b}"] = dict(solver=best["solver"], dt_s=best["dt_s"],
                                                  devices=best["devices"], sims_per_s=best["sims_per_s"])
            out[f"speedup_vs_scipy_{tag}_b{b}"] = best["sims_per_s"] * p["scipy_python_rhs_s_per_sim"]
            out[f"speedup_vs_scipy_numpy_rhs_{tag}_b{b}"] = best["sims_per_s"] * p["scipy_numpy_rhs_s_per_sim"]
            out[f"speedup_vs_scipy_jax_rhs_{tag}_b{b}"] = best["sims_per_s"] * p["scipy_jax_rhs_s_per_sim"]
    bmax = max(batches)
    top = out[f"best_config_rtol1e-03_b{bmax}"]
    fast = dict(solver=top["solver"], dt=top["dt_s"])
    out["fast_config"] = fast
    # The Jacobian's primary loss is reduced inside the time loop (sample_mean); the same loss
    # through the stored trajectory is reported beside it. At the largest batch both are also
    # timed on two host devices (see jacobian_cost).
    for b in jac_batches:
        ndev = (1, 2) if two and b == max(jac_batches) else (1,)
        out[f"jacobian_b{b}"] = jacobian_cost(b, loss_kind="sample_mean", devices=ndev, **fast)
        out[f"jacobian_b{b}_trajectory_loss"] = jacobian_cost(b, loss_kind="trajectory", **fast)
        bar.update()
    fl = rhs_floor()
    evals = next(r["rhs_evals_per_sim"] for r in rows if (r["solver"], r["dt_s"]) == (fast["solver"], fast["dt"]))
    fl["rhs_evals_per_sim"] = evals
    fl["floor_sims_per_s_one_device"] = 1e9 / (fl["ns_per_rhs_eval"] * evals)
    fl["achieved_over_floor_one_device"] = next(
        r["sims_per_s"] for r in tp if r["batch"] == bmax and r["devices"] == 1
        and (r["solver"], r["dt_s"]) == (fast["solver"], fast["dt"])) / fl["floor_sims_per_s_one_device"]
    out["floor"] = fl
    bar.update()
    n_mem = 10_000 if quick else 100_000
    out["memory_one_call"] = memory_run(n_mem, None, len(jax.devices()), **fast)  # default chunks
    bar.update()
    out["peak_rss_gb_this_process"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2
    bar.close()
    return out
