"""Project-wide JAX configuration: float64 everywhere.

Friction at 0.001 deg/s is a small difference of large numbers (bristle deflections of 1e-4 deg,
breakaway torques of several N*m), so float32 is not an option.
"""

import jax

jax.config.update("jax_enable_x64", True)
