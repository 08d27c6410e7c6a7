"""SPEC checking (one clear line, nothing written), dotted paths, and the per-lane metrics against
lugre_jax.metrics (the NumPy definitions)."""

import copy
import json
import subprocess
import sys

import diffrax
import equinox as eqx
import jax
import numpy as np
import pytest

import lugre_jax as lj
from lugre_jax import metrics as M
from lugre_jax.scenario import scenario_from_dict
from lugre_jax.sweep import (BandFraction, CreepAmplitude, DeadZone, StickSlip, TrackingError, spec_from_dict)
from lugre_jax.sweep._paths import batch_system

SCENARIO = {
    "friction": {"model": "lugre", "Fc": 2.4, "Fs": 3.0, "vs": 0.05, "sigma0": 300, "sigma1": 5, "sigma2": 0.5},
    "joint": {"J": 0.128},
    "controller": {"type": "velocity_pid", "kp": 8.0, "ki": 60.0},
    "reference": {"type": "velocity_steps", "levels": [0.005, 0.01], "dwell_s": 100.0},
    "duration_s": 4.0, "sample_hz": 100,
}
SPEC = {"scenario": SCENARIO,
        "problem": {"names": ["friction.Fs", "controller.ki", "reference.levels[0]"],
                    "bounds": [[2.5, 4.0], [20, 100], [0.002, 0.02]]},
        "sampler": "sobol", "n": 8, "seed": 1, "outputs": ["dead_zone", "creep_amplitude"]}


def _with(**kw):
    d = copy.deepcopy(SPEC)
    for path, v in kw.items():
        node = d
        keys = path.split("__")
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = v
    return d


@pytest.mark.parametrize("change,message", [
    (dict(problem__names=["friction.Fx", "controller.ki", "reference.levels[0]"]),
     r"SPEC.problem.names\[0\] 'friction.Fx': friction \(LuGre\) has no field 'Fx'"),
    (dict(problem__names=["friction.Fs", "controller.ki", "reference.levels[2]"]),
     r"reference.levels has 2 entries, no \[2\]"),
    (dict(problem__names=["friction.Fs", "controller.ki", "reference.levels"]),
     r"not a number; index it"),
    (dict(problem__bounds=[[4.0, 2.5], [20, 100], [0.002, 0.02]]),
     r"SPEC.problem.bounds\[0\] \(friction.Fs\): expected lo < hi, got \[4.0, 2.5\]"),
    (dict(problem__bounds=[[2.5, 4.0], [20, 100], [0.002, 0.02]], n=12),
     r"SPEC.n: expected a power of two for the sobol sampler, got 12"),
    (dict(problem__names=["friction.sigma0", "controller.ki", "reference.levels[0]"],
          problem__bounds=[[0, 2e4], [20, 100], [0.002, 0.02]]),
     r"leaves the parameter's range \[0, 10000\] N\*m/deg"),
    (dict(sampler="random"), r"SPEC.sampler: expected"),
    (dict(outputs=["dead_zone", "wobble"]), r"SPEC.outputs\[1\]: expected one of"),
])
def test_bad_spec_one_line(change, message):
    with pytest.raises(ValueError, match=message) as e:
        spec_from_dict(_with(**change))
    assert "\n" not in str(e.value)


def test_cli_bad_spec_exit_2_nothing_written(tmp_path):
    p = tmp_path / "spec.json"
    p.write_text(json.dumps(_with(n=12)))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "lugre_jax.cli", "--no-cache", "sweep", str(p), "--out", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    assert r.stderr.strip().count("\n") == 0
    assert f"{p}: SPEC.n: expected a power of two" in r.stderr
    assert not out.exists()


def test_paths_write_each_lane():
    spec = spec_from_dict(SPEC)
    X = np.array([[2.6, 30.0, 0.003], [3.9, 90.0, 0.015]])
    sysb = batch_system(spec.system, list(spec.paths), X)
    for i, row in enumerate(X):  # the independent route: the scenario file with those values
        d = copy.deepcopy(SCENARIO)
        d["friction"]["Fs"], d["controller"]["ki"], d["reference"]["levels"][0] = row
        ref, _ = scenario_from_dict(d)
        lane = jax.tree.map(lambda x: x[i] if eqx.is_array(x) else x, sysb)
        for a, b in zip(jax.tree.leaves(ref), jax.tree.leaves(lane)):
            np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    # a segmented friction's segment parameter
    d = copy.deepcopy(SPEC)
    d["scenario"] = dict(SCENARIO, friction="paper")
    d["problem"]["names"][0] = "friction.segments[1].sigma0"
    d["problem"]["bounds"][0] = [100, 200]
    spec = spec_from_dict(d)
    sysb = batch_system(spec.system, list(spec.paths), np.array([[150.0, 50.0, 0.01]]))
    assert float(sysb.friction.segments[1].sigma0[0]) == 150.0


def test_metrics_match_numpy_definitions():
    system, _ = scenario_from_dict(dict(SCENARIO, reference={"type": "velocity_step", "velocity_deg_s": 0.005},
                                        duration_s=10.0))
    sol = lj.simulate(system, 10.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.01))
    t, th, om, ref = (np.asarray(x) for x in (sol.ts, sol.theta, sol.omega, sol.theta_ref))
    v = 0.005
    # Tolerances: the same formulas in float64 (JAX vs NumPy summation order): 1e-9 relative.
    assert float(DeadZone("d")(sol)) == pytest.approx(float(M.dead_zone_lag(t, th, v)), rel=1e-9)
    assert float(CreepAmplitude("c")(sol)) == pytest.approx(float(M.creep_amplitude(t, th, ref, t_from=5.0)), rel=1e-9)
    assert float(BandFraction("b")(sol)) == float(M.band_fraction(t, om, v, 0.001, t_from=5.0))
    assert float(TrackingError("e")(sol)) == pytest.approx(float(M.tracking_errors(t, th, ref, t_from=5.0)["rms_deg"]), rel=1e-9)
    slow = np.any(om[t >= 5.0] < 0.1 * v)
    assert float(StickSlip("s")(sol)) == float(slow)
