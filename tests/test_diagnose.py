"""Tests of lugre_jax.diagnose: recovery of each candidate physics on synthetic recordings, the null
case, malformed recordings, the locator's statistics and the stiff bristle update."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import lugre_jax  # noqa: F401
from lugre_jax.diagnose import DiagnoseConfig, diagnose, holm, make_recording
from lugre_jax.diagnose._synthetic import effect_instance
from lugre_jax.io._recording import load_recording, write_recording

DURATION = 200.0  # s: half the proof experiment's recordings, to keep the suite fast
STRENGTH = 2.0  # x the concealed reference level of the proof experiment

# effect -> (parameter name in the report, true value getter, relative tolerance)
CHECKS = {
    "position_ripple": [("period", lambda e: float(e.period), 0.05),
                        ("amplitude", lambda e: float(e.amplitude), 0.30)],
    "gravity": [("amplitude", lambda e: float(e.amplitude), 0.30)],
    "asymmetry": [("offset", lambda e: float(e.offset), 0.30)],
    "thermal_drift": [("rate", lambda e: float(e.rate), 0.30)],
    "stribeck_shape": [("delta", lambda e: float(e.delta), 0.10)],
    "backlash": [("width", lambda e: float(e.width), 0.30), ("share", lambda e: float(e.share), 0.30)],
    "compliance": [("fn_hz", lambda e: float(e.fn), 0.05)],
    "load_dependent": [("mu", lambda e: float(e.mu), 0.30)],
}


# The two most confusable rivals of each effect compete with it here (CI budget: compiling and
# refitting all eight per test costs minutes); the full library competes in the proof experiment
# (experiments/diagnose_proof).
RIVALS = {
    "position_ripple": ["gravity", "asymmetry"],
    "gravity": ["position_ripple", "asymmetry"],
    "asymmetry": ["gravity", "thermal_drift"],
    "thermal_drift": ["asymmetry", "gravity"],
    "stribeck_shape": ["asymmetry", "load_dependent"],
    "backlash": ["stribeck_shape", "load_dependent"],
    "compliance": ["load_dependent", "asymmetry"],
    "load_dependent": ["asymmetry", "stribeck_shape"],
}


@pytest.mark.parametrize("effect", list(CHECKS))
def test_candidate_named_first_and_recovered(effect):
    rec, truth = make_recording(seed=3, effect=effect, strength=STRENGTH, duration=DURATION)
    rep = diagnose(rec, progress=False, max_effects=1, candidates=RIVALS[effect] + [effect])
    # naming does not need the residual tests to locate anything first: the calibrated test is the
    # more powerful of the two on a single effect
    assert rep.missing_physics, f"{effect}: nothing named"
    first = rep.missing_physics[0]
    assert first.name == effect, (effect, rep.verdict, rep.selection_log)
    eff = effect_instance(effect, STRENGTH)
    for key, true_of, tol in CHECKS[effect]:
        got, true = first.params[key], true_of(eff)
        assert abs(got - true) <= tol * abs(true), (effect, key, got, true)
    assert rep.improved.validation_rmse_nm < rep.baseline.validation_rmse_nm


@pytest.mark.parametrize("seed", [101, 102])
def test_null_recording_gives_none(seed):
    rec, _ = make_recording(seed=seed, effect=None, duration=DURATION)
    rep = diagnose(rec, progress=False)
    assert rep.verdict == "none", rep.mismatch
    assert rep.missing_physics == ()
    # the fitted baseline is the truth within noise: validation RMSE within 5% of the noise std
    assert abs(rep.baseline.validation_rmse_nm / 0.05 - 1) < 0.05


# REPORT.json as `lugre-jax diagnose` wrote it while diagnose returned a dict; Diagnosis.to_json()
# keeps it: these keys in this order, a region being a located test cut to REGION_KEYS.
REPORT_KEYS = ["recording", "baseline", "alpha", "kappa_long_run_variance", "verdict", "mismatch", "n_tests",
               "missing_physics", "improved", "selection_log", "seconds", "config", "attribution"]
RECORDING_KEYS = ["source", "n_samples", "units", "duration", "sample_rate_hz", "validation", "held_out_phase",
                  "cross_validated_phases"]
BASELINE_KEYS = ["params", "rmse_nm", "validation_rmse_nm", "fit", "noise_floor_nm", "torque_noise_nm",
                 "kinematic_noise_nm", "floor_ratio", "at_floor", "shortcoming", "conditioning",
                 "unresolved_transient_fraction", "at_rest_fraction", "fixed_phase_rmse_nm"]
REGION_KEYS = ("test", "region", "statistic", "p_value", "p_holm", "mean_residual", "ci95", "df", "n")
FINDING_KEYS = ["name", "explanation", "params", "validation_rmse_nm", "delta_bic", "p_validation", "p_family",
                "alternatives", "alternative_terms"]
IMPROVED_KEYS = ["params", "rmse_nm", "validation_rmse_nm", "fixed_phase_rmse_nm"]


def test_diagnosis_to_json_is_the_report(tmp_path):
    """Two effects, one of them offered: an accepted finding, an unexplained one, binned and
    spectral regions and two selection steps all reach the JSON; each part is its attributes, the
    regions are the locator's own entries, and the written file reads back equal and as --params."""
    from lugre_jax import testing as T
    from lugre_jax.diagnose import Diagnosis, Finding, Region
    from lugre_jax.io import load_params_json, read_json, write_json

    exc = T.Staircase(speeds=(0.02, 0.1, 0.5, 2.0, 4.0), dwell=6.0, seed=3)
    g = T.generate(exc, [T.PositionRippleEffect(0.12, 5.0, 1.0), T.AsymmetryEffect(0.1)], sensors=T.Sensors(fs=100.0), seed=9)
    rep = diagnose(g.to_recording(), progress=False, candidates=["position_ripple", "gravity"])
    assert isinstance(rep, Diagnosis)
    assert rep.verdict == "position_ripple+unexplained", rep.selection_log
    js = rep.to_json()
    assert list(js) == REPORT_KEYS
    assert js["recording"] == {k: getattr(rep.recording, k) for k in RECORDING_KEYS}
    assert list(js["recording"]) == RECORDING_KEYS
    assert js["baseline"] == {k: getattr(rep.baseline, k) for k in BASELINE_KEYS}
    assert list(js["baseline"]) == BASELINE_KEYS
    assert js["improved"] == {k: getattr(rep.improved, k) for k in IMPROVED_KEYS}
    assert list(js["improved"]) == IMPROVED_KEYS
    for k in ("alpha", "kappa_long_run_variance", "verdict", "n_tests", "selection_log", "seconds"):
        assert js[k] == getattr(rep, k), k
    assert len(js["selection_log"]) == 2

    def cut(x):
        return {k: x[k] for k in REGION_KEYS if k in x}

    located = rep.arrays.loc0["located"]
    assert all(isinstance(m, Region) for m in rep.mismatch)
    assert js["mismatch"] == [cut(x) for x in located]
    assert [list(m) for m in js["mismatch"]] == [list(cut(x)) for x in located]
    assert {len(m) for m in js["mismatch"]} == {5, 9}  # spectral/whiteness and binned regions
    accepted, unexplained = rep.missing_physics
    assert isinstance(accepted, Finding) and not accepted.unexplained and unexplained.unexplained
    assert rep.named == ["position_ripple", "unexplained"]
    assert list(js["missing_physics"][0]) == FINDING_KEYS
    assert list(js["missing_physics"][1]) == FINDING_KEYS[:4]  # no fit, no evidence
    assert js["missing_physics"][0]["delta_bic"] == accepted.delta_bic < 0
    assert js["missing_physics"][1]["params"]["regions"] == [cut(x) for x in rep.arrays.loc1["located"]][:10]
    assert js["missing_physics"][1]["params"]["attribution"] == js["attribution"]
    assert js["config"] == rep.config and js["config"]["alpha"] == rep.alpha
    # the null's kinematic draws in the arrays are those the floor's kinematic part is the rms of
    # (over the training samples: resolved, not held out)
    ke, rows = np.asarray(rep.arrays.kinematic_errors), rep.arrays.keep & ~rep.arrays.val
    assert ke.shape == (DiagnoseConfig().kinematic_draws, rep.arrays.r0.size)
    assert rep.baseline.kinematic_noise_nm > 0
    assert np.sqrt(np.mean(ke[:, rows] ** 2)) == pytest.approx(rep.baseline.kinematic_noise_nm, rel=1e-9)
    # a named finding lowers the held-out error and beat its simulated null family-wise
    assert accepted.validation_rmse_nm < rep.baseline.validation_rmse_nm
    assert accepted.p_family < rep.alpha / 3
    assert "arrays" not in js

    path = tmp_path / "REPORT.json"
    write_json(path, js)
    assert read_json(path) == js
    assert load_params_json(path)["J"] == rep.baseline.params["J"]


