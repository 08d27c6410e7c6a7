"""Loader for maxon EPOS Studio data-recorder exports, as published with A. Mablekos-Alexiou,
L. da Cruz, C. Bergeles, "Friction-Inclusive Modeling of Sliding Contact Transmission Systems in
Robotics", IEEE T-RO 37(4), 2021 (the ``tro2021`` steady-state sweeps).

File layout: a header block (``Key:;value;...``), a line ``;Velocity actual value averaged;Torque actual
value averaged`` naming the channels, a units line ``ms;rpm;%``, then semicolon-separated rows
``time;velocity;torque``. The torque is in percent of the motor's nominal torque (9.84 mN*m for the
TRO2021 motor).

Sign convention: the authors' own loader, ``omega = -rpm*pi/30`` [rad/s] and
``tau = -% * nominal/100`` [N*m]. We apply it and then convert to this package's units: velocity in
deg/s (``-rpm*6``), torque in N*m.

Real-file quirks handled: Windows line ends, trailing commas on every line of some files, and a
hand-corrected value annotated in the row (``0.000;-1;-800,,was -11.1``). An annotated row is
dropped (neither the edited nor the original value is trustworthy as a steady-state sample) and
noted in the result. Anything else that does not parse raises ``ValueError`` naming the file, line,
column and what was expected.
"""

from __future__ import annotations

import dataclasses
import os
import re
from pathlib import Path

import numpy as np

from ._stribeck_data import StribeckData

TRO2021_NOMINAL_TORQUE_NM = 9.84e-3
VELOCITY_CHANNEL = "Velocity actual value averaged"
TORQUE_CHANNEL = "Torque actual value averaged"
_ANNOTATED = re.compile(r"^(?P<row>[^,]*?),*\s*was\s+(?P<was>\S+)\s*$", re.IGNORECASE)


@dataclasses.dataclass(frozen=True)
class EposRecording:
    """One EPOS Studio recording, converted to the package's units and the authors' sign convention.

    Attributes: ``time`` [s], ``velocity`` [deg/s], ``torque`` [N*m] (arrays of equal length),
    ``header`` (the header block as key -> list of values), ``path``, ``notes``.
    """

    time: np.ndarray
    velocity: np.ndarray
    torque: np.ndarray
    header: dict
    path: str
    notes: tuple[str, ...] = ()


def _clean(line: str) -> str:
    return line.rstrip("\r\n").rstrip().rstrip(",").rstrip()


def load_epos_file(path: str | os.PathLike, *, nominal_torque_nm: float = TRO2021_NOMINAL_TORQUE_NM) -> EposRecording:
    """Read one EPOS Studio export (see module docstring). Velocity out in deg/s, torque in N*m."""
    from ._validate import read_text

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file (expected an EPOS Studio .csv export)")
    lines = read_text(path, "EPOS Studio .csv export").splitlines()
    header: dict[str, list[str]] = {}
    names_line = None
    for i, raw in enumerate(lines):
        s = _clean(raw)
        if s.startswith(";"):
            names_line = i
            break
        if not s:
            continue
        key, _, rest = s.partition(";")
        header[key.rstrip(":").strip()] = rest.split(";") if rest else []
    if names_line is None:
        raise ValueError(
            f"{path}:{len(lines) or 1}: no channel line found; expected a line like "
            f"';{VELOCITY_CHANNEL};{TORQUE_CHANNEL}' after the header block"
        )
    names = [c.strip() for c in _clean(lines[names_line]).split(";")]
    for ch in (VELOCITY_CHANNEL, TORQUE_CHANNEL):
        if ch not in names:
            raise ValueError(f"{path}:{names_line + 1}: channel {ch!r} not found among {names[1:]}")
    iv, it = names.index(VELOCITY_CHANNEL), names.index(TORQUE_CHANNEL)
    if names_line + 1 >= len(lines):
        raise ValueError(f"{path}:{names_line + 2}: expected a units line 'ms;rpm;%', found end of file")
    units = [u.strip() for u in _clean(lines[names_line + 1]).split(";")]
    if len(units) != len(names) or units[0] != "ms" or units[iv] != "rpm" or units[it] != "%":
        raise ValueError(
            f"{path}:{names_line + 2}: expected units 'ms' for time, 'rpm' for velocity and '%' for torque "
            f"(a line like 'ms;rpm;%'), got {';'.join(units)!r}"
        )
    rows, notes = [], []
    for i in range(names_line + 2, len(lines)):
        lineno = i + 1
        s = lines[i].rstrip("\r\n").strip()
        if not s.rstrip(","):
            continue
        m = _ANNOTATED.match(s)
        if m:
            notes.append(
                f"{path.name}:{lineno}: dropped hand-corrected sample {m.group('row')!r} (annotated 'was {m.group('was')}')"
            )
            continue
        cells = _clean(s).split(";")
        if len(cells) != len(names):
            raise ValueError(
                f"{path}:{lineno}: expected {len(names)} ';'-separated cells ({';'.join(units)}), got {len(cells)}: {s!r}"
            )
        vals = []
        for k, c in enumerate(cells):
            try:
                x = float(c)
            except ValueError:
                raise ValueError(
                    f"{path}:{lineno}, column {k + 1} ({names[k] or 'time'}): expected a number in {units[k]}, got {c!r}"
                ) from None
            if not np.isfinite(x):
                raise ValueError(f"{path}:{lineno}, column {k + 1}: expected a finite number, got {c!r}")
            vals.append(x)
        rows.append(vals)
    if not rows:
        raise ValueError(f"{path}:{names_line + 3}: no data rows after the units line")
    a = np.asarray(rows)
    rec = header.get("Recorded samples")
    if rec and rec[0].strip().isdigit() and int(rec[0]) != len(rows) + len(notes):
        notes.append(f"{path.name}: header says {int(rec[0])} recorded samples, file holds {len(rows) + len(notes)}")
    return EposRecording(
        time=a[:, 0] * 1e-3,
        velocity=-a[:, iv] * 6.0,  # -rpm * 360/60 deg/s (authors' sign convention)
        torque=-a[:, it] * nominal_torque_nm / 100.0,
        header=header,
        path=str(path),
        notes=tuple(notes),
    )


