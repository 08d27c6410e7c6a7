"""Entry point of the ``lugre-jax`` command: process settings that must precede the first import of
equinox, then :func:`lugre_jax.cli.main`.

``EQX_ON_ERROR=nan``: equinox's runtime checks (inside diffrax's and optimistix's solvers) then
return NaN instead of raising through a host callback. The simulator reports such a lane as
failed (a result code), and a compiled program without host callbacks can be kept in JAX's
persistent compilation cache, so a second run does not compile again. A value the user set is kept.
"""

import os
import sys


def main() -> int:
    os.environ.setdefault("EQX_ON_ERROR", "nan")
    try:
        from lugre_jax.cli import main as cli_main
    except KeyboardInterrupt:  # Ctrl-C while JAX loads, before cli.main handles signals
        print("lugre-jax: interrupted (Ctrl-C)", file=sys.stderr)
        return 130
    return cli_main()


if __name__ == "__main__":
    sys.exit(main())
