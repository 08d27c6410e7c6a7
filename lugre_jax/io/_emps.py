"""Loader for the EMPS benchmark recording (DATA_EMPS.mat), preprocessed as the benchmark does.

Source: A. Janot, M. Gautier, M. Brunot, "Data set and reference models of EMPS", Nonlinear System
Identification Benchmarks workshop, 2019 (nonlinearbenchmark.org). A DC motor drives a prismatic load
through a ball screw, in closed loop, sampled at 1 kHz.

UNITS ARE SI, NOT THE PAPER'S: position m, velocity m/s, acceleration m/s^2, force N (the motor force
``gtau*vir``). The friction models of this package are unit-agnostic: fitted on EMPS, Fc is in N,
sigma2 in N*s/m, sigma0 in N/m, J is the mass in kg. The returned ``Recording.units`` says so.

Preprocessing reproduces the benchmark's IDIM-LS script step by step:

1. force = gtau * vir;
2. position low-passed by a zero-phase 4th-order Butterworth at 100 Hz (``filtfilt(butter(4, 0.2))``);
3. velocity and acceleration by central differences of the filtered position (``diffcent``);
4. the first 49 samples dropped (``n_border = 50`` in MATLAB's 1-based indexing);
5. every column decimated by ``ndecim = round(0.8*500/40) = 10`` with an 8th-order Chebyshev-I
   anti-alias filter applied forward-backward (``decimate``; scipy's ``decimate(x, 10)`` is the same
   filter and phase; the picked sample phase may differ from MATLAB's by a few samples).

:func:`read_emps_mat` is the strict raw reader (1 kHz columns, no preprocessing) used by
:mod:`lugre_jax.emps`, which holds the IDIM-LS (``lugre_jax.emps.idim_ls``, script-exact: the
observation matrix, including ``sign(dq)``, is built at 1 kHz and then decimated column by column,
as the MATLAB script does). :func:`load_emps` is for tools that take a :class:`Recording`
(``diagnose``).
"""

from __future__ import annotations

import os
from pathlib import Path

import equinox as eqx
import numpy as np

from ._recording import Recording, central_difference

SI_UNITS = {
    "time": "s",
    "position": "m",
    "velocity": "m/s",
    "acceleration": "m/s^2",
    "torque": "N",
}
EMPS_REFERENCE = {
    # Janot et al. 2019, IDIM-LS on the estimation run (decimated data): parameter values and
    # relative force error in percent.
    "symmetric": {"M": 95.1089, "Fv": 203.5034, "Fc": 20.3935, "offset": -3.1648, "rel_err_pct": 4.08},
    "asymmetric": {"Fv+": 166.71, "Fc+": 20.14, "Fv-": 240.42, "Fc-": 20.63, "rel_err_pct": 3.11},
}


EMPS_KEYS = ("t", "qm", "qg", "vir", "gtau", "kp", "kv")


class EmpsRun(eqx.Module):
    """One EMPS run as recorded (1 kHz, SI units), no preprocessing.

    ``t`` [s], ``qm`` motor position [m], ``qg`` reference position [m], ``vir`` controller output [V],
    ``gtau`` [N/V] (motor force = gtau*vir), ``kp`` [1/s] and ``kv`` [V*s/m] the loop gains, and
    ``pulses_N`` the known external force on the load [N] (validation runs; zeros when absent,
    ``has_pulses`` says which).
    """

    t: np.ndarray
    qm: np.ndarray
    qg: np.ndarray
    vir: np.ndarray
    pulses_N: np.ndarray
    gtau: float = eqx.field(static=True)
    kp: float = eqx.field(static=True)
    kv: float = eqx.field(static=True)
    has_pulses: bool = eqx.field(static=True, default=False)
    source: str = eqx.field(static=True, default="<memory>")

    @property
    def n(self) -> int:
        return int(self.t.shape[0])

    @property
    def dt(self) -> float:
        return float(np.median(np.diff(self.t)))

    @property
    def force(self) -> np.ndarray:
        """Motor force gtau*vir [N]."""
        return self.gtau * self.vir

    def slice(self, start: int, stop: int | None = None) -> "EmpsRun":
        """Samples ``start:stop`` (time keeps its absolute values)."""
        s = slice(start, stop)
        return EmpsRun(self.t[s], self.qm[s], self.qg[s], self.vir[s], self.pulses_N[s], self.gtau,
                       self.kp, self.kv, self.has_pulses, self.source)


def _loadmat(path: Path, expected: str) -> dict:
    """The variables of the .mat file ``path``; one-line ``ValueError`` naming the file when it is
    absent (``expected`` says what to pass) or not a MATLAB file."""
    import scipy.io

    if path.is_dir():
        mats = sorted(q.name for q in path.glob("*.mat"))
        raise ValueError(f"{path}: is a folder; expected the EMPS .mat file itself, {expected}"
                         + (f" (this folder holds {', '.join(mats[:3])})" if mats else ""))
    if not path.is_file():
        raise ValueError(f"{path}: EMPS file not found; pass the path to {expected} "
                         f"(default ../shared/data/emps/DATA_EMPS.mat)")
    try:
        return scipy.io.loadmat(str(path))
    except Exception as e:  # scipy raises several types for a corrupt or foreign file
        msg = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise ValueError(f"{path}: cannot read as a MATLAB .mat file ({msg})") from None


