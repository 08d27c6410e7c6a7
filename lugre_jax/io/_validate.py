"""Reusable input checks shared by the loaders: text decoding, CSV dialect, column names, numbers,
time base, motion, and parameter dicts.

Every check raises ``ValueError`` with one line that names the file, the line (1-based) or key, and
what was expected, so the CLI can print it as it is and exit with code 2. The checks are meant to run
before any work: a file that passes them is one the fitting code can use.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

# A parameter this large in magnitude overflows the friction and dynamics terms (squares, exp) long
# before it could describe a joint, in any units this package uses (deg or m, N*m or N).
MAX_PARAMETER_MAGNITUDE = 1e12


def read_text(path: str | os.PathLike, what: str = "file") -> str:
    """The file's text: UTF-8 (a byte-order mark is dropped), any line ends. Undecodable bytes give a
    ``ValueError`` naming the line and column of the first one."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: is a folder; expected a {what}")
    if not path.is_file():
        raise ValueError(f"{path}: no such {what}")
    data = path.read_bytes()
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        col = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise ValueError(f"{path}: line {line}, column {col}: byte 0x{data[e.start]:02x} is not UTF-8 text; "
                         f"expected a UTF-8 (or ASCII) {what}") from None


def read_json(path: str | os.PathLike, what: str = "JSON file") -> Any:
    """The parsed JSON of ``path`` (read as :func:`read_text`); a syntax error gives a
    ``ValueError`` naming the file, line and column."""
    import json

    text = read_text(path, what)
    try:
        return json.loads(text, parse_constant=lambda c: float(c))
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}:{e.lineno}:{e.colno}: invalid JSON: {e.msg}") from None


def check_delimiter(path, lineno: int, line: str, expected: str = ",") -> None:
    """Refuse a header written with another separator (``;`` or tab, e.g. a spreadsheet's locale
    export), which would otherwise read as one unknown column."""
    if expected in line:
        return
    for sep, name in ((";", "semicolons"), ("\t", "tabs")):
        if sep in line:
            raise ValueError(f"{path}: line {lineno}: the header is separated by {name}; expected "
                             f"'{expected}'-separated columns (decimal points, not commas)")


def check_unique_columns(path, lineno: int, header: Sequence[str]) -> None:
    """Each column name once (a duplicated column would be silently shadowed by its first copy)."""
    seen: dict[str, int] = {}
    for j, h in enumerate(header):
        if h in seen:
            raise ValueError(f"{path}: line {lineno}: column {h!r} appears twice (columns {seen[h] + 1} and {j + 1}); "
                             "expected unique column names")
        seen[h] = j


def check_uniform_time(path, t: np.ndarray, lines: np.ndarray | None = None, rel_tol: float = 0.25,
                       column: str = "time_s") -> float:
    """Refuse a time base whose steps differ from their median by more than ``rel_tol`` of it (gaps,
    dropped samples, irregular logging): the filters and derivatives assume a uniform step. The
    message names the line with the worst step. Returns the median step."""
    t = np.asarray(t, dtype=np.float64)
    d = np.diff(t)
    med = float(np.median(d))
    if not med > 0:
        raise ValueError(f"{path}: column {column!r}: the median time step is {med!r}; expected increasing time")
    dev = np.abs(d - med) / med
    k = int(np.argmax(dev))
    if dev[k] > rel_tol:
        ln = int(lines[k + 1]) if lines is not None else k + 2
        raise ValueError(
            f"{path}: line {ln}: column {column!r}: time step {d[k]:.6g} s from the previous sample, but the median "
            f"step is {med:.6g} s; expected a uniform time base (every step within {rel_tol:.0%} of the median); "
            "resample the recording onto a uniform grid")
    return med


def check_motion(path, velocity: np.ndarray, position: np.ndarray | None = None,
                 column: str = "velocity_deg_s", min_moving: int = 10) -> None:
    """Refuse a recording in which the joint does not move: friction cannot be fitted from rest.
    Moving = |velocity| above 1 % of its largest value, on at least ``min_moving`` samples."""
    v = np.abs(np.asarray(velocity, dtype=np.float64))
    vmax = float(np.max(v)) if v.size else 0.0
    moving = int(np.sum(v > 0.01 * vmax)) if vmax > 0 else 0
    if vmax == 0 or moving < min_moving:
        pos = "" if position is None else f", position range {float(np.ptp(position)):.3g}"
        raise ValueError(f"{path}: column {column!r}: the joint moves on {moving} of {v.size} samples "
                         f"(largest |velocity| {vmax:.3g}{pos}); expected a recording in which the joint moves "
                         f"(at least {min_moving} samples)")


def check_not_constant(path, x: np.ndarray, column: str) -> None:
    """Refuse a column that holds one value on every line (a disconnected sensor, a zero-filled copy)."""
    x = np.asarray(x)
    if x.size and np.all(x == x[0]):
        raise ValueError(f"{path}: column {column!r} is {x[0]:g} on every line; expected a measured signal")


