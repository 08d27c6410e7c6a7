"""Diagnose model-reality mismatch: locate residual structure, name missing physics, refit.

Inverse LuGre joint model of Li et al. (Electronics 2020, 9, 284), fitted by Levenberg-Marquardt;
residual tests with Holm-controlled false-alarm rate; a library of candidate physics, each named
only when its gain beats a null distribution simulated for the recording (family-wise at one
stated alpha, :class:`DiagnoseConfig`) and it lowers the held-out error. Entry point: :func:`diagnose`, which returns a :class:`Diagnosis`
(``to_json()`` is REPORT.json).
"""

from ._config import DiagnoseConfig as DiagnoseConfig
from ._locate import holm as holm, locate as locate
from ._model import (
    AbstractCandidate as AbstractCandidate,
    JointModel as JointModel,
    Kinematics as Kinematics,
    baseline_from_params as baseline_from_params,
    initial_baseline as initial_baseline,
    kinematics_of as kinematics_of,
    lugre_torque as lugre_torque,
    model_params as model_params,
)
from ._physics import (
    CANDIDATES as CANDIDATES,
    Asymmetry as Asymmetry,
    Backlash as Backlash,
    Compliance as Compliance,
    Gravity as Gravity,
    LoadDependent as LoadDependent,
    PositionRipple as PositionRipple,
    StribeckShape as StribeckShape,
    ThermalDrift as ThermalDrift,
)
from ._plots import effect_torques as effect_torques, plot_report as plot_report
from ._refit import predict as predict, refit as refit
from ._report import (
    Baseline as Baseline,
    Diagnosis as Diagnosis,
    DiagnosisArrays as DiagnosisArrays,
    Finding as Finding,
    Improved as Improved,
    RecordingInfo as RecordingInfo,
    Region as Region,
)
from ._select import diagnose as diagnose
from ._synthetic import effect_instance as effect_instance, make_recording as make_recording
