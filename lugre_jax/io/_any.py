"""One reader for every recording format the commands take: the project's CSV, an EPOS Studio
export (TRO2021) and the EMPS benchmark's .mat."""

from __future__ import annotations

import os
from pathlib import Path

from ._recording import Recording


def read_recording(path: str | os.PathLike) -> Recording:
    """A :class:`Recording` from a recording CSV, one EPOS Studio export (velocity and torque only:
    the velocity column measured, the position its integral) or DATA_EMPS.mat, told apart by the
    file's suffix and first lines. Raises ``ValueError`` naming the file for anything else."""
    from ._emps import load_emps
    from ._epos import load_epos_file
    from ._recording import load_recording, recording_from_arrays

    p = Path(path)
    if p.is_dir():
        raise ValueError(f"{p}: is a folder; expected one recording: a CSV, an EPOS Studio export or "
                         "DATA_EMPS.mat")
    if not p.exists():
        raise ValueError(f"{p}: no such file; expected a recording CSV, an EPOS Studio export or DATA_EMPS.mat")
    if p.suffix.lower() == ".mat":
        return load_emps(p)
    with open(p, "rb") as fh:
        head = fh.read(4096).decode("utf-8", errors="replace")
    if "actual value averaged" in head or head.startswith("Date:;"):
        e = load_epos_file(p)
        return recording_from_arrays(e.time, None, e.velocity, e.torque, source=str(p))
    return load_recording(p)
