"""Friction models (paper section 4.1, eq. 9-11 and Table 1)."""

from ._models import (
    AbstractFrictionModel as AbstractFrictionModel,
    CoulombViscous as CoulombViscous,
    LuGre as LuGre,
    Segmented as Segmented,
    Stribeck as Stribeck,
)
