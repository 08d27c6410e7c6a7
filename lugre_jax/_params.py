"""Parameters that carry their unit and bounds.

Every physical parameter of a model is declared with :func:`param`, which stores the unit and the
identification bounds as field metadata. This is the package's one parameter registry: names, order,
units and bounds are read from the model class (or an instance) with :func:`names_of`,
:func:`units_of`, :func:`bounds_of`, and parameter vectors are converted with :func:`to_vector` /
:func:`from_vector`; nothing else lists them.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import equinox as eqx
import jax.numpy as jnp
import numpy as np


def param(unit: str, lower: float = -np.inf, upper: float = np.inf, *, convert: bool = True,
          **kwargs: Any):
    """A model field with a unit and bounds (``lower <= value <= upper``).

    ``convert=False`` keeps a Python number as given: jitted code then treats it as a constant
    (used for terms that are usually off, such as gravity, so they cost nothing when zero).
    """
    if not lower <= upper:
        raise ValueError(f"param bounds must satisfy lower <= upper, got [{lower}, {upper}]")
    metadata = dict(unit=unit, bounds=(float(lower), float(upper)))
    if convert:
        kwargs["converter"] = jnp.asarray
    return eqx.field(metadata=metadata, **kwargs)


def param_fields(module: eqx.Module | type[eqx.Module]) -> list[dataclasses.Field]:
    """The fields of ``module`` (a model class or instance) declared with :func:`param`, in
    declaration order."""
    return [f for f in dataclasses.fields(module) if "bounds" in f.metadata]


def names_of(module: eqx.Module | type[eqx.Module]) -> tuple[str, ...]:
    """Parameter names of a model class or instance, in declaration (= vector) order."""
    return tuple(f.name for f in param_fields(module))


def units_of(module: eqx.Module | type[eqx.Module]) -> dict[str, str]:
    """Parameter name -> unit, in declaration order."""
    return {f.name: f.metadata["unit"] for f in param_fields(module)}


def bounds_of(module: eqx.Module | type[eqx.Module]) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of the parameters of a model class or instance, as two float64 arrays."""
    fs = param_fields(module)
    lo = np.array([f.metadata["bounds"][0] for f in fs], dtype=np.float64)
    hi = np.array([f.metadata["bounds"][1] for f in fs], dtype=np.float64)
    return lo, hi


def to_vector(module: eqx.Module):
    """The module's parameters stacked on the last axis (works for batched modules too)."""
    vals = [jnp.asarray(getattr(module, n)) for n in names_of(module)]
    shape = jnp.broadcast_shapes(*(v.shape for v in vals))
    return jnp.stack([jnp.broadcast_to(v, shape) for v in vals], axis=-1)


def from_vector(cls, x, **static: Any):
    """Build ``cls`` from a vector (``..., n_params``) ordered as ``names_of(cls)``."""
    names = names_of(cls)
    if x.shape[-1] != len(names):
        raise ValueError(
            f"{cls.__name__} has {len(names)} parameters {list(names)}; got a vector of length {x.shape[-1]}"
        )
    return cls(**{n: x[..., i] for i, n in enumerate(names)}, **static)
