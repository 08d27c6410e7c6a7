"""Static friction identification (paper section 4.2): GA, PSO, GA-PSO, gradient refinement, baselines,
whole/piecewise schemes and uncertainty.

The public surface is what a user calls and the results it returns: the schemes (``identify``,
``identify_whole``, ``identify_piecewise``) and their results, the optimisers and their runner
(``optimise``, ``minimise``), the paper-like data, the boundary detection and smoothing of section
4.2.1, and the standard errors. Optimiser states, encodings and objective builders stay in their
modules.
"""

# --- optimisers ---
from ._baselines import CMAES as CMAES, DE as DE
from ._fitness import RunResult as RunResult, paper_fitness as paper_fitness
from ._optimiser import AbstractOptimiser as AbstractOptimiser, minimise as minimise
from ._ga import GA as GA, RealGA as RealGA
from ._gapso import GAPSO as GAPSO
from ._pso import PSO as PSO
from ._refine import Refine as Refine, RefineResult as RefineResult, result_name as result_name
from ._run import OptimResult as OptimResult, optimise as optimise

# --- schemes, data, uncertainty ---
from ._data_gen import (
    decel_branch as decel_branch,
    make_paper_like_samples as make_paper_like_samples,
    minimum_torque_velocity as minimum_torque_velocity,
    paper_like_velocities as paper_like_velocities,
    sample_stribeck_data as sample_stribeck_data,
    table1_static_model as table1_static_model,
)
from ._schemes import (
    Boundaries as Boundaries,
    Identification as Identification,
    SegmentFit as SegmentFit,
    Smoothed as Smoothed,
    auto_bounds as auto_bounds,
    detect_boundaries as detect_boundaries,
    identify as identify,
    identify_piecewise as identify_piecewise,
    identify_whole as identify_whole,
    smooth_segments as smooth_segments,
)
from ._smoothing import (
    SmoothingSpline as SmoothingSpline,
    SumOfSines as SumOfSines,
    fit_smoothing_spline as fit_smoothing_spline,
    fit_sum_of_sines as fit_sum_of_sines,
    fit_tangent_branch as fit_tangent_branch,
)
from ._uncertainty import Uncertainty as Uncertainty, crlb as crlb, standard_errors as standard_errors
