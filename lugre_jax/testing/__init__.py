"""Testing utilities for lugre_jax (like ``numpy.testing``): an independent closed-loop recording
generator built on scipy's ``solve_ivp``, for checking the diagnose tool on recordings that the
project's own simulator did not make: a velocity PI or a position PID, the diagnose candidates'
effects (:data:`EFFECTS`) and effects outside them (:data:`OUTSIDE_EFFECTS`). See :func:`generate`.

Class names carry their role (``...Effect``, ``...Controller``, ``PositionSineExcitation``): none
repeats a class of :mod:`lugre_jax.diagnose` or :mod:`lugre_jax.control`, which model the same
physics or loop in the project's own simulator."""

from ._generator import (
    EFFECTS as EFFECTS,
    OUTSIDE_EFFECTS as OUTSIDE_EFFECTS,
    ActuatorLagEffect as ActuatorLagEffect,
    AsymmetryEffect as AsymmetryEffect,
    BacklashEffect as BacklashEffect,
    ComplianceEffect as ComplianceEffect,
    Excitation as Excitation,
    GeneratedRecording as GeneratedRecording,
    GravityEffect as GravityEffect,
    LoadDependentEffect as LoadDependentEffect,
    Multisine as Multisine,
    Plant as Plant,
    PointToPoint as PointToPoint,
    PositionPIDController as PositionPIDController,
    PositionRippleEffect as PositionRippleEffect,
    PositionSineExcitation as PositionSineExcitation,
    QuadraticDragEffect as QuadraticDragEffect,
    Sensors as Sensors,
    SineSweep as SineSweep,
    Staircase as Staircase,
    StribeckShapeEffect as StribeckShapeEffect,
    ThermalDriftEffect as ThermalDriftEffect,
    TimeDisturbanceEffect as TimeDisturbanceEffect,
    TorqueDependentFrictionEffect as TorqueDependentFrictionEffect,
    VelocityPIController as VelocityPIController,
    generate as generate,
)
from ._reference import velocity_staircase as velocity_staircase
