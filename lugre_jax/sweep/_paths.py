"""Dotted paths into a :class:`lugre_jax.System` (``friction.Fs``, ``friction.segments[1].sigma0``,
``controller.ki``, ``reference.levels[0]``): checked against a system once, then used to write a
column of sample values into a batched copy of it without a Python object per point."""

from __future__ import annotations

import dataclasses
import re

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._simulation import broadcast_system

_TOKEN = re.compile(r"([A-Za-z_]\w*)((?:\[\d+\])*)")


@dataclasses.dataclass(frozen=True)
class Path:
    """A checked path: ``steps`` of attribute names (str) and tuple indices (int) to a leaf, and
    ``element``, the index into that leaf when it is a 1-D array (None for a scalar leaf)."""

    text: str
    steps: tuple
    element: int | None
    bounds: tuple[float, float] | None  # the field's declared range (lugre_jax._params), if any
    unit: str | None

    def get(self, tree):
        for s in self.steps:
            tree = getattr(tree, s) if isinstance(s, str) else tree[s]
        return tree


def parse_path(text: str, system, where: str) -> Path:
    """Resolve ``text`` on ``system``; a one-line ``ValueError`` (prefixed ``where``) if it does not
    name one number of it."""
    parts = text.split(".")
    steps: list = []
    node, here = system, "scenario"
    element = None
    field_meta = None
    for pi, part in enumerate(parts):
        m = _TOKEN.fullmatch(part)
        if m is None:
            raise ValueError(f"{where} '{text}': cannot parse '{part}' (expected name or name[k])")
        name, idx = m.group(1), [int(k) for k in re.findall(r"\[(\d+)\]", m.group(2))]
        fields = {f.name: f for f in dataclasses.fields(node)} if dataclasses.is_dataclass(node) else {}
        if name not in fields or fields[name].metadata.get("static", False):
            avail = ", ".join(n for n, f in fields.items() if not f.metadata.get("static", False)) or "none"
            raise ValueError(f"{where} '{text}': {here} ({type(node).__name__}) has no field '{name}' (fields: {avail})")
        field_meta = fields[name].metadata
        node, here = getattr(node, name), f"{here}.{name}" if here != "scenario" else name
        steps.append(name)
        for k in idx:
            if isinstance(node, (tuple, list)):
                if k >= len(node):
                    raise ValueError(f"{where} '{text}': {here} has {len(node)} entries, no [{k}]")
                node, here = node[k], f"{here}[{k}]"
                steps.append(k)
                field_meta = None
            elif eqx.is_array(node) and np.ndim(node) == 1 and pi == len(parts) - 1 and element is None:
                if k >= node.shape[0]:
                    raise ValueError(f"{where} '{text}': {here} has {node.shape[0]} entries, no [{k}]")
                element = k
            else:
                raise ValueError(f"{where} '{text}': {here} cannot be indexed with [{k}]")
    is_number = isinstance(node, (int, float)) and not isinstance(node, bool)
    if element is None and not (is_number or (eqx.is_array(node) and np.ndim(node) == 0)):
        shape = f"an array of shape {np.shape(node)}" if eqx.is_array(node) else type(node).__name__
        hint = "; index it, e.g. [0]" if eqx.is_array(node) and np.ndim(node) == 1 else ""
        raise ValueError(f"{where} '{text}': {here} is {shape}, not a number{hint}")
    bounds = field_meta.get("bounds") if field_meta else None
    return Path(text, tuple(steps), element, bounds, field_meta.get("unit") if field_meta else None)


def batch_system(system, paths, X):
    """``system`` repeated for each row of ``X`` (n, D) with column ``i`` written at ``paths[i]``
    (``SweepSpec.paths``): every array leaf gets a leading axis of n (as batched ``simulate`` needs).
    One array per leaf, not a Python object per point."""
    n = X.shape[0]
    X = jnp.asarray(X)
    out = broadcast_system(system, n)
    for i, p in enumerate(paths):
        leaf = p.get(out)
        if p.element is None:
            new = X[:, i]
        else:
            new = leaf.at[:, p.element].set(X[:, i])
        out = eqx.tree_at(p.get, out, new, is_leaf=lambda x: x is None)
    return out
