"""Static (Stribeck) identification: boundary detection, whole/piecewise recovery of known parameters,
standard errors against the Cramer-Rao bound, smoothing (spline, eq. 12), bounds errors and the CLI.
Units: deg/s, N*m."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from lugre_jax.cli import main as cli_main
from lugre_jax.friction import CoulombViscous, Stribeck, bounds_of, from_vector, names_of, units_of
from lugre_jax.identify import (
    auto_bounds,
    crlb,
    detect_boundaries,
    fit_smoothing_spline,
    fit_sum_of_sines,
    fit_tangent_branch,
    identify_piecewise,
    identify_whole,
    make_paper_like_samples,
    minimum_torque_velocity,
    paper_like_velocities,
    sample_stribeck_data,
    standard_errors,
    table1_static_model,
)
from lugre_jax.identify._schemes import check_bounds_fit  # internals under test
from lugre_jax.io import summarise_samples
from lugre_jax.plant import TABLE1


def curve(kind, x, v):
    """Steady-state torque of the model ``kind`` with parameter vector ``x`` (the public route)."""
    return from_vector({"stribeck": Stribeck, "coulomb_viscous": CoulombViscous}[kind], x).steady_state(v)

TRUTH = np.array([0.9, 2.4, 0.05, 3.0])  # Fc [N*m], Fs [N*m], vs [deg/s], sigma2 [N*m*s/deg]
NOISE = 0.08  # N*m per sample, 30 samples per set-point
ACCEL_V, _ = paper_like_velocities(0.09)


def _paper_like(seed):
    c = make_paper_like_samples(seed)
    return summarise_samples(c["velocity_deg_s"], c["torque_nm"], c["branch"])


def test_boundary_detection_on_paper_like_data():
    """v_min within 0.015 deg/s of the generating model's minimum (0.0919 deg/s, Table 1 model) and
    v_crit within 0.02 deg/s of its kink at 1.2 deg/s, over three noise realisations. (The minimum is
    flat: the true curve changes by < 0.01 N*m over 0.08-0.10 deg/s, so its location is noise-limited.)"""
    v_true, _ = minimum_torque_velocity(table1_static_model())
    assert abs(v_true - 0.0919) < 1e-3
    for seed in (0, 1, 2):
        b = detect_boundaries(_paper_like(seed))
        assert abs(b.v_min - v_true) < 0.015, (seed, b.v_min)
        assert abs(b.v_crit - 1.2) < 0.02, (seed, b.v_crit)


def test_whole_recovery_and_se_coverage_against_crlb():
    """Whole scheme on data drawn from a known Stribeck curve: over 4 realisations every parameter is
    within 3.5 standard errors of the truth, and the standard errors agree with the CRLB to 25 %."""
    bound = np.sqrt(np.diag(crlb(lambda x, v: curve("stribeck", x, v), TRUTH, ACCEL_V, NOISE / np.sqrt(30))))
    for i in range(4):
        d = sample_stribeck_data(Stribeck(*TRUTH), ACCEL_V, key=jax.random.key(i), noise_sd=NOISE)
        s = identify_whole(d, "lm", key=jax.random.key(100 + i), n_seeds=16).segments[0]
        z = (s.x - TRUTH) / s.uncertainty.se
        assert np.all(np.abs(z) < 3.5), (i, s.x, z)
        np.testing.assert_allclose(s.uncertainty.se, bound, rtol=0.25)


def test_crlb_matches_linear_least_squares_closed_form():
    """For eq. (11) (linear in Fc, sigma2 at v > 0) the CRLB is sigma^2 (A^T A)^-1 exactly."""
    v = np.linspace(0.2, 1.5, 17)
    A = np.stack([np.ones_like(v), v], axis=1)
    sigma = 0.03
    C = crlb(lambda x, vv: curve("coulomb_viscous", x, vv), np.array([4.5, 0.01]), v, sigma)
    np.testing.assert_allclose(C, sigma**2 * np.linalg.inv(A.T @ A), rtol=1e-9)


def test_standard_errors_flag_unidentifiable_parameter():
    """With Fs == Fc the Stribeck velocity has no effect on the curve: the statement must say so."""
    v = jnp.linspace(0.1, 1.5, 30)
    x = jnp.array([1.0, 1.0, 0.3, 2.0])
    y = curve("stribeck", x, v) + 0.01 * jax.random.normal(jax.random.key(0), v.shape)
    u = standard_errors(lambda p: (curve("stribeck", p, v) - y) / 0.01, x, ("Fc", "Fs", "vs", "sigma2"))
    assert "vs" in u.poorly_determined
    assert "vs" in u.statement


def test_piecewise_recovers_table1_with_paper_edges():
    """Accelerating-branch data drawn from Table 1 (segments split at 0.05 and 1.2 deg/s): the
    piecewise scheme with those edges recovers each segment's parameters within 3.5 SE."""

    d = sample_stribeck_data(table1_static_model(), ACCEL_V, key=jax.random.key(7), noise_sd=NOISE)
    # Table 1 itself jumps by 0.008 N*m at 0.05 deg/s: recover each segment on its own (no continuity
    # pseudo-observation), then check that the default (continuity on) leaves only small jumps.
    r = identify_piecewise(d, "lm", key=jax.random.key(3), n_seeds=16, edges=(0.05, 1.2), continuity_weight=0.0)
    by = {s.name: s for s in r.segments}
    for k in ("1", "2"):
        z = (by[k].x - np.array(TABLE1[int(k)])) / by[k].uncertainty.se
        assert np.all(np.abs(z) < 3.5), (k, by[k].x, z)
    Fc3, s23 = TABLE1[3][0], TABLE1[3][3]
    z3 = (by["3"].x - np.array([Fc3, s23])) / by["3"].uncertainty.se
    assert np.all(np.abs(z3) < 3.5), (by["3"].x, z3)
    assert abs(r.jumps["v_min"]) < 0.05 and abs(r.jumps["v_crit"]) < 0.05
    rc = identify_piecewise(d, "lm", key=jax.random.key(3), n_seeds=16, edges=(0.05, 1.2))
    assert abs(rc.jumps["v_min"]) < 0.01 and abs(rc.jumps["v_crit"]) < 0.01


