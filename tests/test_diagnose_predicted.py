"""The held-out samples a diagnosis scores are those the training blocks predict: a held-out sample
whose model torque the fit does not determine (leverage past the kinematics' own criterion) leaves
the validation, and nothing else does."""

from __future__ import annotations

import dataclasses

import equinox as eqx
import numpy as np

import lugre_jax  # noqa: F401
from lugre_jax.diagnose import make_recording
from lugre_jax.diagnose import _model as M
from lugre_jax.diagnose import _select as S
from lugre_jax.diagnose._config import DiagnoseConfig


def _prepared():
    rec, _ = make_recording(seed=3, effect=None, duration=60.0)
    prep, split = S._prepare(rec, DiagnoseConfig(), None, "lugre", False)
    return prep, split


def test_held_out_samples_the_training_does_not_determine_leave_the_validation():
    """Reference: the fit's own behaviour. Held out, the slow samples (|v| under 3 vs, where only Fs,
    vs and the bristles act) while the fit sees none of them: their leverage is past 0.25 and
    they leave ``val`` and ``keep`` (and only they); a fit moved along what the training leaves
    undetermined (Fs and vs changed, the training SSE within a hundredth of one noise variance) predicts them
    differently by more than half the noise. The blocks' own held-out phase loses nothing."""
    prep, split = _prepared()
    share = DiagnoseConfig().resolved_share
    # the recording's own split: every sample determined
    assert S._predicted(prep, split, False, share) is split

    v = np.abs(np.asarray(prep.rec.velocity))
    vs = float(prep.base.friction.vs)
    slow = split.keep & (v < 3 * vs)
    crafted = dataclasses.replace(split, val=slow, w=(split.keep & ~slow).astype(float),
                                  cv_mask=split.keep.copy())
    out = S._predicted(prep, crafted, False, share)
    dropped = crafted.val & ~out.val
    assert out.unpredicted == int(dropped.sum()) > 0.2 * int(slow.sum())
    assert not np.any(out.keep & dropped) and np.array_equal(out.keep | dropped, crafted.keep)
    assert np.array_equal(out.w, crafted.w)

    tau = np.asarray(prep.rec.torque)
    base = prep.base
    other = eqx.tree_at(lambda m: (m.friction.Fs, m.friction.vs), base,
                        (base.friction.Fs * 1.5, base.friction.vs * 0.7))
    p0, p1 = M.predict(base, prep.kin), M.predict(other, prep.kin)
    rows = crafted.w > 0
    sse0 = float(np.sum((tau - p0)[rows] ** 2))
    sse1 = float(np.sum((tau - p1)[rows] ** 2))
    assert abs(sse1 - sse0) < 0.01 * 0.05 ** 2  # a hundredth of one noise variance
    assert float(np.max(np.abs(p1 - p0)[dropped])) > 0.5 * 0.05


def test_given_parameters_taken_as_an_estimate_keep_the_refit():
    """Reference: the fitted baseline's own preparation. Given parameters are held fixed (no free
    parameter, no leverage rule); with ``refit=True`` they count as the fitted baseline's do, and the
    refit flag without parameters is refused."""
    import pytest

    from lugre_jax.diagnose import diagnose

    prep, _ = _prepared()
    params = M.model_params(prep.base)
    held, _ = S._prepare(prep.rec_in, DiagnoseConfig(), params, "lugre", False)
    taken, _ = S._prepare(prep.rec_in, DiagnoseConfig(), params, "lugre", False, refit=True)
    assert held.k == 0
    assert taken.k == prep.k == len(M.baseline_specs(prep.base, M.data_scales(prep.rec), False)) > 0
    with pytest.raises(ValueError, match="refit"):
        diagnose(prep.rec_in, refit=True)


def test_friction_smoothing_error_is_the_conditionings_blur_of_a_friction_driven_acceleration():
    """Reference: the conditioning itself. A joint whose motor torque is linear in time and whose
    friction switches sharply has the acceleration (u - f)/J; conditioned from its velocity (and from
    its position), J times the conditioned acceleration's shortfall is the column, to rounding: the
    filter passes the motor's part exactly and blurs the friction's switches."""
    from types import SimpleNamespace

    from scipy.integrate import cumulative_trapezoid

    from lugre_jax.diagnose._condition import conditioned_kinematics, friction_smoothing_error

    t = np.arange(0.0, 4.0, 1e-3)
    J = 0.3
    f = 1.2 * np.tanh(np.sin(2 * np.pi * 1.3 * t) / 0.02)  # reversals, sharp
    u = 0.5 + 0.8 * t
    a = (u - f) / J
    v = np.concatenate([[0.0], cumulative_trapezoid(a, t)])
    th = np.concatenate([[0.0], cumulative_trapezoid(v, t)])
    for source, blend in (("velocity", 0.0), ("velocity", -0.4), ("position", 0.3)):
        cond = SimpleNamespace(source=source, window=41, order=3, blend=blend)
        a_c = conditioned_kinematics(t, th, v, source, 41, 3, blend)[1]
        col = friction_smoothing_error(t, f, cond)
        inner = slice(100, -100)  # the filter's edge samples extrapolate
        err = J * (a - a_c)  # what the residual keeps: the torque holds J*a, the model J*a_c
        assert np.max(np.abs(err[inner])) > 0.1  # the blur is there
        np.testing.assert_allclose(col[inner], err[inner], atol=1e-6 * np.max(np.abs(err)))
