"""Entry point of the ``lugre-jax`` command.

1. The command line is parsed and checked before JAX and the package are imported (they take seconds
   to load): ``--help``, an argument error or an unusable output path answers at once. The parser
   modules (``lugre_jax/_cli/_args.py`` and each subcommand's ``add_parser`` and ``check``) import
   only the standard library at module level, so they are loaded here on their own, as a private
   package ``_lugre_jax_cli_parse`` over the folder ``lugre_jax/_cli``, without running
   ``lugre_jax/__init__.py``.
2. Process settings that must precede the first import of equinox: ``EQX_ON_ERROR=nan``: equinox's
   runtime checks (inside diffrax's and optimistix's solvers) then return NaN instead of raising
   through a host callback. The simulator reports such a lane as failed (a result code), and a
   compiled program without host callbacks can be kept in JAX's persistent compilation cache, so a
   second run does not compile again. A value the user set is kept.
3. :func:`lugre_jax.cli.main` runs the command (it parses and checks again: the same code, so the
   same answers).
"""

import importlib
import importlib.util
import os
import sys
import types

_PARSE_PACKAGE = "_lugre_jax_cli_parse"


def _early_check(argv: list[str]) -> int | None:
    """Parse ``argv`` and run the subcommand's ``check`` without the package: an exit code if the
    command ends here (``--help``, a bad argument, an unusable output), else None. Anything unexpected
    (e.g. a subcommand module that imports more than the standard library) leaves the decision to
    the full CLI."""
    try:
        spec = importlib.util.find_spec("lugre_jax")
        if spec is None or not spec.submodule_search_locations:
            return None
        pkg = types.ModuleType(_PARSE_PACKAGE, "lugre_jax._cli, loaded for parsing only")
        pkg.__path__ = [os.path.join(list(spec.submodule_search_locations)[0], "_cli")]
        sys.modules[_PARSE_PACKAGE] = pkg
        args_mod = importlib.import_module(f"{_PARSE_PACKAGE}._args")
        parser, modules = args_mod.build_parser(lambda name: importlib.import_module(f"{_PARSE_PACKAGE}.{name}"))
    except Exception:
        return None
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # --help (0) or an argument error (2, argparse's one usage line + message)
        return e.code if isinstance(e.code, int) else 2
    check = getattr(modules[args.command], "check", None)
    if check is not None:
        try:
            check(args)
        except (ValueError, OSError) as e:
            print(args_mod.error_line(args.command, e), file=sys.stderr)
            return 2
        except Exception:
            return None
    return None


def main() -> int:
    try:
        code = _early_check(sys.argv[1:])
        if code is not None:
            return code
        os.environ.setdefault("EQX_ON_ERROR", "nan")
        from lugre_jax.cli import main as cli_main
    except KeyboardInterrupt:  # Ctrl-C while JAX loads, before cli.main handles signals
        print("lugre-jax: interrupted (Ctrl-C)", file=sys.stderr)
        return 130
    return cli_main()


if __name__ == "__main__":
    sys.exit(main())
