"""Static friction identification (paper section 4.2): GA, PSO, GA-PSO, gradient refinement, baselines,
whole/piecewise schemes and uncertainty."""

# --- optimisers (owned by the optimiser module authors) ---
from ._baselines import CMAES as CMAES, DE as DE, EvosaxState as EvosaxState, scipy_least_squares as scipy_least_squares
from ._fitness import (
    RunResult as RunResult,
    evaluate as evaluate,
    finite_or_inf as finite_or_inf,
    half_sse as half_sse,
    loss_from_residual as loss_from_residual,
    paper_fitness as paper_fitness,
)
from ._optimiser import AbstractOptimiser as AbstractOptimiser, minimise as minimise
from ._ga import GA as GA, GAState as GAState, RealGA as RealGA, decode as decode, encode as encode
from ._gapso import GAPSO as GAPSO, GAPSOState as GAPSOState
from ._pso import PSO as PSO, PSOState as PSOState, hash_uniform as hash_uniform
from ._refine import BoxTransform as BoxTransform, Refine as Refine, RefineResult as RefineResult, result_name as result_name
from ._run import METHODS as METHODS, OptimResult as OptimResult, make_optimiser as make_optimiser, optimise as optimise
# --- end optimisers ---

# --- schemes, data, uncertainty ---
from ._data_gen import (
    decel_branch as decel_branch,
    make_paper_like_samples as make_paper_like_samples,
    minimum_torque_velocity as minimum_torque_velocity,
    paper_like_velocities as paper_like_velocities,
    sample_stribeck_data as sample_stribeck_data,
    table1_static_model as table1_static_model,
    write_paper_like_csv as write_paper_like_csv,
)
from ._schemes import (
    Boundaries as Boundaries,
    Identification as Identification,
    SegmentFit as SegmentFit,
    Smoothed as Smoothed,
    auto_bounds as auto_bounds,
    check_bounds_fit as check_bounds_fit,
    detect_boundaries as detect_boundaries,
    identify as identify,
    identify_piecewise as identify_piecewise,
    identify_whole as identify_whole,
    make_objective as make_objective,
    smooth_segments as smooth_segments,
)
from ._smoothing import (
    SmoothingSpline as SmoothingSpline,
    SumOfSines as SumOfSines,
    fit_smoothing_spline as fit_smoothing_spline,
    fit_sum_of_sines as fit_sum_of_sines,
    fit_tangent_branch as fit_tangent_branch,
)
from ._uncertainty import (
    Uncertainty as Uncertainty,
    crlb as crlb,
    fisher_information as fisher_information,
    identifiability_statement as identifiability_statement,
    standard_errors as standard_errors,
)
# --- end schemes ---
