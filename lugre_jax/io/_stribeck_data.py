"""Steady-state friction data (velocity set-point -> torque), as used for static identification in
Li et al., Electronics 2020, 9, 284, section 4.2.2 ("thirty values of torques were recorded at the
same velocity, and their average values taken. A total of 92 sets of torques were measured").

Units: velocity in deg/s, torque in N*m.

CSV format read by :func:`load_stribeck_csv` (comma separated, one header line, ``#`` comment lines
allowed anywhere):

* ``velocity_deg_s`` (required): the velocity set-point;
* ``torque_nm`` (required): a torque sample (several rows per set-point are averaged, and their
  spread becomes the weight of the average);
* ``branch`` (optional): ``accel`` or ``decel`` (section 4.2.2: the low-velocity segment is measured
  while accelerating and while decelerating, with a higher static friction when starting). Rows
  without the column are ``accel``.

Every problem is reported as one ``ValueError`` naming the file, the line (and the column where it
applies) and what was expected.
"""

from __future__ import annotations

import csv
import dataclasses
import os
from pathlib import Path

import numpy as np

BRANCHES = ("accel", "decel")
REQUIRED_COLUMNS = ("velocity_deg_s", "torque_nm")
OPTIONAL_COLUMNS = ("branch",)


@dataclasses.dataclass(frozen=True)
class StribeckData:
    """Averaged steady-state friction data, one entry per (velocity set-point, branch).

    Attributes (all arrays of shape ``(n,)``):
        velocity: set-point velocity [deg/s] (either sign; negative = negative direction).
        torque: mean friction torque at the set-point [N*m].
        torque_sd: sample standard deviation of the torque samples [N*m] (NaN with one sample).
        torque_se: standard error of the mean used as the weight ``1/se**2`` [N*m]; where a set-point
            has a single sample it is the pooled per-sample spread (NaN if no set-point has repeats).
        count: number of samples averaged.
        branch: ``"accel"`` or ``"decel"``.
        source: where the data came from (file or folder).
        notes: remarks made while loading (dropped or annotated samples).
    """

    velocity: np.ndarray
    torque: np.ndarray
    torque_sd: np.ndarray
    torque_se: np.ndarray
    count: np.ndarray
    branch: np.ndarray
    source: str = ""
    notes: tuple[str, ...] = ()

    def __len__(self) -> int:
        return int(self.velocity.shape[0])

    @property
    def has_weights(self) -> bool:
        """True when every set-point has a finite, positive standard error."""
        return bool(np.all(np.isfinite(self.torque_se)) and np.all(self.torque_se > 0))

    def select(self, mask) -> "StribeckData":
        """The subset of set-points where ``mask`` is true."""
        m = np.asarray(mask, dtype=bool)
        return dataclasses.replace(
            self,
            velocity=self.velocity[m],
            torque=self.torque[m],
            torque_sd=self.torque_sd[m],
            torque_se=self.torque_se[m],
            count=self.count[m],
            branch=self.branch[m],
        )

    def direction(self, sign: int) -> "StribeckData":
        """Set-points of one direction (``sign`` = +1 or -1), mirrored to positive velocity/torque."""
        if sign not in (1, -1):
            raise ValueError(f"direction sign must be +1 or -1, got {sign!r}")
        sub = self.select(np.sign(self.velocity) == sign)
        return dataclasses.replace(sub, velocity=sign * sub.velocity, torque=sign * sub.torque).sorted()

    def sorted(self) -> "StribeckData":
        """Set-points ordered by branch (accel first) then velocity."""
        order = np.lexsort((self.velocity, self.branch != "accel"))
        return self._take(order)

    def _take(self, idx) -> "StribeckData":
        return dataclasses.replace(
            self,
            velocity=self.velocity[idx],
            torque=self.torque[idx],
            torque_sd=self.torque_sd[idx],
            torque_se=self.torque_se[idx],
            count=self.count[idx],
            branch=self.branch[idx],
        )


