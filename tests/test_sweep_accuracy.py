"""The sweep checks its fast stepping against a tight solve before it runs: the deviations go into
summary.json, indices.json and accuracy.json; a step too coarse for the SPEC's accuracy.rtol is
refused with one line naming the key, before anything is written; "enforce": false runs anyway."""

import copy
import json

import pytest

from lugre_jax.sweep import run_sweep, spec_from_dict

SCENARIO = {"friction": "paper", "joint": {"J": 0.128}, "controller": {"type": "velocity_pid", "kp": 8.0, "ki": 60.0},
            "reference": {"type": "velocity_step", "velocity_deg_s": 0.02}, "duration_s": 6.0, "sample_hz": 50}
SPEC = {"scenario": SCENARIO,
        "problem": {"names": ["friction.segments[0].Fs", "friction.segments[0].sigma0"],
                    "bounds": [[4.0, 9.0], [50.0, 200.0]]},
        "sampler": "sobol", "n": 4, "seed": 3, "outputs": ["tracking_error", "dead_zone"], "fallback": None,
        "chunk_size": 16, "num_resamples": 10,
        # Bosh3 at 20 ms is 4e-5 of the outputs' scale from a tight solve on these lanes, Tsit5 at
        # 2.5 ms below 1e-8: a tolerance of 1e-6 tells them apart.
        "accuracy": {"lanes": 4, "rtol": 1e-6}}


def _spec(stepping, **accuracy):
    d = copy.deepcopy(SPEC)
    d["stepping"] = stepping
    d["accuracy"].update(accuracy)
    return spec_from_dict(d)


def test_too_coarse_step_refused_before_anything_is_written(tmp_path):
    out = tmp_path / "coarse"
    with pytest.raises(ValueError, match=r"^SPEC\.accuracy\.rtol: the fast stepping FixedStep\(Bosh3\(\), dt=0\.02\)"):
        run_sweep(_spec({"solver": "bosh3", "dt": 0.02}), out, progress=False, figures=False)
    assert not out.exists()


def test_accuracy_in_summary_and_indices(tmp_path):
    out = tmp_path / "fine"
    res = run_sweep(_spec({"solver": "tsit5", "dt": 0.0025}), out, progress=False, figures=False)
    assert res.complete and res.accuracy["within"] and res.accuracy["lanes_compared"] == 4
    summary = json.loads((out / "summary.json").read_text())
    indices = json.loads((out / "indices.json").read_text())
    for acc in (summary["accuracy"], indices["accuracy"], json.loads((out / "accuracy.json").read_text())):
        assert set(acc["outputs"]) == {"tracking_error", "dead_zone"}
        for o in acc["outputs"].values():
            assert o["max_abs_deviation"] <= 1e-6 * o["scale"] and o["within"]


def test_not_enforced_runs_and_records(tmp_path):
    res = run_sweep(_spec({"solver": "bosh3", "dt": 0.02}, enforce=False), tmp_path / "anyway", progress=False,
                    figures=False)
    assert res.complete and not res.accuracy["within"]
    assert res.accuracy["outputs"]["tracking_error"]["relative"] > 1e-6


def test_accuracy_key_checked():
    d = copy.deepcopy(SPEC)
    d["accuracy"] = {"lanes": 0}
    with pytest.raises(ValueError, match=r"SPEC\.accuracy\.lanes"):
        spec_from_dict(d)
    d["accuracy"] = {"tolerance": 1}
    with pytest.raises(ValueError, match=r"SPEC\.accuracy:"):
        spec_from_dict(d)
    d["accuracy"] = None
    assert spec_from_dict(d).accuracy is None


def test_cli_refusal_exit_2(tmp_path):
    import subprocess
    import sys

    d = copy.deepcopy(SPEC)
    d["stepping"] = {"solver": "bosh3", "dt": 0.02}
    p = tmp_path / "spec.json"
    p.write_text(json.dumps(d))
    r = subprocess.run([sys.executable, "-m", "lugre_jax.cli", "sweep", str(p), "--out", str(tmp_path / "o"),
                        "--no-progress", "--no-figures"], capture_output=True, text=True)
    assert r.returncode == 2 and "accuracy.rtol" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "o").exists()


def test_default_is_lane_adaptive_and_within_a_tight_solve(tmp_path):
    """Without a "stepping" key (and no fixed solver in the scenario) every lane takes its own
    error-controlled step: the accuracy check passes at 1e-6 of each output's scale with no
    fallback."""
    import lugre_jax as lj

    d = copy.deepcopy(SPEC)
    spec = spec_from_dict(d)
    assert spec.fast == lj.LaneAdaptive()
    res = run_sweep(spec, tmp_path / "default", progress=False, figures=False)
    assert res.complete and res.accuracy["within"] and res.accuracy["stepping"].startswith("LaneAdaptive(")
    for o in res.accuracy["outputs"].values():
        assert o["max_abs_deviation"] <= 1e-6 * o["scale"]


def test_stepping_forms():
    import diffrax

    import lugre_jax as lj

    assert _spec({"solver": "bosh3", "dt": 0.01}).fast == lj.FixedStep(diffrax.Bosh3(), dt=0.01)
    assert _spec({"solver": "tsit5"}).fast == lj.FixedStep(diffrax.Tsit5(), dt=2.5e-3)
    assert _spec({"rtol": 1e-7}).fast == lj.LaneAdaptive(rtol=1e-7)
    assert _spec({"solver": "dopri5", "rtol": 1e-5, "atol": 1e-8}).fast == lj.LaneAdaptive(
        diffrax.Dopri5(), rtol=1e-5, atol=1e-8)
    for bad, msg in (({"solver": "bosh3", "rtol": 1e-6}, r"SPEC\.stepping\.solver: expected one of tsit5, dopri5"),
                     ({"dt": 0.01, "rtol": 1e-6}, r"^SPEC\.stepping: expected"),
                     ({"rtol": -1.0}, r"SPEC\.stepping\.rtol: expected a positive number"),
                     ({"solver": "euler", "dt": 0.01}, r"SPEC\.stepping\.solver: expected one of")):
        with pytest.raises(ValueError, match=msg):
            _spec(bad)


def test_default_stepping_is_part_of_the_digest():
    """A SPEC without "stepping" runs the default, so a folder swept under another default is not
    resumed (its digest differs); with "stepping" the digest is the SPEC's alone."""
    import dataclasses

    import lugre_jax as lj

    spec = spec_from_dict(copy.deepcopy(SPEC))
    assert spec.digest() != dataclasses.replace(spec, fast=lj.FixedStep()).digest()
    given = _spec({"solver": "bosh3", "dt": 0.01})
    assert given.digest() == dataclasses.replace(given, fast=lj.FixedStep()).digest()