def _ripple_and_offset_recording():
    """A staircase through a joint with a position ripple and a torque offset (100 Hz)."""
    from lugre_jax import testing as T

    exc = T.Staircase(speeds=(0.02, 0.1, 0.5, 2.0, 4.0), dwell=6.0, seed=3)
    g = T.generate(exc, [T.PositionRippleEffect(0.12, 5.0, 1.0), T.AsymmetryEffect(0.1)], sensors=T.Sensors(fs=100.0), seed=9)
    return g.to_recording()


def test_two_findings_report_the_final_joint_fit():
    """Ripple + torque offset, both offered: both are named, one per step, and the second step
    refits both (the first one alone takes a part of the other: the joint dwells near the start
    position at slow speed, where the ripple's sine is ~0.8). Each finding reports its parameters
    in that final joint model, within 10 % (2 % for the period) of the truth."""
    rep = diagnose(_ripple_and_offset_recording(), progress=False, candidates=["position_ripple", "asymmetry"])
    assert sorted(rep.named) == ["asymmetry", "position_ripple"], rep.selection_log
    ripple, asym = sorted(rep.missing_physics, key=lambda f: f.name != "position_ripple")
    for f in (ripple, asym):
        assert f.params == rep.improved.params[f.name]
    assert abs(ripple.params["amplitude"] / 0.12 - 1) < 0.1, ripple.params
    assert abs(ripple.params["period"] / 5.0 - 1) < 0.02, ripple.params
    assert abs(asym.params["offset"] / 0.1 - 1) < 0.1, asym.params


def test_holm_matches_hand_computation():
    p = np.array([0.01, 0.04, 0.03, 0.005])
    # sorted: 0.005*4=0.02, 0.01*3=0.03, 0.03*2=0.06, 0.04*1=0.04 -> running max 0.06
    np.testing.assert_allclose(holm(p), [0.03, 0.06, 0.06, 0.02])


