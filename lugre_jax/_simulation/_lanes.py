"""Batches: lanes in chunks (``lax.map`` over ``vmap``), split over host devices, compiled once."""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from .._types import PyTree
from ._jit import join_arrays, split_arrays

DEFAULT_CHUNK = 200  # simulate's forward solves on a CPU: a step's working set stays in cache
_MEMORY_SHARE = 0.5  # of an accelerator's free memory, for one call's lanes
_MAP_LANES_CHUNK = 64  # map_lanes' reverse passes store each lane's state per step: smaller chunks
_VECTOR_LANES = 8  # float64 lanes of a 512-bit vector (lugre_jax.configure's vector width)


@dataclasses.dataclass(frozen=True)
class DeviceInfo:
    """What the lane layout needs to know of a device: its platform (``"cpu"``, ``"gpu"``,
    ``"tpu"``) and its free memory in bytes (``None`` when the backend does not say)."""

    platform: str
    free_bytes: int | None = None
    kind: str = ""


_CPU_INFO: dict = {}


def device_info(device=None) -> DeviceInfo:
    """:class:`DeviceInfo` of ``device`` (default: the first local device)."""
    device = jax.local_devices()[0] if device is None else device
    if device.platform == "cpu":  # no memory statistics to read: one description per device
        info = _CPU_INFO.get(device.id)
        if info is None:
            info = _CPU_INFO[device.id] = DeviceInfo("cpu", None, getattr(device, "device_kind", "cpu"))
        return info
    free = None
    try:
        stats = device.memory_stats()
    except Exception:  # backends without memory statistics (XLA:CPU) raise or return None
        stats = None
    if stats and "bytes_limit" in stats:
        free = int(stats["bytes_limit"]) - int(stats.get("bytes_in_use", 0))
    return DeviceInfo(device.platform, free, getattr(device, "device_kind", ""))


