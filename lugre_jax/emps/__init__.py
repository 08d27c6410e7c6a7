"""EMPS (Janot, Gautier, Brunot 2019): the electro-mechanical positioning system simulated as a
sampled-data loop, identified (IDIM-LS as the benchmark's scripts, output error through the
simulator) and scored by the benchmark's own protocols. SI units (m, m/s, N, kg). See docs/emps.md.
"""

from ..io import EmpsRun as EmpsRun, read_emps_mat as read_emps_mat
from ._fit import (
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
    MODELS as MODELS,
    AbstractEmpsModel as AbstractEmpsModel,
    AsymmetricCoulombViscous as AsymmetricCoulombViscous,
    AsymmetricLuGreRipple as AsymmetricLuGreRipple,
    AsymmetricRipple as AsymmetricRipple,
    CoulombViscous as CoulombViscous,
    LuGre as LuGre,
    Stribeck as Stribeck,
)
from ._pipeline import (
    PUBLISHED as PUBLISHED,
    EmpsReport as EmpsReport,
    ModelReport as ModelReport,
    identify_emps as identify_emps,
    write_emps_outputs as write_emps_outputs,
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
    AbstractStepping as AbstractStepping,
    ExponentialMidpoint as ExponentialMidpoint,
    RungeKutta as RungeKutta,
    closed_loop as closed_loop,
    default_stepping as default_stepping,
    open_loop as open_loop,
)
