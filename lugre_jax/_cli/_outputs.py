"""Output paths of a command: checked at the start, before any work; written to staging paths beside
their targets; moved into place together only when the whole command succeeded.

The policy, the same for every command (docs/errors.md):

- a FILE output (``--out R.json``, ``--plot F.png``) may be new or an existing regular file, which is
  replaced atomically when the command has succeeded; a folder there, a parent that is a file, a
  wrong suffix or an unwritable folder is refused;
- a FOLDER output (``--out DIR``, ``--plots DIR``) may be new, empty, or an earlier result of the
  same command (it holds a ``MANIFEST.json``, written last), which is replaced as a whole when the
  new run has finished; any other folder is refused, so no file the user put there is deleted. A
  sweep's folder is the exception that resumes: it is kept and continued when it holds the same SPEC.

Every refusal is one ``ValueError`` line naming the flag and the path; the CLI turns it into exit
code 2. :func:`check_outputs` is the one call a subcommand's ``check(args)`` makes; it runs before
JAX and the package are imported (so it uses the standard library only), and again inside ``run``
through :class:`Outputs`::

    def check(args):                                   # lugre_jax_cli calls it before importing JAX
        check_outputs(args, out=".json", plots=FOLDER)

    def run(args):
        with Outputs(meta={"command": "diagnose"}) as outs:
            out = outs.file(args.out, "--out", ".json")     # the same check, then a staging path
            plots = outs.folder(args.plots, "--plots") if args.plots else None
            ... work, then write_json(out, ...), save_figure(fig, plots / "x.png") ...
        # here every output is in place; after an exception (or Ctrl-C) none is and no staging remains
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

MANIFEST = "MANIFEST.json"  # the same name as lugre_jax.io.MANIFEST (tests/test_cli_outputs.py)
FOLDER = "folder"  # check_outputs: this output is a folder

# Refuse (unless --force) to write a single output larger than this: a 20-million-sample trajectory
# is ~1.5 GB of CSV, which is rarely what was meant.
MAX_OUTPUT_BYTES = 500 * 1024**2


def _first_existing(path: Path) -> Path:
    anc = path
    while not anc.exists() and anc != anc.parent:
        anc = anc.parent
    return anc


def _writable(folder: Path) -> str | None:
    """None if a file can be created in ``folder``, else why not. Tried, not inferred from the mode
    bits: a read-only file system, a full disk's quota or a pseudo file system show only then."""
    try:
        fd, probe = tempfile.mkstemp(prefix=".lugre-jax-write-test-", dir=folder)
    except OSError as e:
        return e.strerror or type(e).__name__
    os.close(fd)
    os.unlink(probe)
    return None


def _check_parent(path, p: Path, flag: str, what: str) -> None:
    anc = _first_existing(p.parent)
    if not anc.is_dir():
        raise ValueError(f"{flag} {path}: {anc} is a file, so the {what} cannot be created; expected a path "
                         "in a folder")
    why = _writable(anc)
    if why is not None:
        raise ValueError(f"{flag} {path}: cannot write in {anc} ({why}), so the {what} cannot be "
                         f"{'replaced' if p.exists() else 'created'}")


def check_output_file(path, flag: str, suffixes: str | tuple[str, ...] = ()) -> Path:
    """Raise ``ValueError`` (naming ``flag`` and the path) unless ``path`` can be written as a file:
    not an existing folder, the expected suffix, its folder creatable and writable. An existing
    regular file is allowed: it is replaced atomically when the command has succeeded."""
    suffixes = (suffixes,) if isinstance(suffixes, str) else tuple(suffixes)
    p = Path(path)
    if str(path).endswith(("/", os.sep)) or p.is_dir():
        raise ValueError(f"{flag} {path}: is a folder; expected a file path"
                         + (f" ending in {' or '.join(suffixes)}" if suffixes else ""))
    if suffixes and p.suffix.lower() not in suffixes:
        raise ValueError(f"{flag} {path}: expected a file name ending in {' or '.join(suffixes)}")
    if p.exists() and not p.is_file():
        raise ValueError(f"{flag} {path}: exists and is not a regular file; expected a file path")
    _check_parent(path, p, flag, "file")
    return p


def _manifest_command(folder: Path) -> str | None:
    try:
        meta = json.loads((folder / MANIFEST).read_text()).get("meta") or {}
        return meta.get("command") if isinstance(meta, dict) else None
    except (OSError, ValueError, AttributeError):
        return None


