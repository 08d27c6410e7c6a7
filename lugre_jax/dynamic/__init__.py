"""Dynamic LuGre parameters (sigma0, sigma1), Li et al., Electronics 2020, 9, 284, section 4.2.5:
the paper's pre-sliding step (eq. 17) and eq. (18), time-series identification through the simulator
with Fisher-information standard errors, and D-optimal excitation design."""

from ._presliding import (
    EQ18_FACTOR as EQ18_FACTOR,
    PreslidingResult as PreslidingResult,
    inertia_eq18 as inertia_eq18,
    lugre_from_static as lugre_from_static,
    presliding_step as presliding_step,
    sigma1_eq18 as sigma1_eq18,
)
from ._timeseries import (
    DynamicFit as DynamicFit,
    design_grid as design_grid,
    fisher_information as fisher_information,
    fit_dynamic as fit_dynamic,
    standard_errors_from_fisher as standard_errors_from_fisher,
    theta_response as theta_response,
    torque_sine_system as torque_sine_system,
    with_dynamics as with_dynamics,
)