def test_exact_exponential_bristle_update_matches_fine_ode():
    """Per-sample exact-exponential z update vs scipy's stiff solver on the same velocity."""
    import jax.numpy as jnp
    from scipy.integrate import solve_ivp

    from lugre_jax.diagnose._model import lugre_torque
    from lugre_jax.diagnose._synthetic import true_friction

    f = true_friction()
    t = np.arange(0, 4.0, 0.01)
    vfun = lambda s: 1.5 * np.sin(2 * np.pi * 0.5 * s)  # noqa: E731 (reversals at 0, 1, 2, 3 s)
    v = vfun(t)
    F = np.asarray(lugre_torque(f, jnp.asarray(v), jnp.asarray(np.diff(t)), z0=0.0))
    g = lambda vv: float(f.g(vv))  # noqa: E731
    sol = solve_ivp(lambda s, z: [vfun(s) - 100.0 * abs(vfun(s)) * z[0] / g(vfun(s))], (0, t[-1]), [0.0],
                    method="Radau", t_eval=t, rtol=1e-10, atol=1e-12)
    z = sol.y[0]
    Fref = 100.0 * z + 2.0 * (v - 100.0 * np.abs(v) * z / np.array([g(x) for x in v])) + 0.5 * v
    # mid-interval velocity hold: error O(h^2) in the state; well below the 0.05 N*m test noise
    assert np.max(np.abs(F - Fref)) < 0.02


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "rec.csv"
    p.write_text(text)
    return p


GOOD_HEADER = "time_s,position_deg,velocity_deg_s,torque_nm\n"


def _rows(n=20, bad=None):
    lines = []
    for i in range(n):
        cells = [f"{0.01 * i:.2f}", f"{0.1 * i:.3f}", "1.0", "0.5"]
        if bad and bad[0] == i:
            cells[bad[1]] = bad[2]
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    "text, fragments",
    [
        # position or velocity may be absent (the other is derived), not both
        ("time_s,torque_nm\n" + "0,0\n" * 12, ["line 1", "position_deg or velocity_deg_s"]),
        (GOOD_HEADER + _rows(bad=(5, 3, "nan")), ["line 7", "torque_nm", "finite"]),
        (GOOD_HEADER + _rows(bad=(4, 2, "abc")), ["line 6", "velocity_deg_s", "not a number"]),
        (GOOD_HEADER + _rows(bad=(8, 0, "0.01")), ["line 10", "time_s", "increasing"]),
        (GOOD_HEADER + _rows(bad=(3, 1, "")), ["line 5", "position_deg", "not a number"]),
        ("", ["line 1", "empty"]),
    ],
)
def test_malformed_recordings_raise_with_file_line_column(tmp_path, text, fragments):
    p = _write(tmp_path, text)
    with pytest.raises(ValueError) as ei:
        load_recording(p)
    msg = str(ei.value)
    assert str(p) in msg
    for frag in fragments:
        assert frag in msg, (frag, msg)


def test_short_row_is_reported(tmp_path):
    p = _write(tmp_path, GOOD_HEADER + _rows(12) + "0.5,1.0\n")
    with pytest.raises(ValueError, match=r"line 14: column 'velocity_deg_s' is missing"):
        load_recording(p)


def test_csv_roundtrip_and_cli_error_exit(tmp_path, capsys):
    from lugre_jax.cli import main

    rec, _ = make_recording(seed=1, effect=None, duration=20.0)
    p = tmp_path / "ok.csv"
    write_recording(p, rec)
    back = load_recording(p)
    np.testing.assert_allclose(back.torque, rec.torque, rtol=1e-10)
    assert back.units["torque"] == "N*m"
    bad = _write(tmp_path, GOOD_HEADER + _rows(bad=(5, 3, "nan")))
    assert main(["diagnose", str(bad), "--out", str(tmp_path / "r.json")]) == 2
    err = capsys.readouterr().err
    assert "line 7" in err and "torque_nm" in err
    assert not (tmp_path / "r.json").exists()


def test_emps_loader_reproduces_benchmark_idim(request):
    from lugre_jax.emps import idim_ls, read_emps_mat
    from lugre_jax.io._emps import default_emps_path, load_emps

    path = Path(request.config.rootpath) / default_emps_path()
    if not path.exists():
        pytest.skip(f"EMPS data not found at {path}")
    rec = load_emps(path)
    assert rec.units["position"] == "m" and rec.units["torque"] == "N"
    assert rec.n == 2480
    fit = idim_ls(read_emps_mat(path)).params
    # published: M = 95.1089 kg, Fv = 203.5034 N*s/m, Fc = 20.3935 N, offset = -3.1648 N
    assert abs(fit["M"] / 95.1089 - 1) < 0.01
    assert abs(fit["Fv"] / 203.5034 - 1) < 0.03
    assert abs(fit["Fc"] / 20.3935 - 1) < 0.05
    assert abs(fit["offset"] - (-3.1648)) < 0.2


