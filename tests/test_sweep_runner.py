"""The sweep runner: outputs against one-at-a-time simulations, stiff re-solve of failed lanes,
a SPEC change refused, a SIGKILLed-and-resumed run identical to an uninterrupted one, and two
jax.distributed processes identical to one."""

import copy
import json
import os
import signal
import socket
import subprocess
import sys
import time

import diffrax
import numpy as np
import pytest

import lugre_jax as lj
from lugre_jax import metrics as M
from lugre_jax.scenario import scenario_from_dict
from lugre_jax.sweep import STATUS_FAILED, STATUS_FAST, STATUS_STIFF, run_sweep, spec_from_dict

SCENARIO = {
    "friction": {"model": "lugre", "Fc": 2.4, "Fs": 3.0, "vs": 0.05, "sigma0": 300, "sigma1": 5, "sigma2": 0.5},
    "joint": {"J": 0.128},
    "controller": {"type": "velocity_pid", "kp": 8.0, "ki": 60.0},
    "reference": {"type": "velocity_step", "velocity_deg_s": 0.01},
    "duration_s": 3.0, "sample_hz": 100,
}
SPEC = {"scenario": SCENARIO,
        "problem": {"names": ["friction.sigma0", "controller.ki"], "bounds": [[100, 1000], [20, 100]]},
        "sampler": "sobol", "n": 16, "seed": 1, "outputs": ["dead_zone", "creep_amplitude"],
        "stepping": {"solver": "bosh3", "dt": 0.01}, "chunk_size": 8, "num_resamples": 20}


def _cli(spec_path, out, *extra):
    return [sys.executable, "-m", "lugre_jax.cli", "sweep", str(spec_path), "--out", str(out), "--no-progress",
            "--no-figures", *extra]


def _env(tmp_path):
    return dict(os.environ, LUGRE_JAX_CACHE_DIR=str(tmp_path.parent / "jax_cache"))


@pytest.fixture(scope="module")
def reference_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "out"
    res = run_sweep(spec_from_dict(SPEC), out, progress=False, figures=False)
    return out, res


def _outputs(out):
    with np.load(out / "outputs.npz") as z:
        return z["X"], z["Y"], z["status"]


def test_outputs_match_single_simulations(reference_run):
    out, res = reference_run
    assert res.complete and res.n_points == 16 * 4 and res.status_counts["fast_ok"] == 64
    X, Y, status = _outputs(out)
    for i in (0, 37):  # two points, simulated one at a time from an edited scenario
        d = copy.deepcopy(SCENARIO)
        d["friction"]["sigma0"], d["controller"]["ki"] = X[i]
        system, _ = scenario_from_dict(d)
        sol = lj.simulate(system, 3.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.01))
        t, th, ref = np.asarray(sol.ts), np.asarray(sol.theta), np.asarray(sol.theta_ref)
        # Batched and single lanes round differently: 1e-9 relative.
        np.testing.assert_allclose(Y[i, 0], M.dead_zone_lag(t, th, 0.01), rtol=1e-9)
        np.testing.assert_allclose(Y[i, 1], M.creep_amplitude(t, th, ref, t_from=1.5), rtol=1e-7, atol=1e-12)
    idx = json.loads((out / "indices.json").read_text())["outputs"]
    assert set(idx) == {"dead_zone", "creep_amplitude"}
    assert all(np.isfinite(idx["dead_zone"][k]).all() for k in ("S1", "S1_conf", "ST", "ST_conf"))


def test_changed_spec_refused(reference_run):
    out, _ = reference_run
    before = {p: p.stat().st_mtime_ns for p in out.rglob("*")}
    with pytest.raises(ValueError, match="holds a sweep of a different SPEC"):
        run_sweep(spec_from_dict(dict(SPEC, seed=2)), out, progress=False)
    assert before == {p: p.stat().st_mtime_ns for p in out.rglob("*")}


