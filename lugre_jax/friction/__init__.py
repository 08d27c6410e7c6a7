"""Friction models (paper section 4.1, eq. 9-11 and Table 1).

Each model declares its parameters once, with unit and identification bounds (``param``); the
registry functions read them from a model class or instance: ``names_of`` (vector order),
``units_of``, ``bounds_of``, ``to_vector`` and ``from_vector``.
"""

from .._params import (
    bounds_of as bounds_of,
    from_vector as from_vector,
    names_of as names_of,
    param as param,
    to_vector as to_vector,
    units_of as units_of,
)
from ._models import (
    AbstractFrictionModel as AbstractFrictionModel,
    CoulombViscous as CoulombViscous,
    LuGre as LuGre,
    Segmented as Segmented,
    Stribeck as Stribeck,
)