def test_a_ripple_whose_gain_lives_at_one_speed_is_implausible():
    """PositionRipple.implausible: over a staircase of four speeds, a residual that repeats with
    position at every speed is accepted; one that oscillates only on the slowest plateau (a
    baseline's stick-slip misfit, which a short-period 'ripple' can fit there and nowhere else:
    the held-out recording held_effect00) is rejected with the speed-quartile reason."""
    from types import SimpleNamespace

    import jax.numpy as jnp

    from lugre_jax.diagnose._physics import PositionRipple

    fs, dwell = 200.0, 20.0
    speeds = np.repeat([0.005, 0.05, 0.5, 3.0], int(dwell * fs))
    theta = np.cumsum(speeds) / fs
    noise = 0.04 * np.random.default_rng(0).standard_normal(theta.size)
    kin = SimpleNamespace(theta=jnp.asarray(theta), v=jnp.asarray(speeds))
    ripple = PositionRipple(jnp.asarray(0.02), jnp.asarray(0.08), jnp.asarray(1.0))
    s = 0.02 * np.sin(2 * np.pi * theta / 0.08 + 1.0)
    def ctx(residual):  # the Context fields the check reads
        return SimpleNamespace(scales={"P": float(theta[-1] - theta[0])}, position_resolution=0.0005, kin=kin,
                               residual=residual)

    assert ripple.implausible(ctx(s + noise)) is None
    slow_only = np.where(speeds < 0.01, s, 0.0) + noise
    why = ripple.implausible(ctx(slow_only))
    assert why is not None and "speed quartiles" in why, why


def test_a_compliance_is_plausible_up_to_the_accelerations_bandwidth():
    """Compliance.implausible: a natural frequency below the conditioned acceleration's bandwidth
    (where it still passes 1/sqrt(2) of a sine's acceleration) stays, one above it is refused."""
    from types import SimpleNamespace

    import jax.numpy as jnp

    from lugre_jax.diagnose._physics import Compliance

    ctx = SimpleNamespace(accel_bandwidth_hz=6.48, baseline=SimpleNamespace(J=0.2))

    def spring(fn):
        return Compliance(jnp.asarray(fn), jnp.asarray(0.1), jnp.asarray(0.06))

    assert spring(4.91).implausible(ctx) is None
    why = spring(6.6).implausible(ctx)
    assert why is not None and "bandwidth 6.48 Hz" in why, why
    # only the refusal above the bandwidth is the kinematics' resolution (the selection step then
    # judges its other candidates with that structure in the model); an overdamped one is not
    assert spring(6.6).beyond_resolution(ctx) and not spring(4.91).beyond_resolution(ctx)
    damped = Compliance(jnp.asarray(4.91), jnp.asarray(0.8), jnp.asarray(0.06))
    assert damped.implausible(ctx) is not None and not damped.beyond_resolution(ctx)


def test_a_backlash_narrower_than_the_bristles_is_implausible():
    """Backlash.implausible: with a LuGre baseline of pre-sliding length max(Fs, Fc)/sigma0 = 0.005
    deg, a gap of 0.001 deg acts within the bristles' own transition after a reversal and is
    rejected; 0.02 deg stays plausible; a baseline without bristles leaves the check out."""
    from types import SimpleNamespace

    import jax.numpy as jnp

    from lugre_jax.diagnose._physics import Backlash
    from lugre_jax.friction import LuGre, Stribeck

    lugre = LuGre(Fc=0.6, Fs=1.0, vs=0.05, sigma0=200.0, sigma1=1.0, sigma2=1.0)
    ctx = SimpleNamespace(position_resolution=1e-5, baseline=SimpleNamespace(friction=lugre))
    why = Backlash(jnp.asarray(0.001), jnp.asarray(0.05)).implausible(ctx)
    assert why is not None and "pre-sliding" in why and "0.005" in why, why
    assert Backlash(jnp.asarray(0.02), jnp.asarray(0.05)).implausible(ctx) is None
    ctx_s = SimpleNamespace(position_resolution=1e-5,
                            baseline=SimpleNamespace(friction=Stribeck(Fc=0.6, Fs=1.0, vs=0.05, sigma2=1.0)))
    assert Backlash(jnp.asarray(0.001), jnp.asarray(0.05)).implausible(ctx_s) is None


def test_a_gravity_that_is_flat_over_the_positions_is_implausible():
    """Gravity.implausible: over 40 deg of travel around its crest, A*sin(theta + 1.23) varies by
    2 % of its mean (the fresh set's ripple + asymmetry recording, where such a 'gravity' took the
    asymmetry's constant torque by 9 BIC units): rejected as a constant torque. The issue's gravity
    (phase -0.3: the sine's slope over the span) is mostly variation and stays plausible."""
    from types import SimpleNamespace

    import jax.numpy as jnp

    from lugre_jax.diagnose import DiagnoseConfig
    from lugre_jax.diagnose._physics import Gravity

    theta = np.concatenate([np.linspace(0.0, 39.6, 500), np.linspace(39.6, 0.0, 500)])  # the sine's crest
    ctx = SimpleNamespace(scales={"P": float(np.ptp(theta)), "T": 5.0}, rec=SimpleNamespace(position=theta),
                          config=DiagnoseConfig())
    flat = Gravity(jnp.asarray(0.062), jnp.asarray(1.23))
    why = flat.implausible(ctx)
    assert why is not None and "constant torque" in why, why
    assert Gravity(jnp.asarray(0.15), jnp.asarray(-0.3)).implausible(ctx) is None


def _multisine(t, freqs, amp=1.0):
    return sum(amp * np.sin(2 * np.pi * f * t + 0.7 * k) for k, f in enumerate(freqs))


