"""The joint simulator: the closed loop as one ODE, solved one scenario at a time or in batches.

Layout by concern: ``_system`` (the ODE), ``_stepping`` (choices as objects), ``_fixed``
(fixed-step RK in ``lax.scan``), ``_adaptive`` (diffrax, error-controlled), ``_lanes`` (chunks and
devices), ``_jit`` (the jit boundary), ``_simulate`` (the entry point), ``_solution`` (what comes back).
"""

from ._lanes import (
    batch_size_of as batch_size_of,
    broadcast_system as broadcast_system,
    map_lanes as map_lanes,
    stack_systems as stack_systems,
)
from ._simulate import (
    SteppingCheck as SteppingCheck,
    check_stepping as check_stepping,
    default_stepping as default_stepping,
    simulate as simulate,
)
from ._solution import (
    RESULT_NAMES as RESULT_NAMES,
    RESULT_NONFINITE as RESULT_NONFINITE,
    RESULT_OK as RESULT_OK,
    RESULT_SOLVER_FAILED as RESULT_SOLVER_FAILED,
    Sample as Sample,
    SampleMean as SampleMean,
    SampleValues as SampleValues,
    Solution as Solution,
    trajectory_loss as trajectory_loss,
)
from ._stepping import (
    AbstractStepping as AbstractStepping,
    Adaptive as Adaptive,
    ExponentialBristle as ExponentialBristle,
    FixedStep as FixedStep,
    LaneAdaptive as LaneAdaptive,
    Lanes as Lanes,
    SaveAt as SaveAt,
)
from ._system import N_STATES as N_STATES, STATE_NAMES as STATE_NAMES, System as System, vector_field as vector_field
