import os

os.environ.setdefault("MPLBACKEND", "Agg")

import lugre_jax  # noqa: E402

# The library changes nothing on import; the test session opts in, as a user script would.
lugre_jax.configure()
