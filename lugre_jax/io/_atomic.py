"""Atomic output: write to a temporary file beside the target, then rename.

A command that fails half-way therefore never leaves a truncated CSV, JSON or PNG behind. A result of
several files is built in a temporary sibling folder (:func:`atomic_folder`) whose ``MANIFEST.json``
is written last and which is renamed into place only when complete; a folder without its manifest is
incomplete by definition.
"""

from __future__ import annotations

import contextlib
import datetime
import hashlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, Iterator

import numpy as np


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path in the target's folder; on success it replaces ``path``."""
    path = Path(path)
    if path.is_dir():  # else the final rename fails naming the temporary file, not the user's path
        raise ValueError(f"{path}: is a folder; expected a file path to write")
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    # mkstemp creates 0600 files; outputs are ordinary files, so honour the umask like open() does.
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        with deferred_signals():  # a second Ctrl-C must not cut the cleanup short
            if tmp.exists():
                tmp.unlink()


def _jsonable(x: Any):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if hasattr(x, "__array__") and not isinstance(x, (str, bytes)):
        a = np.asarray(x)
        return _jsonable(a.tolist()) if a.ndim else _jsonable(a.item())
    if isinstance(x, float) and not np.isfinite(x):
        return None if np.isnan(x) else ("inf" if x > 0 else "-inf")
    if isinstance(x, (np.floating, np.integer, np.bool_)):
        return _jsonable(x.item())
    return x


def write_json(path: str | os.PathLike, obj: Any) -> None:
    """Write ``obj`` as indented JSON, atomically (arrays become lists, NaN becomes null)."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(_jsonable(obj), indent=2) + "\n")


CSV_CHUNK_ROWS = 65536  # rows formatted at a time: bounds the text buffer, not the file size


def csv_size_estimate(n_rows: int, n_columns: int, fmt: str = "%.10g") -> int:
    """Bytes a :func:`write_csv` file of ``n_rows`` x ``n_columns`` will take, from the widest value
    ``fmt`` can print (an upper bound up to the header line)."""
    width = len(fmt % -1.2345678901234567e-300)
    return int(n_rows) * int(n_columns) * (width + 1)


def write_csv(path: str | os.PathLike, columns: Mapping[str, Any] | Iterable[Mapping[str, Any]],
              fmt: str = "%.10g") -> None:
    """Write equal-length columns as a CSV with a header, atomically.

    ``columns`` is one mapping name -> array, or an iterable of such mappings with the same names (a
    stream of row chunks, e.g. from a generator), so a long trajectory need never be in memory at once;
    rows are formatted :data:`CSV_CHUNK_ROWS` at a time either way."""
    chunks = iter([columns] if isinstance(columns, Mapping) else columns)
    first = next(chunks, None)
    if first is None:
        raise ValueError(f"{path}: write_csv was given no data")
    names = list(first)
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        fh.write(",".join(names) + "\n")
        for chunk in _chain(first, chunks):
            if list(chunk) != names:
                raise ValueError(f"{path}: a chunk has columns {list(chunk)}, the first had {names}")
            data = np.column_stack([np.asarray(chunk[n], dtype=np.float64).reshape(-1) for n in names])
            for i in range(0, data.shape[0], CSV_CHUNK_ROWS):
                np.savetxt(fh, data[i:i + CSV_CHUNK_ROWS], delimiter=",", fmt=fmt)


def _chain(first, rest):
    yield first
    yield from rest


MANIFEST = "MANIFEST.json"


@contextlib.contextmanager
def deferred_signals() -> Iterator[None]:
    """Hold SIGINT and SIGTERM until the block ends: for the few renames that move a finished result
    into place, which must happen all or not at all. A signal that arrives meanwhile is delivered
    right after the block."""
    import signal

    sigs = {signal.SIGINT, signal.SIGTERM}
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    except (AttributeError, OSError, ValueError):  # platforms without pthread_sigmask
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def check_folder_replaceable(path: str | os.PathLike, what: str = "output folder") -> Path:
    """Raise ``ValueError`` unless ``path`` is absent, an empty folder, or a folder an earlier
    :func:`atomic_folder` wrote (it holds a ``MANIFEST.json``): so replacing it cannot delete files
    the user put there. Checked at the start of a command, before any work."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{path}: {what} is an existing file; expected a folder (new, empty, or a previous result)")
    if path.is_dir() and any(path.iterdir()) and not (path / MANIFEST).is_file():
        raise ValueError(f"{path}: {what} exists, is not empty and holds no {MANIFEST} (not a result of this "
                         "command), so it will not be replaced; expected a new or empty folder")
    anc = path.parent
    while not anc.exists():
        anc = anc.parent
    if not anc.is_dir():
        raise ValueError(f"{path}: {anc} is a file, so the {what} cannot be created; expected a folder path")
    if not os.access(anc, os.W_OK | os.X_OK):
        raise ValueError(f"{path}: cannot create the {what}: {anc} is not writable")
    return path


def write_manifest(folder: Path, meta: Mapping[str, Any] | None = None) -> None:
    """Write ``folder/MANIFEST.json``: every file with its size and SHA-256, plus ``meta``; written
    last, it is what marks the folder complete."""
    folder = Path(folder)
    files = sorted(p for p in folder.rglob("*") if p.is_file() and p.name != MANIFEST)
    write_json(folder / MANIFEST, dict(
        complete=True,
        written_utc=datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        meta=dict(meta or {}),
        files={str(p.relative_to(folder)): dict(bytes=p.stat().st_size, sha256=_sha256(p)) for p in files},
    ))


def replace_folder(tmp: Path, path: Path) -> None:
    """Rename the finished folder ``tmp`` to ``path``, moving a previous result there aside first and
    deleting it afterwards (a folder rename cannot overwrite a non-empty folder)."""
    check_folder_replaceable(path)  # unchanged since the command started?
    old = None
    if path.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old-", dir=path.parent))
        os.replace(path, old / path.name)
    os.replace(tmp, path)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


@contextlib.contextmanager
def atomic_folder(path: str | os.PathLike, *, meta: Mapping[str, Any] | None = None) -> Iterator[Path]:
    """Yield a temporary sibling folder ``.NAME.incomplete-XXXX`` to fill; when the block succeeds,
    write ``MANIFEST.json`` (every file with its size and SHA-256, plus ``meta``) last, then rename the
    folder to ``path``, replacing a previous result there (see :func:`check_folder_replaceable`). When
    the block raises (including Ctrl-C), the temporary folder is deleted and ``path`` is untouched.

    A process killed outright (SIGKILL, power loss) can leave the hidden temporary folder; it has no
    manifest, so it is recognisably incomplete."""
    path = check_folder_replaceable(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.incomplete-", dir=path.parent))
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)
    try:
        yield tmp
        write_manifest(tmp, meta)
        with deferred_signals():  # the renames must not be split by Ctrl-C
            replace_folder(tmp, path)
    finally:
        with deferred_signals():
            if tmp.exists():
                shutil.rmtree(tmp, ignore_errors=True)


def save_figure(fig, path: str | os.PathLike, dpi: int = 120) -> None:
    """Save a matplotlib figure as PNG, atomically, and close it (a saved figure is finished; pyplot
    would otherwise keep every figure of a long run alive)."""
    import matplotlib.pyplot as plt

    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format="png", bbox_inches="tight")
    finally:
        plt.close(fig)