def test_motion_lines_finds_a_multisines_lines_and_not_their_side_lobes():
    """11 log-spaced lines (the generator's multisine band, 0.056-1.75 Hz) in white velocity noise at
    190 Hz over 38.5 s: every line above 0.4 Hz found within a tenth of a Fourier bin, no other (a
    side lobe of a line 1e4 above the background is 50x it, and would be found if lines were not
    fitted out). Below, the six lowest lie within 12 Fourier bins, so their tapered main lobes fill
    the median's window: crowded lines there read as a red hump, as in locate's time lines."""
    from lugre_jax.diagnose._attribute import motion_lines

    rng = np.random.default_rng(3)
    t = np.arange(0.0, 38.5, 1 / 190.0)
    freqs = np.geomspace(0.056, 1.75, 11)
    v = _multisine(t, freqs) + 0.05 * rng.standard_normal(t.size)
    found = np.sort(motion_lines(t, v, 0.05 / 3))
    want = freqs[freqs > 0.4]
    assert found.size == want.size, found
    assert np.max(np.abs(found - want)) < 0.1 / t[-1], found - want


def test_motion_lines_hold_their_alpha_on_a_line_free_velocity():
    """Coloured noise (AR(1) 0.9) with no line: a line is claimed on at most the binomial 99.9 %
    bound of 100 recordings at alpha 0.05 (a per-ordinate threshold without the family's
    correction claims one on nearly every recording)."""
    from scipy.signal import lfilter
    from scipy.stats import binom

    from lugre_jax.diagnose._attribute import motion_lines

    t = np.arange(0.0, 30.0, 1 / 200.0)
    hits = 0
    for seed in range(100):
        e = np.random.default_rng(seed).standard_normal(t.size)
        hits += motion_lines(t, lfilter([1.0], [1.0, -0.9], e), 0.05).size > 0
    assert hits <= binom.ppf(0.999, 100, 0.05), hits


def test_the_time_line_is_fitted_off_the_motions_lines():
    """A sine at a motion line is what a linear kinematic error makes: fitted off the lines it is
    gone (below 1e-3 of its norm); a sine three Fourier bins away keeps over 0.9 of its norm."""
    from lugre_jax.diagnose._attribute import _line_columns, _off_lines, _sincos, motion_lines

    t = np.arange(0.0, 38.5, 1 / 190.0)
    freqs = np.geomspace(0.056, 1.75, 11)
    v = _multisine(t, freqs) + 0.05 * np.random.default_rng(4).standard_normal(t.size)
    lines = _line_columns(t, motion_lines(t, v, 0.05 / 3))
    rows = np.ones(t.size, bool)
    rows[::5] = False
    at_line = _sincos(t, freqs[-1])
    away = _sincos(t, freqs[-1] + 3.0 / t[-1])
    assert np.linalg.norm(_off_lines(at_line, lines, rows)) < 1e-3 * np.linalg.norm(at_line)
    assert np.linalg.norm(_off_lines(away, lines, rows)) > 0.9 * np.linalg.norm(away)


def test_the_smoothing_bias_rule_reads_the_whole_models_torque():
    """A velocity step from +0.05 to -0.05 deg/s in 30 ms, seen through a 57-sample window at
    190 Hz (velocity only): the inertia's change from W to 2W-1 (J 0.1) stays below the rule's share, but a
    friction that turns with the direction (Fc*tanh(v/0.01), Fc 1 N*m) changes by many times it
    near the reversal. Those samples, and only those (within two windows of it), are unresolved."""
    import jax.numpy as jnp

    from lugre_jax.diagnose._condition import Conditioning, model_bias_unresolved
    from lugre_jax.diagnose._model import Kinematics
    from lugre_jax.io import recording_from_arrays

    fs, W = 190.0, 57
    t = np.arange(0.0, 20.0, 1 / fs)
    v_true = 0.05 * np.sign(10.0 - t) * np.minimum(np.abs(t - 10.0) / 0.015, 1.0)
    rng = np.random.default_rng(0)
    vel = v_true + 0.004 * rng.standard_normal(t.size)
    pos = np.concatenate([[0.0], np.cumsum(0.5 * (vel[1:] + vel[:-1]) * np.diff(t))])
    rec = recording_from_arrays(time=t, torque=np.zeros_like(t), velocity=vel, position=pos)
    from scipy.signal import savgol_filter

    v = savgol_filter(vel, W, 3, delta=1 / fs)
    a = savgol_filter(vel, W, 3, deriv=1, delta=1 / fs)
    kin = Kinematics(jnp.asarray(t), jnp.asarray(pos), jnp.asarray(v), jnp.asarray(a), jnp.asarray(np.diff(t)),
                     jnp.asarray(np.diff(pos)), jnp.asarray(1.0))
    cond = Conditioning(torque_noise=0.05, velocity_noise=0.004, position_noise=0.0, quantisation=0.0,
                        source="velocity", window=W, order=3, accel_noise_torque=0.0, velocity_noise_after=0.0)
    J = 0.1
    inertial = model_bias_unresolved(rec, cond, kin, lambda k: J * np.asarray(k.a))
    friction = model_bias_unresolved(rec, cond, kin, lambda k: J * np.asarray(k.a) + np.tanh(np.asarray(k.v) / 0.01))
    assert not inertial.any()
    near = np.abs(t - 10.0) < 2 * W / fs
    assert friction[near].sum() > 10 and not friction[~near].any(), (friction[near].sum(), friction[~near].sum())
    # derivatives of a quantised position: the rule does not read them
    enc = dataclasses.replace(cond, source="position", quantisation=0.001, position_noise=0.001 / np.sqrt(12.0))
    assert not model_bias_unresolved(rec, enc, kin, lambda k: J * np.asarray(k.a) + np.tanh(np.asarray(k.v) / 0.01)).any()