def test_piecewise_detected_on_shipped_style_data_fits_well():
    """Detected boundaries, both branches: every segment's RMS is below twice the per-point noise of
    the averages (0.08/sqrt(30) = 0.015 N*m -> 0.03), except the decelerating branch, whose shape
    (Table 1 minus a quadratic) is not exactly a Stribeck curve (< 0.1 N*m)."""
    r = identify_piecewise(_paper_like(0), "lm", key=jax.random.key(0), n_seeds=16)
    names = [s.name for s in r.segments]
    assert names == ["1", "1 decel", "2", "3"]
    for s in r.segments:
        assert s.rms < (0.1 if s.branch == "decel" else 0.03), (s.name, s.rms)
    # the decelerating branch starts lower (static friction when stopping < when starting)
    dec = {s.name: s for s in r.segments}["1 decel"]
    acc = {s.name: s for s in r.segments}["1"]
    assert dec.params["Fs"] < acc.params["Fs"] - 1.0


def test_spline_sum_of_sines_and_tangent_branch():
    """Eq. (12) with 4 terms reproduces a smooth curve to < 1 % of its range; the decelerating
    branch has the same value and slope as the accelerating spline at the tangent point."""
    v = np.linspace(0.1, 1.2, 40)
    y = 0.86 + 3.05 * v + 0.4 * np.exp(-((v / 0.3) ** 2))
    spl = fit_smoothing_spline(v, y, lam=1e-12)
    ss = fit_sum_of_sines(spl, 0.1, 1.2)
    g = np.linspace(0.1, 1.2, 101)
    assert np.max(np.abs(ss(g) - spl(g))) < 0.01 * np.ptp(y)
    vd = np.linspace(0.01, 0.08, 8)
    branch = fit_tangent_branch(spl, vd, spl(vd) - 2.0 * (1 - vd / 0.09) ** 2, 0.09)
    np.testing.assert_allclose(branch(0.09), spl(0.09), atol=1e-12)
    np.testing.assert_allclose(branch.derivative(0.09), spl.derivative(0.09), atol=1e-9)
    np.testing.assert_allclose(branch(vd), spl(vd) - 2.0 * (1 - vd / 0.09) ** 2, atol=1e-9)


def test_bounds_that_cannot_fit_the_data_are_an_error():
    lo, hi = np.zeros(4), np.array([10.0, 10.0, 1.0, 10.0])
    with pytest.raises(ValueError, match="cannot fit"):
        check_bounds_fit("stribeck", np.array([0.01, 0.02]), np.array([12.0, 11.5]), np.array([0.01, 0.01]), lo, hi)
    check_bounds_fit("stribeck", np.array([0.01, 0.02]), np.array([6.0, 5.5]), np.array([0.01, 0.01]), lo, hi)


