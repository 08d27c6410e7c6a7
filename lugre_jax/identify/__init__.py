"""Static friction identification (paper section 4.2): GA, PSO, GA-PSO, gradient refinement, baselines,
whole/piecewise schemes and uncertainty."""

# --- optimisers (owned by the optimiser module authors) ---
# --- end optimisers ---

# --- schemes, data, uncertainty ---
from ._data_gen import (
    make_paper_like_samples as make_paper_like_samples,
    minimum_torque_velocity as minimum_torque_velocity,
    sample_stribeck_data as sample_stribeck_data,
    write_paper_like_csv as write_paper_like_csv,
)
from ._schemes import (
    Boundaries as Boundaries,
    Identification as Identification,
    SegmentFit as SegmentFit,
    auto_bounds as auto_bounds,
    check_bounds_fit as check_bounds_fit,
    detect_boundaries as detect_boundaries,
    identify as identify,
    identify_piecewise as identify_piecewise,
    identify_whole as identify_whole,
    make_objective as make_objective,
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
