"""A joint model's structure refitted on all samples, and its predicted torque: what a study beside
:func:`diagnose` (which holds every fifth time block out) compares, e.g. a benchmark that
fits on every sample."""

from __future__ import annotations

import numpy as np

from . import _model as M
from ._select import _all_specs


def predict(model: M.JointModel, kin: M.Kinematics) -> np.ndarray:
    """The torque ``model`` predicts along ``kin`` (:func:`kinematics_of` of a recording), in the
    recording's units: :meth:`JointModel.predict` compiled once per length bucket, so recordings of
    similar length share one compilation."""
    return M.predict(model, kin)


def refit(model: M.JointModel, rec, *, fit_offset: bool = False, kin: M.Kinematics | None = None):
    """``model``'s structure (inertia, friction, candidates; the offset too with ``fit_offset``)
    refitted by Levenberg-Marquardt on every sample of the recording ``rec``, from ``model``'s values
    and within the bounds :func:`diagnose` fits in. ``kin`` is ``kinematics_of(rec)`` when
    the caller has it. Returns (model, info), info holding the solver's ``result`` name and ``steps``."""
    kin = M.kinematics_of(rec) if kin is None else kin
    space = M.FitSpace(_all_specs(model, M.data_scales(rec), fit_offset))
    return M.fit(M.clip_into(space, model), space, kin, rec.torque, np.ones(rec.n))