def check_output_folder(path, flag: str, command: str | None = None) -> Path:
    """Raise ``ValueError`` (naming ``flag`` and the path) unless ``path`` can be replaced as a
    result folder: absent, empty, or an earlier result (it holds a ``MANIFEST.json``; of ``command``
    when its manifest names one), in a writable folder."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise ValueError(f"{flag} {path}: is an existing file; expected a folder (new, empty, or an earlier "
                         "result of this command)")
    if p.is_dir() and any(p.iterdir()):
        if not (p / MANIFEST).is_file():
            raise ValueError(f"{flag} {path}: exists, is not empty and holds no {MANIFEST} (not a result of this "
                             "command), so it will not be replaced; expected a new or empty folder")
        other = _manifest_command(p)
        if command is not None and other is not None and other != command:
            raise ValueError(f"{flag} {path}: holds a result of '{other}', not of '{command}', so it will not be "
                             "replaced; expected a new or empty folder")
    _check_parent(path, p, flag, "folder")
    return p


def check_outputs(args, command: str | None = None, **outputs) -> None:
    """Check every output path of a command before any work (see the module docstring). Each
    keyword names an attribute of ``args`` whose flag is ``--name`` (``_`` as ``-``); its value is
    the file suffix(es), or :data:`FOLDER`. An attribute that is None (an optional output not
    asked for) is skipped; two outputs on one path, or a file inside a folder output, are refused."""
    seen: dict[Path, str] = {}
    folders: list[tuple[Path, str]] = []
    for name, kind in outputs.items():
        path = getattr(args, name, None)
        if path is None:
            continue
        flag = "--" + name.replace("_", "-")
        if kind == FOLDER:
            check_output_folder(path, flag, command or getattr(args, "command", None))
        else:
            check_output_file(path, flag, kind)
        key = Path(path).resolve()
        if key in seen:
            raise ValueError(f"{flag} {path}: the same path as {seen[key]}; expected separate paths")
        seen[key] = flag
        if kind == FOLDER:
            folders.append((key, flag))
    for key, flag in seen.items():
        for folder, fflag in folders:
            if folder in key.parents:
                raise ValueError(f"{flag} {key}: inside the output folder {fflag} {folder}, which is replaced as a "
                                 "whole; expected separate paths")


def check_output_size(n_bytes: int, flag: str, path, force: bool, limit: int = MAX_OUTPUT_BYTES) -> None:
    """Refuse an output estimated above ``limit`` bytes unless ``force`` (the command's ``--force``)."""
    if n_bytes > limit and not force:
        raise ValueError(f"{flag} {path}: the output would be about {n_bytes / 1024**2:,.0f} MB, above the "
                         f"{limit / 1024**2:,.0f} MB limit; pass --force to write it anyway, or reduce the duration "
                         "or sample rate")


def csv_output_bytes(n_rows: int, n_columns: int, fmt: str = "%.10g") -> int:
    """Upper estimate of a CSV written by :func:`lugre_jax.io.write_csv`."""
    from ..io import csv_size_estimate

    return csv_size_estimate(n_rows, n_columns, fmt)


class Outputs:
    """The outputs of one command (see the module docstring). A context manager: on success every
    staged output is moved into place (with Ctrl-C held off for those renames); on any exception the
    staging files, staging folders and any parent folders it created are removed."""

    def __init__(self, meta: dict | None = None):
        self._files: list[tuple[Path, Path]] = []  # (staging, final)
        self._folders: list[tuple[Path, Path]] = []
        self._created: list[Path] = []  # parent folders made for the outputs, deepest last
        self._meta = dict(meta or {})
        self._finals: set[Path] = set()

    def _claim(self, final: Path, flag: str, is_folder: bool = False) -> None:
        key = final.resolve()
        if key in self._finals:
            raise ValueError(f"{flag} {final}: the same path is given for two outputs")
        # A folder output is replaced as a whole, so no other output may live inside it.
        folders = [f.resolve() for _, f in self._folders] + ([key] if is_folder else [])
        for other in self._finals | {key}:
            for folder in folders:
                if other != folder and folder in other.parents:
                    raise ValueError(f"{flag} {final}: one output lies inside the output folder {folder}; "
                                     "expected separate paths")
        self._finals.add(key)

    def _make_parent(self, p: Path) -> None:
        missing = []
        anc = p
        while not anc.exists():
            missing.append(anc)
            anc = anc.parent
        for d in reversed(missing):
            d.mkdir()
            self._created.append(d)

    def file(self, path, flag: str, suffixes: str | tuple[str, ...] = ()) -> Path:
        """Check ``path`` now; return the staging path to write instead (same folder, same suffix)."""
        suffixes = (suffixes,) if isinstance(suffixes, str) else tuple(suffixes)
        final = check_output_file(path, flag, suffixes)
        self._claim(final, flag)
        self._make_parent(final.parent)
        fd, tmp = tempfile.mkstemp(prefix=f".{final.name}.incomplete-", suffix=final.suffix, dir=final.parent)
        os.close(fd)
        os.unlink(tmp)  # writers create it (atomically); an unwritten output is simply absent
        self._files.append((Path(tmp), final))
        return Path(tmp)

    def folder(self, path, flag: str) -> Path:
        """Check ``path`` now (new, empty, or an earlier result of this command with its
        MANIFEST.json); return the staging folder to fill instead."""
        final = check_output_folder(path, flag, self._meta.get("command"))
        self._claim(final, flag, is_folder=True)
        self._make_parent(final.parent)
        tmp = Path(tempfile.mkdtemp(prefix=f".{final.name}.incomplete-", dir=final.parent))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)
        self._folders.append((tmp, final))
        return tmp

    def __enter__(self) -> "Outputs":
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        try:
            if exc_type is None:
                self._commit()
        finally:
            self._cleanup()
        return False

    def _commit(self) -> None:
        from ..io import deferred_signals, replace_folder, write_manifest

        for tmp, _ in self._folders:
            write_manifest(tmp, self._meta)
        with deferred_signals():
            for tmp, final in self._files:
                if tmp.exists():
                    os.replace(tmp, final)
            for tmp, final in self._folders:
                replace_folder(tmp, final)
        self._created.clear()  # now in use

    def _cleanup(self) -> None:
        from ..io import deferred_signals

        with deferred_signals():  # a second Ctrl-C must not cut the cleanup short
            self._remove_staging()

    def _remove_staging(self) -> None:
        for tmp, _ in self._files:
            if tmp.exists():
                tmp.unlink()
        for tmp, _ in self._folders:
            if tmp.exists():
                shutil.rmtree(tmp, ignore_errors=True)
        for d in reversed(self._created):
            try:
                d.rmdir()  # only if still empty
            except OSError:
                pass
