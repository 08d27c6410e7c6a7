"""IDIM-LS exactly as the benchmark's MATLAB scripts (Script_IDIM_LS.m, Script_IDIM_LS_Asym_Fric.m).

1. ``q_f = filtfilt(butter(4, 100/500), qm)`` (MATLAB's filtfilt: odd reflection of
   ``3*(nfilt-1)`` samples, which scipy's ``filtfilt`` does with ``padlen=3*(max(len(a),len(b))-1)``);
2. ``dq_f = diffcent(q_f)``, ``ddq_f = diffcent(dq_f)`` (central differences, one-sided ends);
3. samples from MATLAB index ``n_border = 50`` on (Python ``49:``);
4. the observation matrix -- including ``sign(dq_f)`` -- is built at 1 kHz and then DECIMATED column
   by column with MATLAB's ``decimate(x, 10)``: Chebyshev-I (order 8, 0.05 dB, cutoff 0.8/r)
   forward-backward, then samples ``nbeg:r:nd`` with ``nbeg = r - (r*nout - nd)`` (end-aligned);
5. ``Beta = X\\y`` by least squares; relative error ``100*norm(y - X*Beta)/norm(y)``; standard
   deviations ``std(err)*sqrt(diag(inv(X'X)))``.

Decimating ``sign(dq)`` rather than taking the sign of the decimated velocity matters: the
decimated column passes through zero over a few samples at a reversal, as the filtered force does,
while the sign of the decimated velocity jumps, and regressing on it misses the published relative
error (docs/emps.md).
This is the package's only IDIM-LS; ``lugre_jax.io`` only reads the file.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._fit import covariance
from ..io import EmpsRun

N_BORDER = 49  # MATLAB's n_border = 50, 1-based


def filtfilt_matlab(b, a, x):
    from scipy import signal

    return signal.filtfilt(b, a, x, padtype="odd", padlen=3 * (max(len(a), len(b)) - 1))


def diffcent(y, pas):
    """MATLAB ``diffcent``: central differences, one-sided at both ends."""
    y = np.asarray(y, np.float64)
    return np.concatenate([[y[1] - y[0]], 0.5 * (y[2:] - y[:-2]), [y[-1] - y[-2]]]) / pas


def decimate_matlab(x, r: int):
    """MATLAB ``decimate(x, r)`` (IIR, default): Chebyshev-I order 8 forward-backward, end-aligned pick."""
    from scipy import signal

    b, a = signal.cheby1(8, 0.05, 0.8 / r)
    y = filtfilt_matlab(b, a, np.asarray(x, np.float64))
    nd = y.shape[0]
    nout = -(-nd // r)
    nbeg = r - (r * nout - nd)
    return y[nbeg - 1::r]


def sample_period(run: EmpsRun) -> float:
    """Nominal sample period: 1/(sample rate rounded to a whole Hz) -- 1e-3 s, the scripts' ``pas``."""
    return 1.0 / round(1.0 / run.dt)


def filtered_kinematics(run: EmpsRun):
    """``(q_f, dq_f, ddq_f)`` at full rate over the whole run (before the border is dropped)."""
    from scipy import signal

    pas = sample_period(run)
    fnyq = 0.5 / pas
    b, a = signal.butter(4, 100.0 / fnyq)
    q_f = filtfilt_matlab(b, a, run.qm)
    dq_f = diffcent(q_f, pas)
    return q_f, dq_f, diffcent(dq_f, pas)


@dataclasses.dataclass(frozen=True)
class IdimResult:
    """IDIM-LS estimates: ``params`` (name -> value), ``std`` (name -> std. deviation),
    ``rel_err_pct`` (the benchmark's relative force error) on ``n`` decimated samples."""

    params: dict
    std: dict
    rel_err_pct: float
    n: int
    asymmetric: bool
    t: np.ndarray = dataclasses.field(repr=False)
    y: np.ndarray = dataclasses.field(repr=False)
    y_hat: np.ndarray = dataclasses.field(repr=False)

    def to_json(self) -> dict:
        return {"params": dict(self.params), "std": dict(self.std), "rel_err_pct": self.rel_err_pct,
                "n_samples": self.n, "asymmetric": self.asymmetric,
                "units": {k: IDIM_UNITS[k.rstrip("+-")] for k in self.params}}


IDIM_UNITS = {"M": "kg", "Fv": "N*s/m", "Fc": "N", "offset": "N"}


def idim_ls(run: EmpsRun, asymmetric: bool = False) -> IdimResult:
    """The benchmark's IDIM-LS on ``run`` (see the module docstring)."""
    pas = sample_period(run)
    fnyq = 0.5 / pas
    ndecim = round(0.8 * fnyq / 40.0)
    _, dq, ddq = filtered_kinematics(run)
    s = slice(N_BORDER, None)
    dq, ddq, force, td = dq[s], ddq[s], run.force[s], run.t[s]
    sg = np.sign(dq)
    if asymmetric:
        op, om = 0.5 * (1 + sg), 0.5 * (1 - sg)
        X0 = np.column_stack([ddq, dq * op, sg * op, dq * om, sg * om])
        names = ["M", "Fv+", "Fc+", "Fv-", "Fc-"]
    else:
        X0 = np.column_stack([ddq, dq, sg, np.ones_like(dq)])
        names = ["M", "Fv", "Fc", "offset"]
    X = np.column_stack([decimate_matlab(c, ndecim) for c in X0.T])
    y = decimate_matlab(force, ndecim)
    t = decimate_matlab(td, ndecim)
    beta, *_ = np.linalg.lstsq(X, y, rcond=None)
    yhat = X @ beta
    err = y - yhat
    sd = np.std(err, ddof=1) * covariance(X, err, absolute_sigma=True).standard_errors
    return IdimResult(dict(zip(names, map(float, beta))), dict(zip(names, map(float, sd))),
                      float(100 * np.linalg.norm(err) / np.linalg.norm(y)), int(y.shape[0]),
                      asymmetric, t, y, yhat)
