"""Opt-in process configuration: float64 and the XLA:CPU options this library is fast with.

Importing ``lugre_jax`` changes nothing process-wide. Call :func:`configure` once, before the first
JAX computation, in a script, a notebook or a test session (the CLI, the benchmark, the experiments
and the test suite do)::

    import lugre_jax as lj
    lj.configure()              # float64 + one-kernel time loops + 512-bit vectors
    lj.configure(host_devices=2)  # also split batches over two host devices (one per core)

Why each option exists (effects measured in docs/performance.md):

* ``x64``: friction at 0.001 deg/s is a small difference of large numbers (bristle deflections of
  1e-4 deg against breakaway torques of several N*m); float32 cannot resolve it, and the simulator
  refuses to run without it.
* ``one_kernel_loops``: XLA:CPU dispatches a while loop op by op unless the loop touches fewer than
  ``xla_cpu_small_while_loop_byte_threshold`` bytes; a time step of our solvers is 20-60 small ops,
  so dispatch, not arithmetic, would set its cost. Raising the threshold compiles each time loop
  into one kernel. The cost: such a loop runs on one core.
* ``vector_width``: XLA:CPU asks LLVM for 256-bit vectors by default; on AVX-512 CPUs 512 bits let a
  vectorised step use the whole register.
* ``host_devices``: XLA:CPU exposes one device by default; the batched simulator shards lanes over
  as many as exist.

XLA reads ``XLA_FLAGS`` once, when its backend starts, so the XLA options take effect only if no
JAX computation ran before; :func:`configure` says so (``RuntimeError``) rather than silently
doing nothing. Values the user already set in ``XLA_FLAGS`` are kept.
"""

from __future__ import annotations

import os

import jax

SMALL_LOOP_OPTION = "xla_cpu_small_while_loop_byte_threshold"
SMALL_LOOP_BYTES = 100_000_000
VECTOR_WIDTH_FLAG = "--xla_cpu_prefer_vector_width"
HOST_DEVICES_FLAG = "--xla_force_host_platform_device_count"

X64_MESSAGE = ("lugre_jax needs float64: call lugre_jax.configure() (or "
               "jax.config.update('jax_enable_x64', True)) before the first JAX computation")


def with_backend_option(flags: str, key: str, value) -> str:
    """``flags`` (an ``XLA_FLAGS`` string) with ``key=value`` among its backend extra options.

    Merged into an existing ``--xla_backend_extra_options=...`` (comma-separated), not a second copy
    of the flag (which would replace the first); ``flags`` unchanged when it already sets ``key``.
    """
    if key in flags:
        return flags
    parts = flags.split()
    for i, part in enumerate(parts):
        if part.startswith("--xla_backend_extra_options="):
            parts[i] = f"{part},{key}={value}"
            break
    else:
        parts.append(f"--xla_backend_extra_options={key}={value}")
    return " ".join(parts)


def with_flag(flags: str, name: str, value) -> str:
    """``flags`` with ``name=value`` appended, unchanged when it already sets ``name``."""
    if any(part.split("=", 1)[0] == name for part in flags.split()):
        return flags
    return f"{flags} {name}={value}".strip()


def backend_started() -> bool:
    """Whether XLA's backend has started (after which ``XLA_FLAGS`` is no longer read)."""
    from jax._src import xla_bridge

    return bool(xla_bridge._backends)


def xla_flags(flags: str = "", *, one_kernel_loops: bool = True, vector_width: int | None = 512,
              host_devices: int | None = None) -> str:
    """``flags`` with this library's XLA options added (user values kept). Pure: sets nothing."""
    if one_kernel_loops:
        flags = with_backend_option(flags, SMALL_LOOP_OPTION, SMALL_LOOP_BYTES)
    if vector_width:
        flags = with_flag(flags, VECTOR_WIDTH_FLAG, int(vector_width))
    if host_devices:
        flags = with_flag(flags, HOST_DEVICES_FLAG, int(host_devices))
    return flags


def configure(*, x64: bool = True, one_kernel_loops: bool = True, vector_width: int | None = 512,
              host_devices: int | None = None) -> None:
    """Enable float64 and set this library's XLA:CPU options for this process (opt-in).

    ``host_devices``: number of XLA host devices (``None`` keeps XLA's default of one; the CLI passes
    the number of cores). Raises ``RuntimeError`` when XLA options are requested after the backend
    started (they would be ignored); call it first thing, or pass only ``x64``.
    """
    if x64:
        jax.config.update("jax_enable_x64", True)
    new = xla_flags(os.environ.get("XLA_FLAGS", ""), one_kernel_loops=one_kernel_loops,
                    vector_width=vector_width, host_devices=host_devices)
    if new != os.environ.get("XLA_FLAGS", ""):
        if backend_started():
            raise RuntimeError(
                "lugre_jax.configure(): JAX has already run a computation, so XLA options can no "
                "longer be set; call configure() before any JAX work, or configure("
                "one_kernel_loops=False, vector_width=None) for float64 only")
        os.environ["XLA_FLAGS"] = new


def require_x64() -> None:
    """Raise a ``RuntimeError`` saying what to call when float64 is off."""
    if not jax.config.jax_enable_x64:
        raise RuntimeError(X64_MESSAGE)
