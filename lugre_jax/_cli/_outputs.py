"""Output paths of a command: checked at the start, before any work; written to staging paths beside
their targets; moved into place together only when the whole command succeeded.

Usage in a subcommand's ``run``::

    with Outputs() as outs:
        out = outs.file(args.out, "--out", ".json")        # raises ValueError now if unusable
        plot = outs.file(args.plot, "--plot", ".png") if args.plot else None
        ... work, then write_json(out, ...), save_figure(fig, plot) ...
    # here every output is in place; after an exception (or Ctrl-C) none is and no staging remains

A folder output (``outs.folder``) gets a ``MANIFEST.json`` written last and replaces only an empty
folder or a previous result of the same kind (see :func:`lugre_jax.io.check_folder_replaceable`).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from ..io import check_folder_replaceable, csv_size_estimate, deferred_signals, replace_folder, write_manifest

# Refuse (unless --force) to write a single output larger than this: a 20-million-sample trajectory
# is ~1.5 GB of CSV, which is rarely what was meant.
MAX_OUTPUT_BYTES = 500 * 1024**2


def _first_existing(path: Path) -> Path:
    anc = path
    while not anc.exists() and anc != anc.parent:
        anc = anc.parent
    return anc


def check_output_file(path, flag: str, suffixes: tuple[str, ...] = ()) -> Path:
    """Raise ``ValueError`` (naming ``flag`` and the path) unless ``path`` can be written as a file:
    not an existing folder, the expected suffix, its folder creatable and writable."""
    p = Path(path)
    if str(path).endswith(("/", os.sep)) or p.is_dir():
        raise ValueError(f"{flag} {path}: is a folder; expected a file path"
                         + (f" ending in {'/'.join(suffixes)}" if suffixes else ""))
    if suffixes and p.suffix.lower() not in suffixes:
        raise ValueError(f"{flag} {path}: expected a file name ending in {' or '.join(suffixes)}")
    if p.exists() and not p.is_file():
        raise ValueError(f"{flag} {path}: exists and is not a regular file")
    anc = _first_existing(p.parent)
    if not anc.is_dir():
        raise ValueError(f"{flag} {path}: {anc} is a file, so the folder cannot be created")
    if not os.access(anc, os.W_OK | os.X_OK):
        raise ValueError(f"{flag} {path}: {anc} is not writable")
    return p


def check_output_size(n_bytes: int, flag: str, path, force: bool, limit: int = MAX_OUTPUT_BYTES) -> None:
    """Refuse an output estimated above ``limit`` bytes unless ``force`` (the command's ``--force``)."""
    if n_bytes > limit and not force:
        raise ValueError(f"{flag} {path}: the output would be about {n_bytes / 1024**2:,.0f} MB, above the "
                         f"{limit / 1024**2:,.0f} MB limit; pass --force to write it anyway, or reduce the duration "
                         "or sample rate")


def csv_output_bytes(n_rows: int, n_columns: int, fmt: str = "%.10g") -> int:
    """Upper estimate of a CSV written by :func:`lugre_jax.io.write_csv`."""
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
        """Check ``path`` now (new, empty, or a previous result with its MANIFEST.json); return the
        staging folder to fill instead."""
        try:
            final = check_folder_replaceable(path)
        except ValueError as e:
            raise ValueError(f"{flag} {e}") from None
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