def _set_point_from_name(p: Path) -> float | None:
    m = re.fullmatch(r"(n?)(\d+(?:\.\d+)?)", p.stem)
    if not m:
        return None
    rpm = float(m.group(2))
    # File names give the commanded direction: 'n' = negative. After the authors' sign flip the
    # positive-direction files carry positive velocity.
    return (-rpm if m.group(1) else rpm) * 6.0


def load_epos_steady_state(
    folder: str | os.PathLike,
    *,
    nominal_torque_nm: float = TRO2021_NOMINAL_TORQUE_NM,
) -> StribeckData:
    """Load a folder of constant-velocity EPOS runs (one ``.csv`` per set-point, e.g.
    ``tro2021/driveNo1/steady_state/0.096kg``) as steady-state friction data.

    Each file becomes one set-point: the mean measured velocity [deg/s], the mean torque [N*m], the
    torque spread and its standard error. Both directions are kept (negative velocity = negative
    direction); use :meth:`StribeckData.direction` to pick one.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder}: not a folder (expected a folder of EPOS Studio .csv exports, one per set-point)")
    files = sorted(folder.glob("*.csv"))
    if not files:
        raise ValueError(f"{folder}: no .csv files found (expected one EPOS Studio export per velocity set-point)")
    vel, tor, sd, cnt, notes = [], [], [], [], []
    for f in files:
        rec = load_epos_file(f, nominal_torque_nm=nominal_torque_nm)
        notes.extend(rec.notes)
        v = float(np.mean(rec.velocity))
        sp = _set_point_from_name(f)
        if sp is not None and np.sign(v) != np.sign(sp):
            notes.append(f"{f.name}: mean velocity {v:.4g} deg/s has the opposite sign to the file name's set-point")
        vel.append(v)
        tor.append(float(np.mean(rec.torque)))
        sd.append(float(np.std(rec.torque, ddof=1)) if rec.torque.size > 1 else np.nan)
        cnt.append(rec.torque.size)
    if len(np.unique(np.round(vel, 9))) < 2:
        raise ValueError(f"{folder}: a single velocity set-point; identification needs at least two")
    vel, tor, sd, cnt = map(np.asarray, (vel, tor, sd, cnt))
    order = np.argsort(vel)
    vel, tor, sd, cnt = vel[order], tor[order], sd[order], cnt[order]
    # Consecutive samples of one run are strongly correlated (the drive's averaging filter), so
    # sd/sqrt(n) understates the uncertainty of the mean; we still use it as the relative weight and
    # let the schemes rescale by the residual variance.
    se = sd / np.sqrt(cnt)
    return StribeckData(
        velocity=vel,
        torque=tor,
        torque_sd=sd,
        torque_se=se,
        count=cnt.astype(np.int64),
        branch=np.full(vel.shape, "accel", dtype="<U5"),
        source=str(folder),
        notes=tuple(notes),
    )


def load_friction_data(path: str | os.PathLike) -> StribeckData:
    """Load a Stribeck CSV file or an EPOS steady-state folder (deg/s, N*m), chosen by what ``path`` is."""
    from ._stribeck_data import load_stribeck_csv

    p = Path(path)
    if p.is_dir():
        return load_epos_steady_state(p)
    if p.is_file():
        return load_stribeck_csv(p)
    raise ValueError(f"{p}: no such file or folder (expected a Stribeck CSV or an EPOS steady-state folder)")
