"""Joint recordings: a ``Recording`` container, a strict CSV loader and kinematics derivation.

A recording is what the diagnose tool is given: time, joint position, joint velocity and the actuator
torque at the joint, with optional reference/current/voltage columns. Units are carried in a
``units`` dict per recording, because two sources are in use: CSV recordings in the paper's units
(s, deg, deg/s, N*m; Li et al., Electronics 2020, 9, 284) and the EMPS benchmark in SI units
(s, m, m/s, N), see :mod:`lugre_jax.io._emps`. The friction models are unit-agnostic (every
parameter simply takes the units implied by the data); the units dict says which.

CSV format (header line required, comma separated, one sample per line)::

    time_s,[position_deg,][velocity_deg_s,]torque_nm[,velocity_ref_deg_s,position_ref_deg,current_a,voltage_v]

At least one of ``position_deg`` and ``velocity_deg_s`` must be present. A missing velocity is the
position's central difference, a missing position the integral of the velocity; ``meta`` records
which were measured (``velocity_measured``, ``position_measured``), so that the diagnosis conditions
the kinematics from what was measured; ``acceleration_supplied`` says whether the acceleration came
with the data (e.g. EMPS: computed upstream at the full rate) rather than being derived here.

Malformed input (missing column, non-numeric or NaN cell, non-increasing time) raises ``ValueError``
naming the file, the line (1-based, header = line 1), the column and what was expected.

Acceleration is not a column: it is derived as the benchmark of Janot et al. (EMPS, 2019) does, by a
zero-phase 4th-order Butterworth low-pass followed by central differences (:func:`derive_kinematics`;
default cutoff fs/4 and a 5-point stencil, see there).
"""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path
from typing import Any

import equinox as eqx
import numpy as np

REQUIRED_COLUMNS = ("time_s", "torque_nm")
KINEMATIC_COLUMNS = ("position_deg", "velocity_deg_s")  # at least one of them
OPTIONAL_COLUMNS = ("velocity_ref_deg_s", "position_ref_deg", "current_a", "voltage_v")
# written by `lugre-jax simulate` and read back without use (a recording has no bristle state)
IGNORED_COLUMNS = ("z_deg",)
PAPER_UNITS = {
    "time": "s",
    "position": "deg",
    "velocity": "deg/s",
    "acceleration": "deg/s^2",
    "torque": "N*m",
}


class Recording(eqx.Module):
    """One recording of a joint, as numpy float64 arrays of equal length ``n``.

    ``time`` [units['time']], ``position`` [units['position']], ``velocity`` [units['velocity']],
    ``acceleration`` [units['acceleration']] (derived, see :func:`derive_kinematics`), ``torque``
    (actuator torque/force at the joint) [units['torque']]; ``extra`` holds optional columns by name.
    """

    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    torque: np.ndarray
    units: dict = eqx.field(static=True)
    source: str = eqx.field(static=True, default="<memory>")
    extra: dict = eqx.field(default_factory=dict)
    meta: dict = eqx.field(static=True, default_factory=dict)

    @property
    def n(self) -> int:
        return int(self.time.shape[0])

    @property
    def dt(self) -> float:
        """Median sample interval [units['time']]."""
        return float(np.median(np.diff(self.time)))

    @property
    def rotary(self) -> bool:
        """True when position is an angle (deg or rad)."""
        return self.units.get("position") in ("deg", "rad")

    def subset(self, idx) -> "Recording":
        """Samples ``idx`` (a slice or index array) of every column."""
        return Recording(
            self.time[idx], self.position[idx], self.velocity[idx], self.acceleration[idx],
            self.torque[idx], self.units, self.source, {k: v[idx] for k, v in self.extra.items()},
            self.meta,
        )


