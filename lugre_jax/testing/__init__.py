"""Testing utilities for lugre_jax (like ``numpy.testing``): an independent closed-loop recording
generator built on scipy's ``solve_ivp``, for checking the diagnose tool on recordings that the
project's own simulator did not make. See :func:`generate`."""

from ._generator import (
    EFFECTS as EFFECTS,
    Asymmetry as Asymmetry,
    Backlash as Backlash,
    Compliance as Compliance,
    Excitation as Excitation,
    GeneratedRecording as GeneratedRecording,
    Gravity as Gravity,
    LoadDependent as LoadDependent,
    Multisine as Multisine,
    Plant as Plant,
    PositionRipple as PositionRipple,
    PositionSine as PositionSine,
    Sensors as Sensors,
    SineSweep as SineSweep,
    Staircase as Staircase,
    StribeckShape as StribeckShape,
    ThermalDrift as ThermalDrift,
    VelocityPI as VelocityPI,
    generate as generate,
)
