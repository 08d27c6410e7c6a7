"""Testing utilities for lugre_jax (like ``numpy.testing``): an independent closed-loop recording
generator built on scipy's ``solve_ivp``, for checking the diagnose tool on recordings that the
project's own simulator did not make: a velocity PI or a position PID, the diagnose candidates'
effects (:data:`EFFECTS`) and effects outside them (:data:`OUTSIDE_EFFECTS`). See :func:`generate`."""

from ._generator import (
    EFFECTS as EFFECTS,
    OUTSIDE_EFFECTS as OUTSIDE_EFFECTS,
    ActuatorLag as ActuatorLag,
    Asymmetry as Asymmetry,
    Backlash as Backlash,
    Compliance as Compliance,
    Excitation as Excitation,
    GeneratedRecording as GeneratedRecording,
    Gravity as Gravity,
    LoadDependent as LoadDependent,
    Multisine as Multisine,
    Plant as Plant,
    PointToPoint as PointToPoint,
    PositionPID as PositionPID,
    PositionRipple as PositionRipple,
    PositionSine as PositionSine,
    QuadraticDrag as QuadraticDrag,
    Sensors as Sensors,
    SineSweep as SineSweep,
    Staircase as Staircase,
    StribeckShape as StribeckShape,
    ThermalDrift as ThermalDrift,
    TimeDisturbance as TimeDisturbance,
    TorqueDependentFriction as TorqueDependentFriction,
    VelocityPI as VelocityPI,
    generate as generate,
)
