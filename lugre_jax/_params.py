"""Parameters that carry their unit and bounds.

Every physical parameter of a model is declared with :func:`param`, which stores the unit, the
identification bounds (the search box of section 4.2.2) and the physical domain (the values the
model is defined for, e.g. ``sigma1 >= 0``) as field metadata. This is the package's one parameter
registry: names, order, units and bounds are read from the model class (or an instance) with
:func:`names_of`, :func:`units_of`, :func:`bounds_of`, and parameter vectors are converted with
:func:`to_vector` / :func:`from_vector`; nothing else lists them. :func:`check_domains` checks a
built model's concrete values against the domains.
"""

from __future__ import annotations

import dataclasses
from typing import Any, NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np


class Domain(NamedTuple):
    """The values a parameter is physically defined for: ``lower <= x <= upper`` (``lower < x``
    with ``lower_open``). Unlike the identification bounds, which are a search box in the paper's
    units, a domain holds in any unit system (a damping is never negative)."""

    lower: float = -np.inf
    upper: float = np.inf
    lower_open: bool = False

    def contains(self, x: np.ndarray) -> np.ndarray:
        above = x > self.lower if self.lower_open else x >= self.lower
        return above & (x <= self.upper)

    def describe(self) -> str:
        if np.isinf(self.upper):
            return f"{'>' if self.lower_open else '>='} {self.lower:g}"
        return f"in {'(' if self.lower_open else '['}{self.lower:g}, {self.upper:g}]"


ANY = Domain()
NONNEGATIVE = Domain(0.0)
POSITIVE = Domain(0.0, lower_open=True)


def param(unit: str, lower: float = -np.inf, upper: float = np.inf, *, domain: Domain = ANY,
          convert: bool = True, **kwargs: Any):
    """A model field with a unit, identification bounds (``lower <= value <= upper``) and a physical
    ``domain``, checked on concrete values when the model is built (:func:`check_domains`).

    ``convert=False`` keeps a Python number as given: jitted code then treats it as a constant
    (used for terms that are usually off, such as gravity, so they cost nothing when zero).
    """
    if not lower <= upper:
        raise ValueError(f"param bounds must satisfy lower <= upper, got [{lower}, {upper}]")
    if not (domain.lower <= lower and upper <= domain.upper):
        raise ValueError(f"param bounds [{lower}, {upper}] must lie in its domain ({domain.describe()})")
    metadata = dict(unit=unit, bounds=(float(lower), float(upper)), domain=domain)
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


def concrete(value: Any) -> np.ndarray | None:
    """``value`` as a float64 numpy array if it is a concrete number or array, ``None`` if it is traced
    (under ``jit``/``vmap``/``grad``) or not numeric: checks at construction never touch a tracer."""
    if isinstance(value, jax.core.Tracer):
        return None
    if not isinstance(value, (int, float, np.ndarray, np.generic, jax.Array)) or isinstance(value, bool):
        return None
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        return None


def describe_value(name: str, arr: np.ndarray, bad: np.ndarray) -> str:
    """``name=value`` of the first element flagged in ``bad`` (with its index for a batch)."""
    if arr.ndim == 0:
        return f"{name}={float(arr)!r}"
    idx = tuple(int(i) for i in np.argwhere(bad)[0])
    return f"{name}[{', '.join(map(str, idx))}]={float(arr[idx])!r} (batch of shape {arr.shape})"


def check_domains(module: eqx.Module) -> None:
    """Raise ``ValueError`` naming the first concrete parameter of ``module`` outside its domain,
    as ``LuGre(sigma1=-5.0): sigma1 must be >= 0 [N*m*s/deg]``. Batched values are checked element
    by element; traced values are skipped; NaN passes (a failed estimate carries its own result
    code and must stay representable)."""
    for f in param_fields(module):
        domain = f.metadata.get("domain", ANY)
        if domain == ANY:
            continue
        arr = concrete(getattr(module, f.name, None))
        if arr is None:
            continue
        bad = ~(domain.contains(arr) | np.isnan(arr))
        if bad.any():
            raise ValueError(f"{type(module).__name__}({describe_value(f.name, arr, bad)}): {f.name} must be "
                             f"{domain.describe()} [{f.metadata['unit']}]")