def test_a_term_reading_follows_its_coefficients_sign():
    """v|v| with a negative coefficient is not drag: the reading says the friction grows slower than
    linearly with speed (TRO2021 driveNo1's term); one-column groups without a signed reading, and
    two-column ones, keep theirs."""
    from lugre_jax.diagnose._attribute import TIME_LINE, TermGroup

    g = TermGroup("velocity_squared", ("v*|v|",), ("N*m*s^2/deg^2",), "grows with v|v|: drag",
                  "falls with v|v|: slower than linear")
    assert g.read([2e-8]) == "grows with v|v|: drag"
    assert g.read([-2e-8]) == "falls with v|v|: slower than linear"
    assert TermGroup("time", ("t",), ("N*m/s",), "drifts").read([-1.0]) == "drifts"
    assert TIME_LINE.read([-1.0, -1.0]) == TIME_LINE.reading


def test_noise_free_simulation_is_reported_as_such(tmp_path):
    """The project's own noise-free output (a position sine through `lugre-jax simulate`) has no
    measurement noise to calibrate against: the report says so in its shortcoming. The same run
    with seeded sensor noise added (torque 0.02 N*m, velocity 0.002 deg/s, position 1e-4 deg)
    carries no such clause, and its torque noise is estimated within 10 %."""
    import json

    from lugre_jax.cli import main

    scen = json.loads((Path(__file__).parents[1] / "experiments" / "scenarios" / "position_sine_pid.json").read_text())
    scen["duration_s"] = 12.0
    (tmp_path / "s.json").write_text(json.dumps(scen))
    assert main(["simulate", str(tmp_path / "s.json"), "--out", str(tmp_path / "sim.csv"), "--quiet"]) == 0
    assert main(["diagnose", str(tmp_path / "sim.csv"), "--out", str(tmp_path / "r0.json"), "--quiet"]) == 0
    rep = json.loads((tmp_path / "r0.json").read_text())
    assert "no measurable noise" in (rep["baseline"]["shortcoming"] or ""), rep["baseline"]

    d = np.genfromtxt(tmp_path / "sim.csv", delimiter=",", names=True)
    rng = np.random.default_rng(4)
    cols = {"time_s": d["time_s"], "position_deg": d["position_deg"] + rng.normal(0, 1e-4, d.size),
            "velocity_deg_s": d["velocity_deg_s"] + rng.normal(0, 0.002, d.size),
            "torque_nm": d["torque_nm"] + rng.normal(0, 0.02, d.size)}
    np.savetxt(tmp_path / "noisy.csv", np.column_stack(list(cols.values())), delimiter=",",
               header=",".join(cols), comments="", fmt="%.10g")
    assert main(["diagnose", str(tmp_path / "noisy.csv"), "--out", str(tmp_path / "r1.json"), "--quiet"]) == 0
    b = json.loads((tmp_path / "r1.json").read_text())["baseline"]
    assert "no measurable noise" not in (b["shortcoming"] or "")
    assert abs(b["torque_noise_nm"] / 0.02 - 1) < 0.1, b


@pytest.mark.parametrize("correlation", [0.8, 0.95])
def test_starts_are_spaced_by_their_shapes_correlation(correlation):
    """spaced_starts: on a family of bumps whose widths span two decades, each start's shape
    correlates at least ``correlation`` with the next start's, the shape after that next start
    falls below it (no start is wasted), the first and last shapes are starts, and a closer bound
    takes more of them."""
    from lugre_jax.diagnose._physics import spaced_starts

    t = np.linspace(-1.0, 1.0, 4001)
    widths = np.geomspace(0.005, 0.5, 60)
    shapes = np.exp(-0.5 * (t[None, :] / widths[:, None]) ** 2)
    u = shapes / np.linalg.norm(shapes, axis=1)[:, None]
    picks = spaced_starts(shapes, correlation)
    assert picks[0] == 0 and picks[-1] == len(widths) - 1 and picks == sorted(set(picks))
    for p, q in zip(picks[:-1], picks[1:]):
        assert u[p] @ u[q] >= correlation or q == p + 1
        if q < len(widths) - 1:
            assert u[p] @ u[q + 1] < correlation
    assert 2 < len(picks) < len(widths)
    assert len(spaced_starts(shapes, 0.5 * (1.0 + correlation))) > len(picks)
    # made a batch at a time (a grid too fine to hold whole), the same starts
    for batch in (1, 7, 60):
        assert spaced_starts((lambda idx: shapes[idx], len(widths)), correlation, batch=batch) == picks


def test_compliance_starts_leave_no_spring_between_them():
    """compliance_starts on an acceleration that steps between -50, 0 and 50 every 0.3-1.5 s (40 s
    at 400 Hz): a spring anywhere in 0.6-15 Hz, damped at the starts' zeta 0.1 or lighter (0.08),
    has a start whose response correlates at least 0.9 with its own; with the fixed list 0.5, 1,
    1.5, 2, 3, 5, 7, 10, 15, 20 Hz some spring correlates below 0.5 with every start (its ringing
    after each step decorrelates within a few per cent of fn)."""
    import jax.numpy as jnp

    from lugre_jax.diagnose._model import Kinematics
    from lugre_jax.diagnose._physics import _compliance_response, compliance_starts

    fs, T = 400.0, 40.0
    t = np.arange(0.0, T, 1.0 / fs)
    rng = np.random.default_rng(1)
    edges = np.cumsum(rng.uniform(0.3, 1.5, 60))
    a = 50.0 * rng.choice([-1.0, 0.0, 1.0], 61)[np.searchsorted(edges, t)]
    z = jnp.zeros(t.size)
    kin = Kinematics(jnp.asarray(t), z, z, jnp.asarray(a), jnp.full(t.size - 1, 1.0 / fs), z[1:], jnp.asarray(0.0))
    starts = compliance_starts(kin, fs, 0.8)
    assert starts[0] == 0.5 and abs(starts[-1] - 20.0) < 1e-9 and starts == sorted(starts)

    def unit(fn, zeta):
        x = np.asarray(_compliance_response(jnp.asarray(a), 1.0 / fs, fn, zeta))
        return x / np.linalg.norm(x)

    U = np.stack([unit(f, 0.1) for f in starts])
    fixed = np.stack([unit(f, 0.1) for f in (0.5, 1, 1.5, 2, 3, 5, 7, 10, 15, 20)])
    springs = np.geomspace(0.6, 15.0, 60)
    for zeta in (0.1, 0.08):
        assert min(np.max(U @ unit(fn, zeta)) for fn in springs) >= 0.9
    assert min(np.max(np.abs(fixed @ unit(fn, 0.1))) for fn in springs) < 0.5