@pytest.mark.slow  # compiling the batched Kvaerno5 solve takes ~20 s
def test_stiff_lanes_resolved_and_double_failures_dropped(tmp_path):
    # sigma0 up to the library's 1e4 N*m/deg: a 20 ms Bosh3 step is unstable for the stiff lanes.
    spec = dict(SPEC, problem={"names": ["friction.sigma0", "controller.ki"], "bounds": [[100, 1e4], [20, 100]]},
                stepping={"solver": "bosh3", "dt": 0.02}, chunk_size=64, fallback={"max_steps": 400})
    res = run_sweep(spec_from_dict(spec), tmp_path / "out", progress=False, figures=False)
    X, Y, status = _outputs(tmp_path / "out")
    n_stiff, n_failed = (status == STATUS_STIFF).sum(), (status == STATUS_FAILED).sum()
    assert (status == STATUS_FAST).sum() > 0 and n_stiff > 0 and n_failed > 0, np.bincount(status)
    assert np.all(np.isnan(Y[status == STATUS_FAILED])) and np.all(np.isfinite(Y[status != STATUS_FAILED]))
    # A re-solved lane's outputs are the adaptive solver's (independent single run, same tolerances).
    i = int(np.flatnonzero(status == STATUS_STIFF)[0])
    d = copy.deepcopy(SCENARIO)
    d["friction"]["sigma0"], d["controller"]["ki"] = X[i]
    system, _ = scenario_from_dict(d)
    sol = lj.simulate(system, 3.0, 100.0, stepping=lj.Adaptive(diffrax.Kvaerno5(), rtol=1e-6, atol=1e-9, max_steps=400))
    np.testing.assert_allclose(Y[i, 0], M.dead_zone_lag(np.asarray(sol.ts), np.asarray(sol.theta), 0.01), rtol=1e-9)
    # Whole groups (D + 2 = 4 rows) with a failed run are dropped, and said so; no NaN.
    groups_bad = (status.reshape(-1, 4) == STATUS_FAILED).any(axis=1).sum()
    for name, idx in res.indices.items():
        assert idx.n_dropped == groups_bad and idx.n_groups == 16 - groups_bad
        assert all(np.all(np.isfinite(idx[k])) for k in idx.keys())


def test_sigkill_then_resume_identical(tmp_path, reference_run):
    ref_out, _ = reference_run
    spec_path = tmp_path / "spec.json"
    spec_path.write_text(json.dumps(SPEC))
    out = tmp_path / "out"
    proc = subprocess.Popen(_cli(spec_path, out), env=_env(tmp_path), stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    chunks = out / "chunks"
    deadline = time.monotonic() + 120
    while proc.poll() is None and time.monotonic() < deadline:
        if chunks.exists() and any(p.name.startswith("chunk_") for p in chunks.iterdir()):
            break
        time.sleep(0.002)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = sorted(p.name for p in chunks.iterdir() if p.name.startswith("chunk_"))
    assert 0 < len(done) < 8, f"kill landed after {len(done)} of 8 chunks"
    assert not (out / "outputs.npz").exists()
    # A temporary left by a write the kill interrupted is cleaned up.
    (chunks / ".chunk_000007.npz.abc123.npz").write_bytes(b"partial")
    r = subprocess.run(_cli(spec_path, out), env=_env(tmp_path), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout.strip().splitlines()[-1])["chunks_computed"] == 8 - len(done)
    assert not list(chunks.glob(".chunk_*"))
    for a, b in zip(_outputs(out), _outputs(ref_out)):
        np.testing.assert_array_equal(a, b)
    assert (json.loads((out / "indices.json").read_text())["outputs"]
            == json.loads((ref_out / "indices.json").read_text())["outputs"])


def test_two_processes_equal_one(tmp_path, reference_run):
    ref_out, _ = reference_run
    spec_path = tmp_path / "spec.json"
    spec_path.write_text(json.dumps(SPEC))
    out = tmp_path / "out"
    with socket.socket() as s:
        s.bind(("localhost", 0))
        port = s.getsockname()[1]
    procs = [subprocess.Popen(_cli(spec_path, out, "--coordinator", f"localhost:{port}", "--num-processes", "2",
                                   "--process-id", str(k)), env=_env(tmp_path), stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for k in (0, 1)]
    outs = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1][-2000:] for o in outs]
    computed = [json.loads(o[0].strip().splitlines()[-1])["chunks_computed"] for o in outs]
    assert computed == [4, 4]  # chunks i = rank (mod 2)
    for a, b in zip(_outputs(out), _outputs(ref_out)):
        np.testing.assert_array_equal(a, b)


def test_grid_and_lhs_sweeps(tmp_path):
    # Same scenario, outputs, stepping and chunk size as SPEC: the compiled chunk is reused.
    grid = dict(SPEC, sampler="grid", n=3)
    res = run_sweep(spec_from_dict(grid), tmp_path / "grid", progress=False)
    X, Y, status = _outputs(tmp_path / "grid")
    assert res.complete and res.indices is None and X.shape == (9, 2) and Y.shape == (9, 2)
    np.testing.assert_array_equal(np.unique(X[:, 0]), [100, 550, 1000])
    assert (tmp_path / "grid" / "heatmap_dead_zone.png").stat().st_size > 0
    assert not (tmp_path / "grid" / "indices.json").exists()
    lhs = dict(SPEC, sampler="lhs", n=5)
    run_sweep(spec_from_dict(lhs), tmp_path / "lhs", progress=False, figures=False)
    X, Y, status = _outputs(tmp_path / "lhs")
    assert X.shape == (5, 2) and np.all(status == STATUS_FAST)
    summary = json.loads((tmp_path / "lhs" / "summary.json").read_text())
    np.testing.assert_allclose(summary["outputs"]["dead_zone"]["mean"], Y[:, 0].mean(), rtol=1e-12)
