"""The static (Stribeck) identification problem of Li et al., Electronics 2020, 9, 284, section 4.2.2,
as synthetic data with a known truth, for the optimiser studies.

Model: eq. (10) for v > 0 with delta = 2, ``F(v) = Fc + (Fs - Fc)*exp(-(v/vs)^2) + sigma2*v``
[N*m, v in deg/s, sigma2 in N*m*s/deg]. Truth: Table 1, segment 1 (Fc 0.9150, Fs 6.4808, vs 0.0315,
sigma2 2.9804). Bounds: section 4.2.2 (Fc, Fs, sigma2 in [0, 10], vs in [0, 1]). 92 velocity points
(the paper measured 92), white noise of sd 0.015 N*m (0.08 N*m per sample averaged over the paper's
30 samples per set-point). Two problems:

* ``"segment1"``: 92 points evenly over (0, 0.05] deg/s -- the paper's low-velocity segment (1), the
  problem of its Fig. 5;
* ``"whole"``: 92 points log-spaced over [0.001, 1.5] deg/s -- the whole-range problem.

The loss is vectorised over the points and costs one ``exp`` per point (``delta = 2`` is a square,
not ``exp(delta*log(...))``). ``tests/test_optimisers.py`` checks it against
``lugre_jax.Stribeck.steady_state``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from lugre_jax.friction import stribeck_curve

TRUTH_SEGMENT1 = np.array([0.9150, 6.4808, 0.0315, 2.9804])  # Fc, Fs, vs, sigma2
LOWER = np.array([0.0, 0.0, 0.0, 0.0])
UPPER = np.array([10.0, 10.0, 1.0, 10.0])
NAMES = ("Fc", "Fs", "vs", "sigma2")
NOISE_SD = 0.015  # N*m


def stribeck(p, v):
    """Eq. (10), delta = 2: torque [N*m] at velocities ``v`` [deg/s]; ``p = (Fc, Fs, vs, sigma2)`` (the
    package's one Stribeck curve)."""
    return stribeck_curve(v, p[0], p[1], p[2], p[3])


def stribeck_np(P, v):
    """Numpy version for a whole swarm ``P`` (n, 4): (n, len(v)) torques (for pyswarms)."""
    Fc, Fs, vs, s2 = (P[:, i : i + 1] for i in range(4))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return Fc + (Fs - Fc) * np.exp(-np.square(v[None, :] / vs)) + s2 * v[None, :]


class Problem:
    """Data, residual and loss (``J = 1/2 sum e^2``, the paper's objective) of one static problem."""

    def __init__(self, kind: str = "whole", n: int = 92, noise_sd: float = NOISE_SD, seed: int = 0):
        if kind == "segment1":
            v = np.linspace(0.05 / n, 0.05, n)
        elif kind == "whole":
            v = np.geomspace(0.001, 1.5, n)
        else:
            raise ValueError(f"kind must be 'segment1' or 'whole', got {kind!r}")
        rng = np.random.default_rng(seed)
        self.kind, self.truth, self.seed = kind, TRUTH_SEGMENT1.copy(), seed
        self.v = v
        self.tau = np.asarray(stribeck(jnp.asarray(self.truth), jnp.asarray(v))) + noise_sd * rng.standard_normal(n)
        self.lower, self.upper = LOWER.copy(), UPPER.copy()
        v_j, tau_j = jnp.asarray(self.v), jnp.asarray(self.tau)

        def residual_fn(p):
            return stribeck(p, v_j) - tau_j

        def loss_fn(p):
            return 0.5 * jnp.sum(jnp.square(residual_fn(p)))

        self.residual_fn, self.loss_fn = residual_fn, loss_fn

    def loss_np(self, P):
        """Loss of every row of ``P`` (n, 4), numpy; non-finite -> inf."""
        r = stribeck_np(P, self.v) - self.tau[None, :]
        J = 0.5 * np.sum(r * r, axis=1)
        return np.where(np.isfinite(J), J, np.inf)

    def describe(self, x_ref, j_ref, **more) -> dict:
        """The problem as the studies' results record it, with its reference optimum (``more``: further
        entries, before the data seed)."""
        return {"kind": self.kind, "n_points": len(self.v), "noise_sd": NOISE_SD, "truth": self.truth,
                "reference_x": x_ref, "reference_J": j_ref, **more, "data_seed": self.seed}

    def reference(self):
        """Best known optimum: LM (optimistix, box-transformed) from the truth. Returns (x, J)."""
        from lugre_jax.identify import Refine

        r = jax.jit(lambda x0: Refine("lm", max_steps=500)(x0, self.lower, self.upper, residual_fn=self.residual_fn))(
            jnp.asarray(self.truth)
        )
        return np.asarray(r.x), float(r.loss)


def study_parser(doc: str, seeds: int, key: int, out: Path) -> argparse.ArgumentParser:
    """The options of the optimiser studies on one problem: ``--seeds``, ``--data-seed`` (the noise
    draw), ``--key`` (the optimisers' random key) and ``--out``. A script adds its own options."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=seeds)
    ap.add_argument("--data-seed", type=int, default=0)
    ap.add_argument("--key", type=int, default=key)
    ap.add_argument("--out", default=str(out))
    return ap



def study_problem(args: argparse.Namespace, kind: str) -> tuple[Problem, np.ndarray, float]:
    """The problem ``kind`` drawn with ``args.data_seed`` and its reference optimum (x, J_ref)."""
    if args.seeds < 1:
        raise ValueError("--seeds must be >= 1")
    prob = Problem(kind, seed=args.data_seed)
    return (prob, *prob.reference())