def summarise_samples(
    velocity, torque, branch=None, *, source: str = "", notes: tuple[str, ...] = ()
) -> StribeckData:
    """Average repeated torque samples per (velocity, branch) into a :class:`StribeckData`.

    ``velocity`` [deg/s] and ``torque`` [N*m] are per-sample arrays; ``branch`` per-sample strings
    (default all ``"accel"``). The standard error of each mean is ``sd/sqrt(count)``; set-points with
    a single sample (or zero spread, e.g. quantised readings) get the pooled per-sample spread so that
    no point receives an infinite weight.
    """
    velocity = np.asarray(velocity, dtype=np.float64)
    torque = np.asarray(torque, dtype=np.float64)
    branch = np.full(velocity.shape, "accel", dtype=object) if branch is None else np.asarray(branch, dtype=object)
    keys: dict[tuple[str, float], list[float]] = {}
    for v, t, b in zip(velocity, torque, branch):
        keys.setdefault((str(b), float(v)), []).append(float(t))
    items = sorted(keys.items(), key=lambda kv: (kv[0][0] != "accel", kv[0][1]))
    n = len(items)
    vel = np.array([k[1] for k, _ in items])
    br = np.array([k[0] for k, _ in items], dtype="<U5")
    cnt = np.array([len(s) for _, s in items], dtype=np.int64)
    mean = np.array([np.mean(s) for _, s in items])
    sd = np.array([np.std(s, ddof=1) if len(s) > 1 else np.nan for _, s in items])
    ok = np.isfinite(sd) & (sd > 0)
    if ok.any():
        # Pooled spread: the noise level to assume where a set-point cannot estimate its own.
        pooled = float(np.sqrt(np.sum((cnt[ok] - 1) * sd[ok] ** 2) / np.sum(cnt[ok] - 1)))
        floor = 0.1 * pooled
        per_sample = np.where(ok, np.maximum(np.nan_to_num(sd, nan=pooled), floor), pooled)
        se = per_sample / np.sqrt(cnt)
    else:
        se = np.full(n, np.nan)
    return StribeckData(vel, mean, sd, se, cnt, br, source=source, notes=tuple(notes))


def _fail(path, line, msg, column=None) -> ValueError:
    where = f"{path}:{line}" + (f", column {column!r}" if column is not None else "")
    return ValueError(f"{where}: {msg}")


def _number(text: str, path, line, column) -> float:
    s = text.strip()
    try:
        x = float(s)
    except ValueError:
        raise _fail(path, line, f"expected a number, got {s!r}", column) from None
    if not np.isfinite(x):
        raise _fail(path, line, f"expected a finite number, got {s!r}", column)
    return x


def load_stribeck_csv(path: str | os.PathLike) -> StribeckData:
    """Load steady-state friction data from a CSV (columns ``velocity_deg_s``, ``torque_nm``, optional
    ``branch``), averaging repeated samples per set-point. Units: deg/s and N*m.

    Raises ``ValueError`` naming the file and line for: a missing file, an empty file, a missing or
    unknown column, a row with the wrong number of cells, a non-numeric / NaN / infinite cell, an
    unknown branch, or fewer than two distinct velocities per branch.
    """
    from ._validate import check_delimiter, read_text

    path = Path(path)
    if not path.exists():
        raise ValueError(f"{path}: no such file (expected a CSV with columns velocity_deg_s,torque_nm[,branch])")
    text = read_text(path, "Stribeck CSV (velocity_deg_s,torque_nm[,branch])")
    rows = [(i + 1, r) for i, r in enumerate(csv.reader(text.splitlines()))]
    rows = [(i, r) for i, r in rows if r and any(c.strip() for c in r) and not r[0].lstrip().startswith("#")]
    if not rows:
        raise _fail(path, 1, "the file is empty; expected a header line 'velocity_deg_s,torque_nm[,branch]'")
    hline, header = rows[0]
    check_delimiter(path, hline, ",".join(header) if len(header) > 1 else header[0])
    header = [h.strip() for h in header]
    unknown = [h for h in header if h not in REQUIRED_COLUMNS + OPTIONAL_COLUMNS]
    if unknown:
        raise _fail(
            path, hline,
            f"unknown column(s) {unknown}; expected {list(REQUIRED_COLUMNS)} and optionally {list(OPTIONAL_COLUMNS)}",
        )
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise _fail(path, hline, f"missing column(s) {missing}; the header must name {list(REQUIRED_COLUMNS)}")
    if len(set(header)) != len(header):
        raise _fail(path, hline, f"duplicate column names in header {header}")
    if len(rows) == 1:
        raise _fail(path, hline, "header found but no data rows follow")
    iv, it = header.index("velocity_deg_s"), header.index("torque_nm")
    ib = header.index("branch") if "branch" in header else None
    vel, tor, br = [], [], []
    for line, r in rows[1:]:
        if len(r) != len(header):
            raise _fail(path, line, f"expected {len(header)} cells ({','.join(header)}), got {len(r)}")
        vel.append(_number(r[iv], path, line, "velocity_deg_s"))
        tor.append(_number(r[it], path, line, "torque_nm"))
        if ib is not None:
            b = r[ib].strip().lower()
            if b not in BRANCHES:
                raise _fail(path, line, f"expected branch 'accel' or 'decel', got {r[ib].strip()!r}", "branch")
            br.append(b)
        else:
            br.append("accel")
    vel, br = np.asarray(vel), np.asarray(br)
    for b in BRANCHES:
        m = br == b
        if m.any() and np.unique(vel[m]).size < 2:
            first = rows[1 + int(np.argmax(m))][0]
            raise _fail(
                path, first,
                f"branch {b!r} has a single velocity ({vel[m][0]:g} deg/s); identification needs at least "
                "two distinct velocity set-points",
            )
    return summarise_samples(vel, np.asarray(tor), br, source=str(path))
