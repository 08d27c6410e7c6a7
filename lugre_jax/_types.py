"""Shared jaxtyping aliases."""

from jaxtyping import Array, ArrayLike, Bool, Float, Int, PRNGKeyArray, PyTree

Scalar = Float[Array, ""]
ScalarLike = Float[ArrayLike, ""]
Population = Float[Array, "pop dim"]
Params = Float[Array, " dim"]
Fitness = Float[Array, " pop"]

__all__ = [
    "Array",
    "ArrayLike",
    "Bool",
    "Float",
    "Int",
    "PRNGKeyArray",
    "PyTree",
    "Scalar",
    "ScalarLike",
    "Population",
    "Params",
    "Fitness",
]