def number(value: Any, where: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    """A finite real number (JSON int or float, not bool or string) of sane magnitude, optionally
    > 0 or >= 0; ``where`` is the ``file: key`` prefix of the message."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where}: expected a number, got {type(value).__name__} {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{where}: expected a finite number, got {value!r}")
    if abs(x) > MAX_PARAMETER_MAGNITUDE:
        raise ValueError(f"{where}: {x:g} is beyond +-{MAX_PARAMETER_MAGNITUDE:g}; expected a physical value "
                         "in the recording's units")
    if positive and not x > 0:
        raise ValueError(f"{where}: expected a value > 0, got {x:g}")
    if nonnegative and not x >= 0:
        raise ValueError(f"{where}: expected a value >= 0, got {x:g}")
    return x


FRICTION_MODELS = ("LuGre", "Stribeck", "CoulombViscous")
_PARAM_RULES = {  # key -> (positive, nonnegative, meaning)
    "J": (True, False, "inertia (or mass)"),
    "offset": (False, False, "constant torque offset"),
    "Fc": (False, True, "Coulomb friction"),
    "Fs": (False, True, "static friction"),
    "vs": (True, False, "Stribeck velocity"),
    "sigma2": (False, True, "viscous coefficient"),
    "sigma0": (True, False, "bristle stiffness"),
    "sigma1": (False, True, "bristle damping"),
    "delta": (True, False, "Stribeck exponent"),
}
_NEEDED = {"LuGre": ("J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1"),
           "Stribeck": ("J", "Fc", "Fs", "vs", "sigma2"),
           "CoulombViscous": ("J", "Fc", "sigma2")}
FS_BELOW_FC_REASON = "Fs_below_Fc_reason"


def validate_joint_params(params: Any, source: str) -> dict:
    """Check a baseline-parameter dict (the ``baseline.params`` format of a diagnose REPORT.json):
    known keys only, every value a finite number of sane magnitude, J > 0, vs > 0, sigma0 > 0,
    Fc, Fs, sigma1, sigma2 >= 0, delta > 0, and Fs >= Fc unless the dict states why not under
    ``"Fs_below_Fc_reason"`` (a rising friction curve is possible, but usually a swapped pair).
    Returns the dict without the reason key. ``source`` names the file in messages."""
    if not isinstance(params, Mapping):
        raise ValueError(f"{source}: expected a JSON object of parameter values, got {type(params).__name__}")
    known = set(_PARAM_RULES) | {"friction_model", FS_BELOW_FC_REASON}
    unknown = sorted(set(params) - known)
    if unknown:
        raise ValueError(f"{source}: unknown key(s) {unknown}; expected some of {sorted(known)}")
    kind = params.get("friction_model", "LuGre")
    if kind not in FRICTION_MODELS:
        raise ValueError(f"{source}: key 'friction_model': expected one of {list(FRICTION_MODELS)}, got {kind!r}")
    missing = [k for k in _NEEDED[kind] if k not in params]
    if missing:
        raise ValueError(f"{source}: missing key(s) {missing} for a {kind} baseline; expected {list(_NEEDED[kind])}")
    out: dict = {"friction_model": kind}
    for k, (pos, nonneg, meaning) in _PARAM_RULES.items():
        if k in params:
            out[k] = number(params[k], f"{source}: key {k!r} ({meaning})", positive=pos, nonnegative=nonneg)
    if "Fs" in out and out["Fs"] < out["Fc"]:
        reason = params.get(FS_BELOW_FC_REASON)
        if not (isinstance(reason, str) and reason.strip()):
            raise ValueError(f"{source}: key 'Fs' = {out['Fs']:g} is below 'Fc' = {out['Fc']:g}; expected Fs >= Fc "
                             f"(or give the reason under {FS_BELOW_FC_REASON!r})")
    return out


def load_params_json(path: str | os.PathLike) -> dict:
    """Read and check a ``--params`` file: a parameter dict, or a previous diagnose REPORT.json (its
    ``baseline.params`` are used; a fitted Fs < Fc is accepted there, the fit being the reason)."""
    path = Path(path)
    obj = read_json(path)
    if isinstance(obj, dict) and "baseline" in obj:
        base = obj["baseline"]
        if not isinstance(base, dict) or not isinstance(base.get("params"), dict):
            raise ValueError(f"{path}: key 'baseline': expected an object with a 'params' object "
                             "(a diagnose REPORT.json)")
        params = dict(base["params"])
        params.setdefault(FS_BELOW_FC_REASON, "fitted by a previous diagnose run")
        return validate_joint_params(params, f"{path}: baseline.params")
    return validate_joint_params(obj, str(path))
