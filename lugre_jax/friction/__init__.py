"""Friction models (paper section 4.1, eq. 9-11 and Table 1).

Each model declares its parameters once, with unit, identification bounds and physical domain
(``param``); the registry functions read them from a model class or instance: ``names_of`` (vector
order), ``units_of``, ``bounds_of``, ``to_vector`` and ``from_vector``. A model built from concrete
values checks them (sign; LuGre's passivity, see :class:`LuGre`).

The formulas every friction computation shares are written once here: the Stribeck curve
(:func:`stribeck_g`, :func:`stribeck_curve`), LuGre's bristle force and rate (:func:`bristle_force`)
and the exact bristle update over a sample (:func:`bristle_coefficients`, :func:`bristle_step`, both
from :func:`exp_phi1`, which the simulator's exponential stepping uses too).
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
    NonPassiveWarning as NonPassiveWarning,
    Segmented as Segmented,
    Stribeck as Stribeck,
    bristle_coefficients as bristle_coefficients,
    bristle_force as bristle_force,
    bristle_step as bristle_step,
    exp_phi1 as exp_phi1,
    stribeck_curve as stribeck_curve,
    stribeck_g as stribeck_g,
)