def read_emps_mat(path: str | os.PathLike) -> EmpsRun:
    """Read an EMPS .mat file (DATA_EMPS.mat layout, optional ``pulses_N``) strictly.

    Raises ``ValueError`` with one line naming the file and the missing or malformed key.
    """
    path = Path(path)
    d = _loadmat(path, f"a .mat file with {list(EMPS_KEYS)}")
    for k in EMPS_KEYS:
        if k not in d:
            raise ValueError(f"{path}: key '{k}' missing; expected an EMPS run with {list(EMPS_KEYS)} "
                             f"(+ optional pulses_N)")

    def column(k):
        a = d[k]
        if not (isinstance(a, np.ndarray) and a.dtype.kind in "fiu" and a.ndim == 2 and 1 in a.shape):
            raise ValueError(f"{path}: key '{k}' must be a real column vector, got "
                             f"{getattr(a, 'dtype', type(a))} of shape {np.shape(a)}")
        a = np.asarray(a, np.float64).ravel()
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{path}: key '{k}' has {int(np.sum(~np.isfinite(a)))} non-finite values")
        return a

    def scalar(k):
        a = d[k]
        if not (isinstance(a, np.ndarray) and a.dtype.kind in "fiu" and a.size == 1):
            raise ValueError(f"{path}: key '{k}' must be a real scalar, got shape {np.shape(a)}")
        v = float(a.ravel()[0])
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{path}: key '{k}' must be positive and finite, got {v}")
        return v

    cols = {k: column(k) for k in ("t", "qm", "qg", "vir")}
    has_pulses = "pulses_N" in d
    cols["pulses_N"] = column("pulses_N") if has_pulses else np.zeros_like(cols["t"])
    n = cols["t"].shape[0]
    for k, a in cols.items():
        if a.shape[0] != n:
            raise ValueError(f"{path}: key '{k}' has {a.shape[0]} samples, expected {n} (as 't')")
    if n < 100:
        raise ValueError(f"{path}: key 't' has {n} samples, expected at least 100")
    dt = np.diff(cols["t"])
    if not np.all(dt > 0):
        raise ValueError(f"{path}: key 't' must increase strictly (sample {int(np.argmin(dt > 0)) + 1})")
    med = float(np.median(dt))
    if np.max(np.abs(dt - med)) > 0.01 * med:
        raise ValueError(f"{path}: key 't' must be uniformly sampled (median step {med:g} s, "
                         f"largest deviation {np.max(np.abs(dt - med)):g} s)")
    return EmpsRun(cols["t"], cols["qm"], cols["qg"], cols["vir"], cols["pulses_N"], scalar("gtau"),
                   scalar("kp"), scalar("kv"), has_pulses, str(path))


def default_emps_path(data_root: str | os.PathLike = "../shared/data") -> Path:
    """Where DATA_EMPS.mat lies under a data folder laid out as the shared one (``emps/DATA_EMPS.mat``)."""
    return Path(data_root) / "emps" / "DATA_EMPS.mat"


def load_emps(path: str | os.PathLike, decimate: bool = True) -> Recording:
    """Load DATA_EMPS.mat into a :class:`Recording` in SI units (m, m/s, m/s^2, N).

    With ``decimate=False`` the 1 kHz filtered data (after step 4) are returned instead.
    """
    from scipy import signal

    path = Path(path)
    d = _loadmat(path, "DATA_EMPS.mat")
    need = ("t", "qm", "qg", "vir", "gtau")
    missing = [k for k in need if k not in d]
    if missing:
        raise ValueError(f"{path}: variables {missing} missing; expected the EMPS file with {list(need)}")
    t = np.asarray(d["t"], np.float64).ravel()
    qm = np.asarray(d["qm"], np.float64).ravel()
    qg = np.asarray(d["qg"], np.float64).ravel()
    vir = np.asarray(d["vir"], np.float64).ravel()
    gtau = float(np.asarray(d["gtau"]).ravel()[0])
    pas = 1e-3
    force = gtau * vir
    b, a = signal.butter(4, 100.0 / 500.0)
    q_f = signal.filtfilt(b, a, qm)
    dq_f = central_difference(q_f, pas)
    ddq_f = central_difference(dq_f, pas)
    sl = slice(49, None)
    cols = dict(t=t[sl], q=q_f[sl], dq=dq_f[sl], ddq=ddq_f[sl], f=force[sl], qg=qg[sl], vir=vir[sl])
    if decimate:
        ndecim = round(0.8 * 500 / 40.0)
        # time is a clock, not a signal: pick every ndecim-th sample rather than filtering it.
        cols = {k: (v[::ndecim] if k == "t" else signal.decimate(v, ndecim)) for k, v in cols.items()}
    return Recording(
        cols["t"], cols["q"], cols["dq"], cols["ddq"], cols["f"], dict(SI_UNITS), str(path),
        {"position_ref": cols["qg"], "voltage_v": cols["vir"]},
        {"acceleration_supplied": True, "gtau": gtau, "kp": float(np.ravel(d.get("kp", [np.nan]))[0]),
         "kv": float(np.ravel(d.get("kv", [np.nan]))[0]), "decimated": decimate,
         "preprocessing": "benchmark IDIM: filtfilt butter(4,100Hz), central differences, "
                          "drop 49 samples, decimate 10 (Chebyshev-I, zero-phase)" if decimate else
                          "filtfilt butter(4,100Hz), central differences, drop 49 samples"},
    )
