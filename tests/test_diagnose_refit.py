"""The public refit and predict of :mod:`lugre_jax.diagnose` (an application, experiments/diagnose_emps,
compares diagnose's held-out fits with its structure refitted on every sample)."""

import numpy as np

import lugre_jax
from lugre_jax.diagnose import effect_instance, initial_baseline, kinematics_of, make_recording, predict, refit

lugre_jax.configure()


def test_refit_on_all_samples_lowers_the_error_and_keeps_the_structure():
    rec, _ = make_recording(seed=1, effect=None, duration=20.0)
    kin = kinematics_of(rec)
    start = initial_baseline(rec, "lugre", fit_offset=True)
    fitted, info = refit(start, rec, fit_offset=True, kin=kin)
    assert type(fitted.friction) is type(start.friction) and fitted.candidates == ()
    assert isinstance(info["result"], str) and info["steps"] > 0
    y = np.asarray(rec.torque)
    rms = lambda m: float(np.sqrt(np.mean((y - predict(m, kin)) ** 2)))  # noqa: E731
    assert rms(fitted) < rms(start)
    # kin is only a shortcut: without it the recording's own kinematics are used
    again, _ = refit(start, rec, fit_offset=True)
    assert np.allclose(predict(again, kin), predict(fitted, kin), rtol=0, atol=1e-9)


def test_refit_fits_the_candidates_too():
    rec, truth = make_recording(seed=2, effect="position_ripple", strength=8.0, duration=20.0)
    base = initial_baseline(rec, "lugre")
    start = type(base)(base.J, base.friction, base.offset, (effect_instance("position_ripple", 2.0),))
    fitted, _ = refit(start, rec)
    got, true = float(fitted.candidates[0].amplitude), float(truth["effect_module"].amplitude)
    assert len(fitted.candidates) == 1 and abs(got - true) < abs(float(start.candidates[0].amplitude) - true)


def test_predict_is_the_models_own_prediction():
    rec, _ = make_recording(seed=1, effect=None, duration=5.0)
    kin = kinematics_of(rec)
    model = initial_baseline(rec, "lugre")
    got = predict(model, kin)
    assert got.shape == (rec.n,)
    np.testing.assert_allclose(got, np.asarray(model.predict(kin)), rtol=1e-12, atol=1e-12)
