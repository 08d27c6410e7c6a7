"""lugre_jax: differentiable LuGre friction, batched joint simulation and GA/PSO/GA-PSO identification.

Implements and extends B. Li, Y. Zhang, L. Yuan, X. Xi, "Study on the Low Velocity Stability of a
Prostate Seed Implantation Robot's Rotatory Joint", Electronics 2020, 9, 284.

Units at every interface are the paper's: angles in deg, velocities in deg/s, torques in N*m.

Subpackages: ``friction``, ``plant``, ``control``, ``identify``, ``dynamic``, ``diagnose``, ``emps``,
``sweep``, ``scenario``, ``testing``, ``io``, ``reproduce``; modules ``metrics``, ``xla`` (:func:`configure`).
Nothing process-wide changes on import: call :func:`configure` first (float64, XLA options).
"""

from .xla import configure as configure
from ._params import bounds_of as bounds_of, names_of as names_of, units_of as units_of
from ._results import RESULTS as RESULTS, result_name as result_name
from ._simulation import (
    RESULT_NONFINITE as RESULT_NONFINITE,
    RESULT_OK as RESULT_OK,
    RESULT_SOLVER_FAILED as RESULT_SOLVER_FAILED,
    STATE_NAMES as STATE_NAMES,
    AbstractStepping as AbstractStepping,
    Adaptive as Adaptive,
    ExponentialBristle as ExponentialBristle,
    FixedStep as FixedStep,
    LaneAdaptive as LaneAdaptive,
    Lanes as Lanes,
    Sample as Sample,
    SampleMean as SampleMean,
    SampleValues as SampleValues,
    SaveAt as SaveAt,
    Solution as Solution,
    SteppingCheck as SteppingCheck,
    System as System,
    broadcast_system as broadcast_system,
    check_stepping as check_stepping,
    default_stepping as default_stepping,
    map_lanes as map_lanes,
    simulate as simulate,
    stack_systems as stack_systems,
    trajectory_loss as trajectory_loss,
    vector_field as vector_field,
)
from .control import (
    LuGreCompensated as LuGreCompensated,
    OpenLoop as OpenLoop,
    OpenLoopVoltage as OpenLoopVoltage,
    PositionPID as PositionPID,
    PositionSine as PositionSine,
    VelocityPID as VelocityPID,
    VelocityRamp as VelocityRamp,
    VelocityTable as VelocityTable,
    VelocitySteps as VelocitySteps,
)
from .friction import (
    AbstractFrictionModel as AbstractFrictionModel,
    CoulombViscous as CoulombViscous,
    LuGre as LuGre,
    Segmented as Segmented,
    Stribeck as Stribeck,
)
from .io import Recording as Recording, load_emps as load_emps, load_recording as load_recording
from .plant import (
    PAPER_J as PAPER_J,
    DCMotor as DCMotor,
    IdealTorque as IdealTorque,
    Joint as Joint,
    paper_friction as paper_friction,
    paper_segment as paper_segment,
)
from . import (  # noqa: E402
    diagnose as diagnose,
    dynamic as dynamic,
    emps as emps,
    identify as identify,
    metrics as metrics,
    scenario as scenario,
    sweep as sweep,
    testing as testing,
)

__version__ = "0.1.0"