def test_cli_identify_whole_and_errors(tmp_path, capsys):
    d = sample_stribeck_data(CoulombViscous(1.0, 2.0), np.linspace(0.1, 1.5, 12), key=jax.random.key(0), n_repeats=3, noise_sd=0.02)
    p = tmp_path / "d.csv"
    rows = ["velocity_deg_s,torque_nm"] + [f"{v},{t}" for v, t in zip(np.repeat(d.velocity, 2), np.repeat(d.torque, 2) + np.tile([-0.01, 0.01], 12))]
    p.write_text("\n".join(rows) + "\n")
    out = tmp_path / "r.json"
    rc = cli_main(["identify", str(p), "--method", "lm", "--scheme", "whole", "--model", "coulomb_viscous", "--seeds", "4", "--out", str(out)])
    assert rc == 0
    res = json.loads(out.read_text())
    seg = res["segments"][0]
    assert set(seg["parameters"]) == {"Fc", "sigma2"}
    assert abs(seg["parameters"]["Fc"] - 1.0) < 0.05 and abs(seg["parameters"]["sigma2"] - 2.0) < 0.05
    for key in ("velocity_range_deg_s", "loss", "standard_errors", "evaluations", "wall_time_s"):
        assert key in seg
    # typed result's record: units and bounds from the model's declaration, the optimiser's steps
    assert seg["units"] == {"Fc": "N*m", "sigma2": "N*m*s/deg"}
    assert seg["bounds"] == {"Fc": [0.0, 10.0], "sigma2": [0.0, 10.0]} and seg["steps"] == 1
    assert res["wall_time_s"] >= seg["wall_time_s"] > 0
    # torques above 10 N*m cannot be fitted with the paper's bounds -> exit 2 with a clear message
    big = tmp_path / "big.csv"
    big.write_text("velocity_deg_s,torque_nm\n" + "".join(f"{v},{15 + v}\n{v},{15.1 + v}\n" for v in (0.01, 0.02, 0.1, 0.5, 1.0)))
    rc = cli_main(["identify", str(big), "--method", "lm", "--scheme", "whole", "--out", str(tmp_path / "x.json")])
    assert rc == 2
    assert "cannot fit" in capsys.readouterr().err
    bad = tmp_path / "bad.csv"
    bad.write_text("velocity_deg_s,torque_nm\n0.1,1\n0.2,oops\n")
    assert cli_main(["identify", str(bad), "--out", str(tmp_path / "y.json")]) == 2
    assert "bad.csv:3" in capsys.readouterr().err
    assert not (tmp_path / "y.json").exists()


def test_parameter_registry_is_the_models_declaration():
    # the scheme code derives names, order, units and bounds from the friction models' param() fields
    from lugre_jax.identify._schemes import NAMES, UNITS, default_bounds  # internals under test

    assert NAMES["stribeck"] == names_of(Stribeck) == ("Fc", "Fs", "vs", "sigma2")
    assert NAMES["coulomb_viscous"] == names_of(CoulombViscous) == ("Fc", "sigma2")
    assert UNITS == {"Fc": "N*m", "Fs": "N*m", "vs": "deg/s", "sigma2": "N*m*s/deg"} == units_of(Stribeck)
    for kind, cls in (("stribeck", Stribeck), ("coulomb_viscous", CoulombViscous)):
        np.testing.assert_array_equal(np.stack(default_bounds(kind)), np.stack(bounds_of(cls)))
    # the paper's section 4.2.2 ranges, read independently of the registry
    np.testing.assert_array_equal(np.stack(bounds_of(Stribeck)), [[0, 0, 0, 0], [10, 10, 1, 10]])
    # auto bounds follow each parameter's unit: torques 2*max|tau|, velocity max|v|, viscous their ratio
    d = sample_stribeck_data(Stribeck(1.0, 1.5, 0.2, 0.5), np.linspace(0.05, 4.0, 12), key=jax.random.key(1),
                             n_repeats=2, noise_sd=0.0)
    tmax, vmax = float(np.max(np.abs(d.torque))), float(np.max(np.abs(d.velocity)))
    lo, hi = auto_bounds("stribeck", d)
    np.testing.assert_allclose(hi, [2 * tmax, 2 * tmax, vmax, 2 * tmax / vmax], rtol=1e-15)
    assert np.all(lo == 0)