def lowpass_zero_phase(x: np.ndarray, dt: float, cutoff_hz: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth low-pass (``scipy.signal.filtfilt``), as the EMPS benchmark scripts do."""
    from scipy import signal

    nyq = 0.5 / dt
    if cutoff_hz >= nyq:
        return np.asarray(x, dtype=np.float64)
    b, a = signal.butter(order, cutoff_hz / nyq)
    x = np.asarray(x, dtype=np.float64)
    # filtfilt's default padding (3*(order+1) samples) exceeds a very short signal; pad what there is.
    return signal.filtfilt(b, a, x, padlen=min(3 * max(len(a), len(b)), x.size - 1))


def central_difference(x: np.ndarray, dt: float) -> np.ndarray:
    """dx/dt by central differences, one-sided at the two ends."""
    return np.gradient(np.asarray(x, dtype=np.float64), dt)


def central_difference5(x: np.ndarray, dt: float) -> np.ndarray:
    """dx/dt by the 5-point (4th-order) central stencil; 2nd-order central/one-sided near the ends."""
    x = np.asarray(x, dtype=np.float64)
    d = np.gradient(x, dt)
    if x.size >= 5:
        d[2:-2] = (-x[4:] + 8 * x[3:-1] - 8 * x[1:-3] + x[:-4]) / (12 * dt)
    return d


def derive_kinematics(
    time: np.ndarray, velocity: np.ndarray, cutoff_hz: float | None = None
) -> np.ndarray:
    """Acceleration from measured velocity: zero-phase low-pass, then central differences.

    As in the EMPS benchmark (Butterworth filtfilt, then central differences), but since a CSV
    carries measured velocity (one derivative, not two, from the encoder) the default cutoff is a
    quarter of the sampling rate and the stencil is the 5-point (4th-order) one, so fast but smooth
    accelerations are not biased.
    """
    dt = float(np.median(np.diff(time)))
    if cutoff_hz is None:
        cutoff_hz = 0.25 / dt
    return central_difference5(lowpass_zero_phase(velocity, dt, cutoff_hz), dt)


def recording_from_arrays(
    time, position, velocity, torque, *, units: dict | None = None, source: str = "<memory>",
    acceleration=None, cutoff_hz: float | None = None, extra: dict | None = None,
    meta: dict | None = None,
) -> Recording:
    """Build a :class:`Recording` from arrays (paper units unless ``units`` says otherwise).

    ``position`` or ``velocity`` may be ``None`` (not measured): the velocity is then the position's
    central difference, the position the trapezoidal integral of the velocity (from 0), and
    ``meta['velocity_measured']`` / ``meta['position_measured']`` say so."""
    if position is None and velocity is None:
        raise ValueError(f"{source}: neither position nor velocity given; expected at least one of them")
    meta = dict(meta or {})
    meta.setdefault("velocity_measured", velocity is not None)
    meta.setdefault("position_measured", position is not None)
    meta.setdefault("acceleration_supplied", acceleration is not None)
    time = np.asarray(time, dtype=np.float64)
    if velocity is None and np.shape(position) == time.shape and time.size >= 2:
        velocity = np.gradient(np.asarray(position, np.float64), time)
    if position is None and np.shape(velocity) == time.shape and time.size >= 2:
        from scipy.integrate import cumulative_trapezoid

        position = np.concatenate([[0.0], cumulative_trapezoid(np.asarray(velocity, np.float64), time)])
    cols = {k: np.asarray(v, dtype=np.float64) for k, v in
            dict(time=time, position=position, velocity=velocity, torque=torque).items()}
    n = cols["time"].shape[0]
    for k, v in cols.items():
        if v.shape != (n,):
            raise ValueError(f"{source}: column {k!r} has shape {v.shape}, expected ({n},)")
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise ValueError(f"{source}: column {k!r} sample {bad[0]} is {v[bad[0]]}; expected a finite number")
    if n < 10:
        raise ValueError(f"{source}: {n} samples; a recording needs at least 10")
    d = np.diff(cols["time"])
    bad = np.flatnonzero(d <= 0)
    if bad.size:
        raise ValueError(f"{source}: time is not strictly increasing at sample {bad[0] + 1}")
    if acceleration is None:
        acceleration = derive_kinematics(cols["time"], cols["velocity"], cutoff_hz)
    return Recording(
        cols["time"], cols["position"], cols["velocity"], np.asarray(acceleration, np.float64),
        cols["torque"], dict(PAPER_UNITS if units is None else units), source,
        {k: np.asarray(v, np.float64) for k, v in (extra or {}).items()}, meta,
    )


MIN_SAMPLES = 100  # a file recording needs this many rows: ~10 parameters, 25 time blocks, filters


def load_recording(path: str | os.PathLike, cutoff_hz: float | None = None) -> Recording:
    """Load a CSV recording (paper units, see the module docstring), validating every cell.

    Raises ``ValueError`` naming file, line and column for: undecodable bytes, a header separated by
    ';' or tabs, a missing or duplicated column, an empty or non-numeric cell, NaN/inf, a short row,
    time that does not strictly increase or is not uniformly sampled (the worst step is named), fewer
    than :data:`MIN_SAMPLES` rows, a joint that never moves, or a constant torque column.
    """
    from ._validate import (
        check_delimiter, check_motion, check_not_constant, check_uniform_time, check_unique_columns, read_text,
    )

    path = Path(path)
    text = read_text(path, "recording CSV")
    reader = csv.reader(text.splitlines())
    try:
        header = next(reader)
    except StopIteration:
        raise ValueError(f"{path}: line 1: empty file; expected a header line such as "
                         f"'time_s,position_deg,velocity_deg_s,torque_nm'") from None
    header = [h.strip() for h in header]
    check_delimiter(path, 1, text.splitlines()[0])
    check_unique_columns(path, 1, header)
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if not any(c in header for c in KINEMATIC_COLUMNS):
        missing.append(" or ".join(KINEMATIC_COLUMNS))
    if missing:
        raise ValueError(
            f"{path}: line 1: missing column(s) {missing}; expected a header with "
            f"{list(REQUIRED_COLUMNS)}, at least one of {list(KINEMATIC_COLUMNS)} "
            f"(optional {list(OPTIONAL_COLUMNS)}), got {header}"
        )
    # one rule with the friction-data reader: a column the format does not know is refused, not
    # silently dropped (a misspelt 'velocity_deg_s' would otherwise leave a position-only recording)
    unknown = [h for h in header if h not in REQUIRED_COLUMNS + KINEMATIC_COLUMNS + OPTIONAL_COLUMNS + IGNORED_COLUMNS]
    if unknown:
        raise ValueError(
            f"{path}: line 1: unknown column(s) {unknown}; expected {list(REQUIRED_COLUMNS)}, at least one of "
            f"{list(KINEMATIC_COLUMNS)}, and optionally {list(OPTIONAL_COLUMNS + IGNORED_COLUMNS)}")
    wanted = [c for c in REQUIRED_COLUMNS + KINEMATIC_COLUMNS + OPTIONAL_COLUMNS if c in header]
    idx = {c: header.index(c) for c in wanted}
    data: dict[str, list[float]] = {c: [] for c in wanted}
    lines: list[int] = []
    last_t = -math.inf
    for lineno, row in enumerate(reader, start=2):
        if not row or all(not cell.strip() for cell in row):
            continue
        if len(row) < len(header):
            raise ValueError(f"{path}: line {lineno}: column {header[len(row)]!r} is missing "
                             f"(row has {len(row)} cells, header has {len(header)})")
        if len(row) > len(header):
            raise ValueError(f"{path}: line {lineno}: {len(row)} cells; expected {len(header)} as in the header "
                             f"({','.join(header)})")
        for c in wanted:
            cell = row[idx[c]].strip()
            try:
                x = float(cell)
            except ValueError:
                raise ValueError(f"{path}: line {lineno}: column {c!r}: {cell!r} is not a number; "
                                 f"expected a finite decimal value") from None
            if not math.isfinite(x):
                raise ValueError(f"{path}: line {lineno}: column {c!r}: {cell!r}; "
                                 f"expected a finite number (no NaN/inf)")
            data[c].append(x)
        t = data["time_s"][-1]
        if not t > last_t:
            raise ValueError(f"{path}: line {lineno}: column 'time_s': {t!r} does not increase "
                             f"(previous {last_t!r}); expected strictly increasing time")
        last_t = t
        lines.append(lineno)
    if len(lines) < MIN_SAMPLES:
        raise ValueError(f"{path}: {len(lines)} data rows; expected at least {MIN_SAMPLES} uniformly sampled rows "
                         "to fit a friction model")
    cols = {c: np.asarray(v) for c, v in data.items()}
    check_uniform_time(path, cols["time_s"], np.asarray(lines))
    pos, vel = cols.get("position_deg"), cols.get("velocity_deg_s")
    if vel is not None:
        check_motion(path, vel, pos)
    else:
        check_motion(path, np.gradient(pos, cols["time_s"]), pos, column="position_deg")
    check_not_constant(path, cols["torque_nm"], "torque_nm")
    extra = {c: cols[c] for c in OPTIONAL_COLUMNS if c in cols}
    return recording_from_arrays(
        cols["time_s"], pos, vel, cols["torque_nm"],
        source=str(path), cutoff_hz=cutoff_hz, extra=extra,
    )


def write_recording(path: str | os.PathLike, rec: Recording) -> None:
    """Write a recording in paper units as the CSV :func:`load_recording` reads (atomically); a
    position or velocity that was derived, not measured (``meta``), is left out."""
    from ._atomic import write_csv

    if rec.units.get("position") != "deg":
        raise ValueError(f"write_recording writes paper units (deg); this recording is in {rec.units}")
    # only the measured kinematics: a derived column read back would pass for a measured one
    cols: dict[str, Any] = {"time_s": rec.time}
    if rec.meta.get("position_measured", True):
        cols["position_deg"] = rec.position
    if rec.meta.get("velocity_measured", True):
        cols["velocity_deg_s"] = rec.velocity
    cols["torque_nm"] = rec.torque
    cols.update({k: v for k, v in rec.extra.items() if k in OPTIONAL_COLUMNS})
    write_csv(path, cols, fmt="%.12g")
