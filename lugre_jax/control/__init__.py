"""Controllers (open loop, PID, cascade, LuGre compensation eq. 19-24) and reference signals."""

from ._controllers import (
    AbstractController as AbstractController,
    CtrlIn as CtrlIn,
    CtrlOut as CtrlOut,
    LuGreCompensated as LuGreCompensated,
    OpenLoop as OpenLoop,
    OpenLoopVoltage as OpenLoopVoltage,
    PositionPID as PositionPID,
    VelocityPID as VelocityPID,
)
from ._reference import (
    AbstractReference as AbstractReference,
    PositionSine as PositionSine,
    VelocityRamp as VelocityRamp,
    VelocityTable as VelocityTable,
    VelocitySteps as VelocitySteps,
)
