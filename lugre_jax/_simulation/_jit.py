"""``array_jit``: ``eqx.filter_jit`` for the simulator's entry points, with less Python per call.

The compiled program is the same as ``filter_jit``'s (array leaves traced, every other leaf a
compile-time constant), but a call flattens its argument once and hands ``jax.jit`` a list of
arrays and one hashable description of the rest, instead of partitioning the whole tree into two
rebuilt trees, hashing them and binding a signature (equinox's per-call work). A batch-1 call is
mostly this dispatch (docs/performance.md).

One difference: an ``eqx.error_if`` that fires inside (e.g. a traced inertia check in a
``map_lanes`` function) surfaces as JAX's runtime error carrying the message, not as equinox's
``EquinoxRuntimeError``: ``filter_jit`` gets the latter by blocking on every call, which would
give up asynchronous dispatch. Under a caller's own ``jax.jit`` nothing changes (its boundary is
the caller's).
"""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax


class _ArraySlot:
    """Marks where an array leaf goes in a :func:`split_arrays` description."""

    def __repr__(self):
        return "<array>"


_ARRAY = _ArraySlot()


def split_arrays(tree):
    """``(arrays, spec)``: ``tree``'s array leaves in flattening order, and a hashable ``spec``
    (tree structure and the non-array leaves) from which :func:`join_arrays` rebuilds it."""
    leaves, treedef = jax.tree_util.tree_flatten(tree)
    is_array = list(map(eqx.is_array, leaves))
    if all(is_array):
        return leaves, (treedef, None)
    return ([x for x, a in zip(leaves, is_array) if a],
            (treedef, tuple(_ARRAY if a else x for x, a in zip(leaves, is_array))))


def join_arrays(arrays, spec):
    treedef, marks = spec
    if marks is None:
        return treedef.unflatten(arrays)
    it = iter(arrays)
    return treedef.unflatten([next(it) if m is _ARRAY else m for m in marks])


@jax.tree_util.register_static
@dataclasses.dataclass(frozen=True)
class _Static:
    """A leafless pytree node: carries an output's non-array part out of ``jax.jit``."""

    spec: object


def array_jit(fn):
    """``fn(tree)`` compiled with ``tree``'s array leaves traced and its other leaves static (as
    ``eqx.filter_jit(fn)``); non-array leaves of the output pass through unchanged."""

    def traced(arrays, spec):
        out_arrays, out_spec = split_arrays(fn(join_arrays(arrays, spec)))
        return out_arrays, _Static(out_spec)

    jitted = jax.jit(traced, static_argnums=1)

    def call(tree):
        out_arrays, out_spec = jitted(*split_arrays(tree))
        return join_arrays(out_arrays, out_spec.spec)

    return call