def test_a_backlash_width_is_found_by_its_profile_where_lm_leaves_it():
    """On an encoder's quantised positions the dead band's torque changes with its width only where
    a gap crossing ends on another encoder step, so the least-squares objective is piecewise flat
    and LM leaves a width where it starts; ``fit`` profiles it (a log grid, the share solved at
    each value). Encoder step 0.001 deg, true width 0.025 deg: from starts 1.8x and 0.45x the true
    width (as far as a start can be from it) the fit lands within 5 % of it,
    while LM alone from 1.8x moves it by under 5 % (and fits worse). Its identifiability is the
    share's, the width held."""
    import equinox as eqx
    import jax.numpy as jnp

    from lugre_jax.diagnose import _model as M
    from lugre_jax.diagnose._physics import Backlash
    from lugre_jax.diagnose._synthetic import TRUE_J, true_friction

    rec, truth = make_recording(seed=3, effect="backlash", strength=STRENGTH, duration=100.0)
    rec = dataclasses.replace(rec, position=np.round(np.asarray(rec.position) / 1e-3) * 1e-3)
    true = truth["effect_module"]
    kin = M.kinematics_of(rec)
    tau = np.asarray(rec.torque)
    w = np.ones(tau.shape)
    scales = M.data_scales(rec)
    base = M.JointModel(jnp.asarray(TRUE_J), true_friction(), jnp.asarray(0.0),
                        (Backlash(true.width, true.share),))
    space = M.FitSpace(M.baseline_specs(base, scales, False) + M.candidate_specs(base, 0, scales))

    def start(factor):
        return M.clip_into(space, eqx.tree_at(lambda m: m.candidates[0].width, base,
                                              jnp.asarray(factor * float(true.width))))

    for factor in (1.8, 0.45):
        fitted, info = M.fit(start(factor), space, kin, tau, w)
        assert float(fitted.candidates[0].width) == pytest.approx(float(true.width), rel=0.05), (factor, info)
    lm_only, _ = M._lm_fit(start(1.8), space, kin, jnp.asarray(tau), jnp.asarray(w),
                           jnp.asarray(float(np.std(tau))), 200)
    assert float(lm_only.candidates[0].width) == pytest.approx(1.8 * float(true.width), rel=0.05)
    fitted, _ = M.fit(start(1.8), space, kin, tau, w)
    assert np.sum((tau - M.predict(fitted, kin)) ** 2) < np.sum((tau - M.predict(lm_only, kin)) ** 2)
    # identifiability holds the profiled width at its value: the share's Wald z with the width's
    # column left out of the Jacobian, not the width's own z through its event-driven column
    from lugre_jax.diagnose._select import _identifiability

    z = _identifiability(fitted, space, kin, tau, w, 1.0, fitted.candidates[0])
    held = M.FitSpace([sp for sp in space.specs if sp.name != "backlash.width"])
    share, se_share = M.standard_errors(fitted, held, kin, tau, w, 1.0)["backlash.share"]
    width, se_width = M.standard_errors(fitted, space, kin, tau, w, 1.0)["backlash.width"]
    assert z == pytest.approx(share / se_share, rel=1e-9) and z != pytest.approx(width / se_width, rel=0.1)


def test_a_library_term_predicting_as_well_as_the_named_candidate_is_listed_with_it():
    """The named candidate's held-out residual against three library terms' on 40 blocks of white
    noise of std 1: one term makes the named candidate's prediction 10 % larger (z about 0.7),
    one removes nothing (the residual before the finding), one makes a quarter of the finding's
    change. Only the first is listed: the held-out test at ``alpha_confirm`` cannot tell it from
    the named one, and the others do not lower the held-out error (the second) or are predicted
    significantly worse (the third, z about 10). The first is not listed either when the model's
    linearised refit alone predicts as well: the change is not the term's."""
    from types import SimpleNamespace

    from lugre_jax.diagnose._attribute import Rivals, TermGroup
    from lugre_jax.diagnose._select import _term_alternatives

    rng = np.random.default_rng(0)
    n, blocks = 40_000, np.repeat(np.arange(40), 1000)
    noise = rng.standard_normal(n)
    effect = 0.1 * np.sin(np.arange(n) / 50.0)  # the finding's change of prediction: 0.07 rms
    r_before, r_named = noise + effect, noise
    split = SimpleNamespace(blocks=blocks, cv_mask=np.ones(n, bool))
    cfg = DiagnoseConfig()
    cv_before = float(np.sqrt(np.mean(r_before ** 2)))
    group = lambda name: TermGroup(name, ("x",), ("N*m",), f"reads {name}")  # noqa: E731
    terms = [(group("same"), noise - 0.1 * effect, "reads same"),
             (group("nothing"), r_before, "reads nothing"),
             (group("quarter"), noise + 0.75 * effect, "")]
    # the model's linearised refit alone removes nothing here
    alts = _term_alternatives(r_named, cv_before, Rivals(terms, refit=r_before), split, cfg)
    assert [a["term"] for a in alts] == ["same"], alts
    assert alts[0]["p_named_better"] > cfg.alpha_confirm and alts[0]["reading"] == "reads same"
    # the same term when the refit alone predicts as well: the change is not the term's
    assert _term_alternatives(r_named, cv_before, Rivals(terms[:1], refit=noise - 0.1 * effect), split, cfg) == []


