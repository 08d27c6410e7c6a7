"""EMPS (Janot, Gautier, Brunot 2019): the electro-mechanical positioning system simulated as a
sampled-data loop, identified (IDIM-LS as the benchmark's scripts, output error through the
simulator) and scored by the benchmark's own protocols. SI units (m, m/s, N, kg). See docs/emps.md.
"""

from ..io import EmpsRun as EmpsRun, read_emps_mat as read_emps_mat
from ._fit import (
    FIT_MAX_STEPS as FIT_MAX_STEPS,
    FitResult as FitResult,
    RunArrays as RunArrays,
    closed_loop_window as closed_loop_window,
    fit_closed_loop as fit_closed_loop,
    fit_open_loop as fit_open_loop,
    open_loop_segments as open_loop_segments,
    segment_starts as segment_starts,
)
from ._idim import (
    IdimResult as IdimResult,
    decimate_matlab as decimate_matlab,
    diffcent as diffcent,
    filtered_kinematics as filtered_kinematics,
    idim_ls as idim_ls,
    sample_period as sample_period,
)
from ._models import (
    DEFAULT_MODELS as DEFAULT_MODELS,
    MODELS as MODELS,
    AbstractEmpsModel as AbstractEmpsModel,
    AsymmetricCoulombViscous as AsymmetricCoulombViscous,
    AsymmetricLuGreRipple as AsymmetricLuGreRipple,
    AsymmetricPositionFriction as AsymmetricPositionFriction,
    AsymmetricPositionLuGre as AsymmetricPositionLuGre,
    AsymmetricRipple as AsymmetricRipple,
    EmpsCoulombViscous as EmpsCoulombViscous,
    EmpsLuGre as EmpsLuGre,
    EmpsStribeck as EmpsStribeck,
)
from ._pipeline import (
    PROTOCOL as PROTOCOL,
    PUBLISHED as PUBLISHED,
    EmpsReport as EmpsReport,
    ModelReport as ModelReport,
    identify_emps as identify_emps,
    write_emps_outputs as write_emps_outputs,
)
from ._pulses import (
    PulseEntry as PulseEntry,
    PulseEstimate as PulseEstimate,
    LocationFit as LocationFit,
    estimate_pulse_entry as estimate_pulse_entry,
    make_pulse_run as make_pulse_run,
    matched_force as matched_force,
    newey_west_cov as newey_west_cov,
    pulse_train as pulse_train,
)
from ._score import (
    BenchmarkScore as BenchmarkScore,
    ClosedLoopScore as ClosedLoopScore,
    benchmark_score as benchmark_score,
    closed_loop_score as closed_loop_score,
    rel_err_pct as rel_err_pct,
)
from ._simulate import (
    VIR_MAX as VIR_MAX,
    AbstractSubstepping as AbstractSubstepping,
    ExponentialMidpoint as ExponentialMidpoint,
    RungeKutta as RungeKutta,
    closed_loop as closed_loop,
    default_stepping as default_stepping,
    fit_stepping as fit_stepping,
    open_loop as open_loop,
)