def default_chunk(info: DeviceInfo, lanes: int, lane_bytes: int, cpu_chunk: int = DEFAULT_CHUNK) -> int:
    """Lanes per chunk when :class:`Lanes` gives none: on a CPU ``cpu_chunk`` (a step's working set
    stays in cache); on an accelerator as many lanes as half its free memory holds at
    ``lane_bytes`` per lane (all ``lanes`` in one chunk when they fit), so its cores are filled."""
    if info.platform == "cpu" or info.free_bytes is None:
        return cpu_chunk
    return max(1, min(lanes, int(_MEMORY_SHARE * info.free_bytes) // max(1, int(lane_bytes))))


def split_lanes(tree, what: str, fix: str):
    """``(arrays, spec, b)``: ``tree`` split as :func:`split_arrays` does, and the leading (lane)
    axis ``b`` shared by its array leaves (``ValueError`` naming ``what`` and ``fix`` if they
    disagree or one is a scalar). One flatten serves the check and the call."""
    arrays, spec = split_arrays(tree)
    shapes = [x.shape for x in arrays]
    sizes = {sh[0] for sh in shapes if sh}
    n_scalars = sum(not sh for sh in shapes)
    if len(sizes) != 1 or n_scalars:
        raise ValueError(
            f"{what} needs one leading batch axis on every array leaf; {fix} "
            f"(found leading sizes {sorted(sizes)} and {n_scalars} unbatched scalars)"
        )
    return arrays, spec, sizes.pop()


_SYSTEM_LANES = ("a batched System", "use lugre_jax.broadcast_system(system, n) or "
                 "lugre_jax.stack_systems([...]) to build one")


def batch_size_of(system) -> int:
    """Leading axis shared by every array leaf of a batched system (raises if they disagree).

    Python-number leaves (e.g. ``delta = 2.0``) are compile-time constants shared by all lanes.
    """
    return split_lanes(system, *_SYSTEM_LANES)[2]


def broadcast_system(system, n: int):
    """Repeat an unbatched system ``n`` times along a new leading axis (Python numbers stay shared)."""
    return jax.tree.map(lambda x: jnp.broadcast_to(x, (n,) + x.shape) if eqx.is_array(x) else x, system)


def stack_systems(systems: list):
    """Stack systems of identical structure into one batched system (Python numbers must agree)."""
    def stack(*xs):
        if eqx.is_array(xs[0]):
            return jnp.stack(xs)
        if any(x != xs[0] for x in xs):
            raise ValueError("stack_systems: Python-number fields differ between systems; pass arrays")
        return xs[0]
    return jax.tree.map(stack, *systems)


def chunked_lanes(key, one_lane, lanes, chunk_size, shard: bool, cpu_chunk: int = DEFAULT_CHUNK,
                  lane_multiple: int = 1, batched_fn: bool = False, lane_bytes: int = 0,
                  device: DeviceInfo | None = None):
    """``jax.vmap(one_lane)(tree)`` over the ``b`` lanes (leading axis) of ``tree``'s arrays, in
    chunks, split across host devices when ``shard``; compiled once per ``key`` (hashable).
    ``lanes`` is ``split_lanes(tree, ...)``. A default chunk of more than ``lane_multiple`` lanes
    is rounded up to a multiple of it; the default chunk is :func:`default_chunk` for ``device``
    (default: the first local device's :func:`device_info`) at ``lane_bytes`` per lane. With ``batched_fn``, ``one_lane`` takes a whole chunk (every
    array leaf with a leading lane axis) and is not vmapped."""
    arrays, spec, b = lanes
    devices = jax.local_devices()
    ndev = max(1, min(len(devices) if shard else 1, b))
    per_dev = -(-b // ndev)
    if chunk_size is None:
        chunk_default = default_chunk(device_info() if device is None else device, per_dev, lane_bytes, cpu_chunk)
        # Balanced so that padding stays below one lane per chunk, or below ``lane_multiple``
        # lanes per chunk when chunks are rounded up to whole vectors.
        n_chunks = -(-per_dev // chunk_default)
        chunk = -(-per_dev // n_chunks)
        if chunk > lane_multiple:
            chunk = -(-chunk // lane_multiple) * lane_multiple
    else:
        chunk = max(1, min(int(chunk_size), per_dev))
    per_dev = -(-per_dev // chunk) * chunk
    total = per_dev * ndev
    if total != b:  # pad with copies of lane 0, dropped afterwards
        arrays = [jnp.concatenate([x, jnp.repeat(x[:1], total - b, 0)]) for x in arrays]
    fn = _compiled(ndev, chunk, key, one_lane, batched_fn)
    if ndev > 1:
        mesh = Mesh(np.array(devices[:ndev]), ("lanes",))
        arrays = jax.device_put(arrays, NamedSharding(mesh, PartitionSpec("lanes")))
    out = fn(arrays, spec)
    # drop the padding lanes; without padding no slicing (one dispatch per output leaf per call)
    return out if total == b else jax.tree.map(lambda x: x[:b], out)


_CACHE: dict = {}


def _compiled(ndev: int, chunk: int, key, one_lane, batched_fn: bool = False):
    """One jitted function per (devices, chunk, key): repeated calls reuse the compilation."""
    key = (ndev, chunk, key, batched_fn)
    fn = _CACHE.get(key)  # one hash of the key (it holds equinox Modules, hashed field by field)
    if fn is not None:
        return fn

    def run_chunks(tree):
        # lax.map over chunks keeps peak memory at one chunk's working set.
        dyn, static = eqx.partition(tree, eqx.is_array)
        n_lanes = jax.tree.leaves(dyn)[0].shape[0]
        dyn = jax.tree.map(lambda x: x.reshape((n_lanes // chunk, chunk) + x.shape[1:]), dyn)
        if batched_fn:
            per_chunk = lambda d: one_lane(eqx.combine(d, static))  # noqa: E731
        else:
            per_chunk = jax.vmap(lambda d: one_lane(eqx.combine(d, static)))
        if n_lanes > chunk:
            # Under reverse mode a lax.map stores every iteration's residuals before its first
            # backward step: all chunks' stored states at once, out of cache. Each chunk is
            # recomputed instead, just before its own backward sweep (one more forward sweep; a
            # forward solve is unaffected). map_lanes differentiates chunk by chunk and needs neither.
            per_chunk = jax.checkpoint(per_chunk)
        out = jax.lax.map(per_chunk, dyn)
        return jax.tree.map(lambda x: x.reshape((n_lanes,) + x.shape[2:]), out)

    def fn(arrays, spec):
        # The arrays are traced, ``spec`` (tree structure and Python-number leaves) is static, as
        # with eqx.filter_jit; lax.map's outputs are all arrays, so they need no filtering.
        run = lambda a: run_chunks(join_arrays(a, spec))  # noqa: E731
        if ndev > 1:
            mesh = Mesh(np.array(jax.local_devices()[:ndev]), ("lanes",))
            run = jax.shard_map(run, mesh=mesh, in_specs=PartitionSpec("lanes"),
                                out_specs=PartitionSpec("lanes"), check_vma=False)
        return run(arrays)

    fn = _CACHE[key] = jax.jit(fn, static_argnums=1)
    if len(_CACHE) > 64:  # bounded: each entry holds a compiled executable
        _CACHE.pop(next(iter(_CACHE)))
    return fn


def map_lanes(fn, xs: PyTree, *, chunk_size: int | None = None, shard: bool | None = None) -> PyTree:
    """``jax.vmap(fn)(xs)``, computed the way batched :func:`simulate` computes its lanes.

    ``xs`` is a pytree whose array leaves share a leading lane axis (e.g. parameter sets (n, 6), or a
    batched :class:`System`); ``fn`` maps one lane to a pytree. Lanes go ``chunk_size`` at a time
    (default ~64, balanced, a multiple of 8: a reverse pass stores each lane's state at every step,
    and larger chunks leave the cache) and, with ``shard=True`` or by default when several host
    devices exist and there are at least two default chunks' worth of lanes, split across devices.

    The use it is for: per-lane derivatives of per-lane losses, e.g. a swarm's gradients,
    ``map_lanes(jax.value_and_grad(loss), P)`` with ``loss(p)`` simulating one lane (ideally with
    ``SaveAt(mean=...)``). Each chunk is differentiated on its own, so a reverse pass's stored
    states stay in cache; ``jax.grad`` of a sum over one batched ``simulate`` call gives the same
    numbers but recomputes each chunk's forward solve first (docs/performance.md).

    ``fn`` is part of the compilation's key, as with ``jax.jit``: pass the same function object to
    reuse the compiled program (a new lambda per call compiles anew).
    """
    if not callable(fn):
        raise ValueError(f"map_lanes needs a function of one lane, got {type(fn).__name__}")
    lanes = split_lanes(xs, "map_lanes", "give every array leaf of xs the same leading (lane) axis")
    if shard is None:
        shard = len(jax.local_devices()) > 1 and lanes[2] >= 2 * _MAP_LANES_CHUNK
    return chunked_lanes(("map_lanes", fn), fn, lanes, chunk_size, shard, _MAP_LANES_CHUNK, _VECTOR_LANES)