def test_the_hump_restart_finds_a_narrow_stribeck_hump_a_humpless_model_misses():
    """Twelve moves between dwells (peak speeds 3.5-7 deg/s, 200 Hz, white torque noise 0.1 N*m)
    through a LuGre joint whose Stribeck hump is narrow (Fs 2.4 over Fc 1.8, vs 0.04 deg/s: under 1 %
    of the speed scale). From the same joint without its hump, :func:`hump_restart` reaches a
    least-squares fit at least as good as the truth's (training SSE within one noise variance of
    it, or below) with vs within 25 % of the truth's; the humpless model is about 18 noise variances
    worse."""
    import jax.numpy as jnp

    from lugre_jax.diagnose import _model as M
    from lugre_jax.diagnose._select import hump_restart
    from lugre_jax.friction import LuGre

    fs, T, vmax = 200.0, 2.0, 7.0
    t_move = np.arange(0.0, T, 1 / fs)
    rng = np.random.default_rng(1)
    v, a = [], []
    for k in range(12):
        peak = (-1) ** k * rng.uniform(0.5, 1.0) * vmax
        v += [peak * np.sin(np.pi * t_move / T) ** 2, np.zeros(int(fs))]
        a += [peak * np.pi / T * np.sin(2 * np.pi * t_move / T), np.zeros(int(fs))]
    v, a = np.concatenate(v), np.concatenate(a)
    t = np.arange(v.size) / fs
    th = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) / fs)])
    kin = M.Kinematics(*(jnp.asarray(x) for x in (t, th, v, a, np.diff(t), np.diff(th), 0.0)))

    def joint(Fs, vs):
        return M.JointModel(jnp.asarray(0.25), LuGre(Fc=1.8, Fs=Fs, vs=vs, sigma2=1.8, sigma0=50.0, sigma1=2.5,
                                                     require_passive=False), jnp.asarray(0.0))

    true = joint(2.4, 0.04)
    tau = M.predict(true, kin) + 0.1 * rng.standard_normal(v.size)
    w = (v != 0).astype(float)
    scales = {"T": 3.0, "V": vmax, "A": 25.0, "P": 20.0, "D": float(t[-1]), "1": 1.0, "fs": fs}
    scales |= {"T/V": 3.0 / vmax, "T/A": 3.0 / 25.0, "T/P": 3.0 / 20.0, "1/D": 1.0 / float(t[-1])}
    space = M.FitSpace(M.baseline_specs(true, scales, False))

    def sse(m):  # in noise variances
        return float(np.sum(w * (tau - M.predict(m, kin)) ** 2)) / 0.01

    flat = M.clip_into(space, joint(1.8 * 1.0001, 1.2))
    assert sse(flat) > sse(true) + 10.0
    found, r = hump_restart(flat, space, kin, tau, w, vmax, DiagnoseConfig())
    assert r is not None and sse(found) <= sse(true) + 1.0
    np.testing.assert_allclose(r, tau - M.predict(found, kin), rtol=0, atol=1e-12)
    assert float(found.friction.vs) == pytest.approx(0.04, rel=0.25)


def test_a_moved_hump_is_kept_only_where_its_path_predicts_better(monkeypatch):
    """Where the hump restart moves the fit after a finding, the selection goes on from both fits and
    keeps the path whose final model has the lower cross-validated error. Here the restart is
    replaced by one that returns the fit with its inertia tripled (a lower training SSE is claimed,
    not checked), on the two-findings recording of the test above with one greedy step: the log
    records both paths, the tripled inertia predicts the held-out blocks worse and is dropped, and
    the report's held-out error is the kept path's."""
    import equinox as eqx
    import jax.numpy as jnp

    from lugre_jax.diagnose import _select as S

    def restart_tripled(model, space, kin, tau, weights, V, cfg, **kw):
        moved = eqx.tree_at(lambda m: m.J, model, jnp.asarray(3.0 * float(model.J)))
        return moved, S._weighted_sse(moved, kin, np.asarray(tau), np.asarray(weights, float))[1]

    monkeypatch.setattr(S, "hump_restart", restart_tripled)
    rep = diagnose(_ripple_and_offset_recording(), progress=False, candidates=["position_ripple", "asymmetry"],
                   max_effects=1)
    paths = rep.selection_log[0]["hump_restart_paths"]
    assert paths["cv_rmse_not_restarted_nm"] < paths["cv_rmse_restarted_nm"], paths
    assert rep.selection_log[0]["hump_restarted"] is False
    assert rep.improved.validation_rmse_nm == pytest.approx(paths["cv_rmse_not_restarted_nm"], rel=1e-12)
    named = [n for n in rep.named if n != "unexplained"]
    assert named == paths["named_not_restarted"] and len(named) == 1
