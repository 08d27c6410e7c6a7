"""Joint and DC-motor models (paper section 3) and the paper's parameter sets (Tables 1-2, eq. 18)."""

from ._paper import (
    PAPER_J as PAPER_J,
    SEGMENT_EDGES as SEGMENT_EDGES,
    TABLE1 as TABLE1,
    TABLE2 as TABLE2,
    paper_friction as paper_friction,
    paper_inertia_per_segment as paper_inertia_per_segment,
    paper_segment as paper_segment,
    paper_table1_array as paper_table1_array,
)
from ._plant import (
    AbstractActuator as AbstractActuator,
    DCMotor as DCMotor,
    IdealTorque as IdealTorque,
    Joint as Joint,
    MOTOR_ASSUMPTIONS as MOTOR_ASSUMPTIONS,
)
