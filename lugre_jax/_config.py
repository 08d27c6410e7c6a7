"""Project-wide JAX configuration: float64 everywhere, XLA:CPU compiling our time loops whole, and
512-bit vectors where the CPU has them.

Friction at 0.001 deg/s is a small difference of large numbers (bristle deflections of 1e-4 deg,
breakaway torques of several N*m), so float32 is not an option.

XLA:CPU runs a while loop as a sequence of separately dispatched kernels unless the loop touches
less than ``xla_cpu_small_while_loop_byte_threshold`` bytes (1 kB by default); below it, the whole
loop is compiled into one kernel. A time step of our solvers is 20-60 small kernels, so dispatch,
not arithmetic, set its cost. Raising the threshold to 100 MB, measured on the benchmark joint
(Bosh3, 20 ms): one unbatched solve 1.25 -> 0.16 ms; 10,000 lanes on 2 devices 56,000 -> 69,000
simulations/s; reverse-mode gradient of 200 lanes 11.3 -> 7.5 ms; the test suite passes unchanged.
(1e5 bytes was slower for batches: 25,900 against 30,000 simulations/s for 1,000 lanes.) The cost:
a loop compiled whole runs on one core, so a loop whose ops XLA spread over both cores can slow
down; measured, the paper's PSO with threefry random numbers (100 seeds) 0.092 -> 0.150 s, with
the hash generator unchanged (README, "Speed" and "Notes").

XLA reads ``XLA_FLAGS`` when its backend starts, so this takes effect only if nothing has run a
JAX computation before ``import lugre_jax`` (importing JAX does not start it). A value the user has
already set for this option is kept; any other ``--xla_backend_extra_options`` are kept too.

XLA:CPU asks LLVM for 256-bit vectors by default (``--xla_cpu_prefer_vector_width=256``), a guard
against the clock throttling of early AVX-512 CPUs, so on a CPU with AVX-512 a vectorised time
step uses half its register width. We ask for 512. Measured on this project's 2-core AMD EPYC
(AVX-512), alternating runs: the benchmark joint (Bosh3, 20 ms) at 1,000 lanes on one device
41,000 -> 60,000 simulations/s, 10,000 lanes on 2 devices 68,000 -> 93,000-106,000; a reverse-mode
gradient of 1,000 lanes 38 -> 28 ms; the PSO's 100 seeds 0.152 -> 0.140 s (threefry) and
0.088 -> 0.075 s (hash); one unbatched solve unchanged. A CPU without AVX-512 has not been measured:
there LLVM has to split each 512-bit vector op into 256-bit halves. With XLA limited to AVX2 here
(``xla_cpu_max_isa=AVX2``) the wide setting was still faster (one core, 1,000 lanes: 52,000
against 34,000 simulations/s), but we did not check that the option really withholds AVX-512 from
LLVM. A value the user has set is kept.
"""

import os

import jax

jax.config.update("jax_enable_x64", True)

SMALL_LOOP_OPTION = "xla_cpu_small_while_loop_byte_threshold"
SMALL_LOOP_BYTES = 100_000_000
VECTOR_WIDTH_FLAG = "--xla_cpu_prefer_vector_width"
VECTOR_WIDTH_BITS = 512


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


os.environ["XLA_FLAGS"] = with_flag(
    with_backend_option(os.environ.get("XLA_FLAGS", ""), SMALL_LOOP_OPTION, SMALL_LOOP_BYTES),
    VECTOR_WIDTH_FLAG, VECTOR_WIDTH_BITS,
)
