"""Whole and piecewise static (Stribeck) identification, Li et al., Electronics 2020, 9, 284, section
4.2.2 and 4.2.4 (Table 1).

* **Whole**: one Stribeck parameter set (Fc, Fs, vs, sigma2) over the full velocity range, as "most
  researchers" do (the paper's refs. 36-40).
* **Piecewise** (the paper's method): the accelerating-branch data are split at the velocity of
  minimum torque ``v_min`` and at the critical Stribeck velocity ``v_crit``, both *detected from the
  data*: ``v_min`` as the minimum of a cubic smoothing spline of the averaged torques, ``v_crit`` as
  the break point of a continuous two-line (hinge) fit above ``v_min``, i.e. where the curve turns
  from the rising Stribeck/viscous part to the stable high-velocity part. Segments 1 (below
  ``v_min``) and 2 (``v_min``..``v_crit``) are Stribeck curves, eq. (10); segment 3 (above
  ``v_crit``) is eq. (11), ``Fc + sigma2*v`` (the paper prints '/' for its Fs and vs). If the data
  hold a decelerating branch, it is identified as its own segment "1 decel". Continuity at each
  boundary is imposed softly: the fit of a segment sees one pseudo-observation equal to the
  previous segment's torque at the shared boundary (weight ``continuity_weight**2`` times that of a
  typical data point; ``continuity_weight=0`` switches it off), and the remaining jump is reported.
  The pseudo-observation treats the previous segment's estimate as exact, so it trades a little bias
  (when the truth itself jumps, as Table 1 does by 0.008 N*m at 0.05 deg/s) for a continuous curve.

The smoothing spline and the eq. (12) sum-of-sines curves of each segment (Fig. 4) are computed and
reported; ``target="sines"`` fits the Stribeck curves to eq. (12) evaluated at the set-points (the
paper's route) instead of to the averaged data (default, the statistically sound route). Standard
errors always come from the data residuals.

The loss handed to the optimisers is a pure ``jnp`` function of the parameter vector:
``0.5 * sum(((F(v_i; x) - tau_i) / se_i)**2)`` (the paper's ``J = 1/2 sum e^2`` with weights).

Units: velocity deg/s, torque N*m, vs deg/s, sigma2 N*m*s/deg. Parameter names, their order, units
and the paper's bounds are those the friction models declare (``lugre_jax/_params.py``): ``MODELS``
maps each ``kind`` to its model class and everything below is read from it.
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Literal

import jax
import jax.numpy as jnp
import numpy as np

from .._params import bounds_of, from_vector, names_of, units_of
from .._types import PRNGKeyArray
from ..friction import CoulombViscous, Segmented, Stribeck
from ..io import StribeckData
from ._smoothing import SmoothingSpline, TangentBranch, fit_smoothing_spline, fit_sum_of_sines, fit_tangent_branch
from ._uncertainty import Uncertainty, standard_errors

Kind = Literal["stribeck", "coulomb_viscous"]
# The static models of section 4.2; names, order, units and bounds come from their param() fields.
MODELS: dict[str, type[Stribeck] | type[CoulombViscous]] = {"stribeck": Stribeck, "coulomb_viscous": CoulombViscous}
NAMES: dict[str, tuple[str, ...]] = {k: names_of(m) for k, m in MODELS.items()}
UNITS: dict[str, str] = {n: u for m in MODELS.values() for n, u in units_of(m).items()}


# ----------------------------------------------------------------------------------------------
# models and objectives
# ----------------------------------------------------------------------------------------------


def curve(kind: Kind, x, v):
    """Steady-state torque [N*m] of a ``kind`` model with parameter vector ``x`` at ``v`` [deg/s]."""
    return from_vector(MODELS[kind], x).steady_state(v)


def model_of(kind: Kind, x):
    """The ``kind`` model with parameter vector ``x`` (ordered as ``NAMES[kind]``)."""
    return from_vector(MODELS[kind], np.asarray(x, dtype=np.float64))


def default_bounds(kind: Kind) -> tuple[np.ndarray, np.ndarray]:
    """The paper's identification ranges (section 4.2.2), as the model declares them: Fc, Fs, sigma2
    in [0, 10], vs in [0, 1]."""
    return bounds_of(MODELS[kind])


def auto_bounds(kind: Kind, data: StribeckData) -> tuple[np.ndarray, np.ndarray]:
    """Bounds scaled to the data (for drives far from the paper's N*m and deg/s scale), chosen by each
    parameter's declared unit: torques [N*m] in [0, 2*max|tau|], velocities [deg/s] in [0, max|v|],
    viscous coefficients [N*m*s/deg] in [0, 2*max|tau|/max|v|]."""
    tmax = float(np.max(np.abs(data.torque)))
    vmax = float(np.max(np.abs(data.velocity)))
    upper = {"N*m": 2 * tmax, "deg/s": vmax, "N*m*s/deg": 2 * tmax / vmax}
    units = units_of(MODELS[kind])
    return np.zeros(len(units)), np.array([upper[u] for u in units.values()])


def parse_bounds(spec: str | None, kind: Kind, data: StribeckData) -> tuple[np.ndarray, np.ndarray]:
    """``None``/``"paper"`` -> paper bounds; ``"auto"`` -> :func:`auto_bounds`; otherwise start from
    the paper's and override with ``"Fc=0:5,vs=0:0.5"``."""
    if spec in (None, "", "paper"):
        return default_bounds(kind)
    if spec == "auto":
        return auto_bounds(kind, data)
    lo, hi = (b.copy() for b in default_bounds(kind))
    names = NAMES[kind]
    for item in spec.split(","):
        name, _, rng = item.partition("=")
        name = name.strip()
        try:
            a, b = (float(s) for s in rng.split(":"))
        except ValueError:
            raise ValueError(f"bad bounds item {item!r}: expected NAME=LO:HI, e.g. 'Fc=0:5,vs=0:0.5'") from None
        if name not in UNITS:
            raise ValueError(f"bad bounds item {item!r}: unknown parameter {name!r}, expected one of {list(UNITS)}")
        if not a < b:
            raise ValueError(f"bad bounds item {item!r}: need LO < HI")
        if name in names:
            i = names.index(name)
            lo[i], hi[i] = a, b
    return lo, hi


def check_bounds_fit(kind: Kind, v, tau, se, lo, hi, *, what: str = "data") -> None:
    """Raise a ValueError when no parameter inside ``[lo, hi]`` can reach the torques ``tau``
    (beyond 5 standard errors), e.g. torques above 10 N*m with Fc, Fs in [0, 10] at low velocity."""
    v, tau = np.abs(np.asarray(v)), np.asarray(tau)
    se = np.where(np.isfinite(se), se, 0.0) if se is not None else np.zeros_like(tau)
    names = NAMES[kind]
    b = {n: (lo[i], hi[i]) for i, n in enumerate(names)}
    g_hi = max(b["Fc"][1], b.get("Fs", b["Fc"])[1])
    g_lo = min(b["Fc"][0], b.get("Fs", b["Fc"])[0])
    top = g_hi + b["sigma2"][1] * v
    bottom = g_lo + b["sigma2"][0] * v
    over = tau - 5 * se > top
    under = tau + 5 * se < bottom
    if over.any() or under.any():
        i = int(np.argmax(np.where(over, tau - top, bottom - tau)))
        side = "above the largest" if over[i] else "below the smallest"
        raise ValueError(
            f"the bounds {dict(zip(names, zip(lo.tolist(), hi.tolist())))} cannot fit the {what}: "
            f"{int(over.sum() + under.sum())} averaged torque(s) lie {side} torque the model can produce, "
            f"worst {tau[i]:.4g} N*m at {v[i]:.4g} deg/s (reachable {bottom[i]:.4g}..{top[i]:.4g} N*m). "
            "Check units (N*m, deg/s) and sign convention, or widen the bounds (--bounds auto or NAME=LO:HI)."
        )


def make_objective(kind: Kind, v, tau, se, anchor: tuple[float, float, float] | None = None):
    """``(loss_fn, residual_fn)``: jnp functions of the parameter vector (see module docstring).
    ``anchor = (v_b, tau_b, sd_b)`` adds the continuity pseudo-observation ``F(v_b) = tau_b``."""
    v = jnp.asarray(v, dtype=jnp.float64)
    tau = jnp.asarray(tau, dtype=jnp.float64)
    se = jnp.asarray(se, dtype=jnp.float64)

    def residual_fn(x):
        r = (curve(kind, x, v) - tau) / se
        if anchor is not None:
            vb, tb, sb = anchor
            r = jnp.concatenate([r, jnp.atleast_1d((curve(kind, x, jnp.asarray(vb)) - tb) / sb)])
        return r

    def loss_fn(x):
        val = 0.5 * jnp.sum(residual_fn(x) ** 2)
        return jnp.where(jnp.isfinite(val), val, jnp.inf)  # a failed evaluation is +inf, never NaN

    return loss_fn, residual_fn


# ----------------------------------------------------------------------------------------------
# optimiser bridge
# ----------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class _Fit:
    x: np.ndarray
    loss: float
    seed_losses: np.ndarray
    evaluations: int  # loss evaluations over all seeds (a Jacobian counts as dim evaluations)
    wall_time: float  # s, execution of all seeds, compilation excluded
    compile_time: float  # s
    steps: int  # optimiser steps per seed (max_steps; 1 for a local method)


def run_optimiser(method: str, loss_fn, residual_fn, lo, hi, *, key, n_seeds: int = 1, refine: bool = False, **settings) -> _Fit:
    """Minimise ``loss_fn`` in the box ``[lo, hi]`` with :func:`lugre_jax.identify.optimise`; returns
    the best parameters over ``n_seeds`` seeds with the cost of getting them."""
    from ._run import METHODS as ALL_METHODS, optimise

    if method not in ALL_METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(ALL_METHODS)}")
    res = optimise(method, loss_fn, jnp.asarray(lo, dtype=jnp.float64), jnp.asarray(hi, dtype=jnp.float64), key=key,
                   n_seeds=n_seeds, residual_fn=residual_fn, refine=refine, **settings)
    xs = np.atleast_2d(np.asarray(res.x))
    ls = np.where(np.isfinite(res.loss), np.asarray(res.loss, dtype=np.float64), np.inf)
    i = int(np.argmin(ls))
    return _Fit(xs[i], float(ls[i]), ls, int(np.sum(res.n_evals)), float(res.wall_time), float(res.compile_time),
                res.steps)


# ----------------------------------------------------------------------------------------------
# boundaries
# ----------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Boundaries:
    """Detected segment boundaries [deg/s] and the smoothing spline they came from."""

    v_min: float  # velocity of minimum torque
    tau_min: float  # N*m, spline value there
    v_crit: float  # critical Stribeck velocity
    spline: SmoothingSpline
    detected: bool = True


def _hinge_break(v, tau, w, v_from: float, n_grid: int = 600, min_side: int = 3) -> float:
    """Break point of the best continuous two-line fit of ``tau(v)`` for ``v > v_from``."""
    m = v > v_from
    v, tau, w = v[m], tau[m], w[m]
    if v.size < 2 * min_side + 1:
        raise ValueError(
            f"too few set-points above the minimum-torque velocity ({v.size}) to locate the critical Stribeck "
            "velocity; pass the boundaries explicitly (--edges VMIN,VCRIT) or use --scheme whole"
        )
    sw = np.sqrt(w)

    def sse(b):
        A = np.stack([np.ones_like(v), v, np.maximum(v - b, 0.0)], axis=1)
        coef, *_ = np.linalg.lstsq(A * sw[:, None], tau * sw, rcond=None)
        return float(np.sum(w * (A @ coef - tau) ** 2))

    grid = np.linspace(v[min_side - 1], v[-min_side], n_grid)
    errs = np.array([sse(b) for b in grid])
    return float(grid[int(np.argmin(errs))])


def detect_boundaries(data: StribeckData, *, n_grid: int = 20001) -> Boundaries:
    """Locate ``v_min`` (minimum of the smoothing spline of the accelerating branch) and ``v_crit``
    (hinge break point above ``v_min``) in deg/s. Uses positive velocities only."""
    main = data.select((data.branch == "accel") & (data.velocity > 0)).sorted()
    if len(main) < 5:
        raise ValueError(f"{data.source}: need at least 5 accelerating-branch set-points at positive velocity, got {len(main)}")
    spl = fit_smoothing_spline(main.velocity, main.torque, main.torque_se if main.has_weights else None, log_x=True)
    g = np.geomspace(main.velocity[0], main.velocity[-1], n_grid)
    s = spl(g)
    i = int(np.argmin(s))
    v_min = float(g[i])
    if v_min <= main.velocity[1]:
        raise ValueError(
            f"{data.source}: no Stribeck dip: the smoothed torque is lowest at {v_min:.4g} deg/s, at the slowest "
            "set-points, so there is no minimum-torque velocity to split at; use --scheme whole, or give "
            "--edges VMIN,VCRIT explicitly"
        )
    w = 1.0 / main.torque_se**2 if main.has_weights else np.ones(len(main))
    v_crit = _hinge_break(main.velocity, main.torque, w, v_min)
    return Boundaries(v_min, float(s[i]), v_crit, spl)


# ----------------------------------------------------------------------------------------------
# results
# ----------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class SegmentFit:
    """One identified segment (one row of a Table 1-style table); ``to_json()`` for the record.

    ``x`` is ordered as ``names`` (the model's declared parameters), ``loss`` is the paper's ``J``
    (weighted, 1/2 sum of squares) at ``x``; ``bounds`` the box searched.
    """

    name: str
    kind: Kind
    branch: str
    v_range: tuple[float, float]  # deg/s, the segment's validity range
    x: np.ndarray
    loss: float
    rms: float  # N*m, RMS of (model - averaged data) over the segment's set-points
    n_points: int
    evaluations: int
    wall_time: float  # s, optimiser execution over all seeds (compilation excluded)
    compile_time: float  # s
    seed_losses: np.ndarray
    uncertainty: Uncertainty
    velocity: np.ndarray  # the set-points used [deg/s]
    residual: np.ndarray  # model - data [N*m] at those set-points
    steps: int = 0  # optimiser steps per seed
    bounds: tuple[np.ndarray, np.ndarray] | None = None  # (lower, upper) searched, ordered as names

    @property
    def names(self) -> tuple[str, ...]:
        return NAMES[self.kind]

    @property
    def params(self) -> dict[str, float]:
        return dict(zip(self.names, self.x.tolist()))

    @property
    def se(self) -> dict[str, float]:
        return dict(zip(self.names, self.uncertainty.se.tolist()))

    def model(self):
        return model_of(self.kind, self.x)

    @property
    def units(self) -> dict[str, str]:
        return {n: UNITS[n] for n in self.names}

    def to_json(self) -> dict:
        """JSON-ready dict. Keys: segment, branch, model, velocity_range_deg_s, parameters (name ->
        value), units (name -> unit), bounds (name -> [lower, upper]), loss, rms_nm, n_points,
        steps, evaluations, wall_time_s, compile_time_s, seed_losses, and the uncertainty's keys
        (standard_errors, relative_standard_errors, correlation, ...)."""
        bounds = None if self.bounds is None else {
            n: [float(lo), float(hi)] for n, lo, hi in zip(self.names, *self.bounds)}
        return dict(
            segment=self.name,
            branch=self.branch,
            model="Stribeck eq. (10)" if self.kind == "stribeck" else "Coulomb + viscous eq. (11)",
            velocity_range_deg_s=list(self.v_range),
            parameters=self.params,
            units=self.units,
            bounds=bounds,
            loss=self.loss,
            rms_nm=self.rms,
            n_points=self.n_points,
            steps=self.steps,
            evaluations=self.evaluations,
            wall_time_s=self.wall_time,
            compile_time_s=self.compile_time,
            seed_losses=self.seed_losses.tolist(),
            **self.uncertainty.to_json(),
        )


@dataclasses.dataclass(frozen=True)
class Identification:
    """Result of :func:`identify_whole` or :func:`identify_piecewise`; ``to_json()`` for the record
    (what ``lugre-jax identify`` writes)."""

    scheme: str
    method: str
    target: str
    segments: tuple[SegmentFit, ...]
    boundaries: Boundaries | None
    sines: dict  # segment name -> SumOfSines (piecewise only)
    decel_curve: TangentBranch | None
    data: StribeckData
    jumps: dict  # boundary name -> torque jump [N*m] between neighbouring identified segments

    def main_segments(self) -> tuple[SegmentFit, ...]:
        return tuple(s for s in self.segments if s.branch == "accel")

    def friction_model(self):
        """The identified accelerating-branch model: a ``Stribeck`` (whole) or ``Segmented``."""
        segs = self.main_segments()
        if len(segs) == 1:
            return segs[0].model()
        # Hard switches: the identified segments are valid on their own ranges, nothing is blended.
        return Segmented(tuple(s.model() for s in segs), jnp.asarray([s.v_range[1] for s in segs[:-1]]), blend=0.0)

    def predict(self, v, branch: str = "accel"):
        """Identified steady-state torque [N*m] at ``v`` [deg/s]."""
        v = np.asarray(v, dtype=np.float64)
        out = np.asarray(self.friction_model().steady_state(jnp.asarray(v)))
        if branch == "decel":
            for s in self.segments:
                if s.branch == "decel":
                    m = np.abs(v) < s.v_range[1]
                    out = np.where(m, np.asarray(s.model().steady_state(jnp.asarray(v))), out)
        return out

    def rms(self) -> float:
        """RMS error [N*m] over all set-points used (all segments)."""
        r = np.concatenate([s.residual for s in self.segments])
        return float(np.sqrt(np.mean(r**2)))

    @property
    def wall_time(self) -> float:
        """Optimiser execution over all segments and seeds [s], compilation excluded."""
        return float(sum(s.wall_time for s in self.segments))

    @property
    def compile_time(self) -> float:
        return float(sum(s.compile_time for s in self.segments))

    def to_json(self) -> dict:
        """JSON-ready dict: scheme, method, target, units, data, rms_nm, wall_time_s, compile_time_s,
        segments (:meth:`SegmentFit.to_json` each), and for the piecewise scheme boundaries,
        continuity_jumps_nm and sum_of_sines_eq12."""
        out = dict(
            scheme=self.scheme,
            method=self.method,
            target=self.target,
            units=dict(velocity="deg/s", torque="N*m", **UNITS),
            data=dict(source=self.data.source, n_set_points=len(self.data), notes=list(self.data.notes)),
            rms_nm=self.rms(),
            wall_time_s=self.wall_time,
            compile_time_s=self.compile_time,
            segments=[s.to_json() for s in self.segments],
        )
        if self.boundaries is not None:
            b = self.boundaries
            out["boundaries"] = dict(v_min_deg_s=b.v_min, tau_min_nm=b.tau_min, v_crit_deg_s=b.v_crit, detected=b.detected)
            out["continuity_jumps_nm"] = self.jumps
        if self.sines:
            out["sum_of_sines_eq12"] = {k: s.to_json() for k, s in self.sines.items()}
        return out

    def table(self) -> str:
        """Table 1-style text table, one row per segment, value +- standard error."""
        cols = list(UNITS)
        head = f"{'segment':<9} {'v range [deg/s]':<17}" + "".join(f"{c + ' [' + UNITS[c] + ']':>26}" for c in cols)
        head += f"{'loss':>11} {'RMS [N*m]':>10} {'evals':>8} {'time [s]':>9}"
        lines = [head, "-" * len(head)]
        for s in self.segments:
            cells = []
            for c in cols:
                if c in s.names:
                    i = s.names.index(c)
                    cells.append(f"{s.x[i]:.5g} +- {s.uncertainty.se[i]:.2g}")
                else:
                    cells.append("/")
            lines.append(
                f"{s.name:<9} {f'{s.v_range[0]:.3g}-{s.v_range[1]:.3g}':<17}" + "".join(f"{c:>26}" for c in cells)
                + f"{s.loss:>11.4g} {s.rms:>10.3g} {s.evaluations:>8d} {s.wall_time:>9.2f}"
            )
        return "\n".join(lines)


# ----------------------------------------------------------------------------------------------
# schemes
# ----------------------------------------------------------------------------------------------


def _weights(d: StribeckData) -> np.ndarray:
    """Standard errors to weight by; unit weights (and residual-based SE scaling) without repeats."""
    return d.torque_se if d.has_weights else np.ones(len(d))


def _fit_segment(
    name: str, kind: Kind, branch: str, d: StribeckData, v_range, method: str, *, key, n_seeds: int,
    refine: bool, bounds: str | None, target_fn: Callable | None = None, anchor=None, settings: dict,
    data_for_bounds: StribeckData,
) -> SegmentFit:
    names = NAMES[kind]
    if len(d) < len(names):
        raise ValueError(
            f"segment {name} ({v_range[0]:.4g}-{v_range[1]:.4g} deg/s) has {len(d)} set-point(s) for {len(names)} "
            "parameters; give more data there" + ("" if name == "whole" else ", move the boundaries (--edges) or use --scheme whole")
        )
    se = _weights(d)
    lo, hi = parse_bounds(bounds, kind, data_for_bounds)
    check_bounds_fit(kind, d.velocity, d.torque, d.torque_se, lo, hi, what=f"data of segment {name}")
    target = d.torque if target_fn is None else np.asarray(target_fn(d.velocity))
    loss_fn, residual_fn = make_objective(kind, d.velocity, target, se, anchor)
    fit = run_optimiser(method, loss_fn, residual_fn, lo, hi, key=key, n_seeds=n_seeds, refine=refine, **settings)
    # Statistics always against the data, with the same continuity anchor.
    _, data_residual = make_objective(kind, d.velocity, d.torque, se, anchor)
    unc = standard_errors(data_residual, fit.x, names, absolute_sigma=False, bounds=(lo, hi))
    resid = np.asarray(curve(kind, jnp.asarray(fit.x), jnp.asarray(d.velocity))) - d.torque
    return SegmentFit(
        name=name, kind=kind, branch=branch, v_range=(float(v_range[0]), float(v_range[1])), x=np.asarray(fit.x),
        loss=fit.loss, rms=float(np.sqrt(np.mean(resid**2))), n_points=len(d), evaluations=fit.evaluations,
        wall_time=fit.wall_time, compile_time=fit.compile_time, seed_losses=fit.seed_losses, uncertainty=unc,
        velocity=d.velocity, residual=resid, steps=fit.steps, bounds=(np.asarray(lo), np.asarray(hi)),
    )


def _main_branch(data: StribeckData) -> StribeckData:
    d = data.select((data.branch == "accel") & (data.velocity > 0)).sorted()
    if len(d) < 2:
        raise ValueError(
            f"{data.source}: no accelerating-branch data at positive velocity; for a negative-direction sweep "
            "select it first (StribeckData.direction(-1), or --direction negative)"
        )
    return d


def identify_whole(
    data: StribeckData, method: str = "gapso", *, key: PRNGKeyArray, n_seeds: int = 1, refine: bool = False,
    bounds: str | None = None, kind: Kind = "stribeck", **settings,
) -> Identification:
    """One parameter set of ``kind`` (Stribeck eq. 10, or "coulomb_viscous" eq. 11) over the whole
    accelerating branch at positive velocity. Units deg/s, N*m."""
    d = _main_branch(data)
    seg = _fit_segment("whole", kind, "accel", d, (0.0, float(d.velocity[-1])), method, key=key, n_seeds=n_seeds,
                       refine=refine, bounds=bounds, settings=settings, data_for_bounds=d)
    return Identification("whole", method, "data", (seg,), None, {}, None, data, {})


@dataclasses.dataclass(frozen=True)
class Smoothed:
    """Section 4.2.2 pre-processing: boundaries, per-segment data, the spline, the decelerating
    branch tangent at ``v_min`` and the eq. (12) sum-of-sines curve of each segment (Fig. 4)."""

    boundaries: Boundaries
    segments: dict  # name -> StribeckData ("1", "2", "3", and "1 decel" when present)
    ranges: dict  # name -> (v_lo, v_hi) deg/s
    splines: dict  # name -> SmoothingSpline (accelerating-branch segments)
    sines: dict  # name -> SumOfSines
    decel_curve: TangentBranch | None


def smooth_segments(data: StribeckData, edges: tuple[float, float] | None = None) -> Smoothed:
    """Split the data at detected (or given ``edges``) boundaries and smooth each segment (deg/s, N*m)."""
    d = _main_branch(data)
    if edges is not None:
        v_min, v_crit = (float(e) for e in edges)
        if not 0 < v_min < v_crit:
            raise ValueError(f"edges must satisfy 0 < v_min < v_crit, got {edges}")
        spl = fit_smoothing_spline(d.velocity, d.torque, d.torque_se if d.has_weights else None, log_x=True)
        bnd = Boundaries(v_min, float(spl(v_min)), v_crit, spl, detected=False)
    else:
        bnd = detect_boundaries(data)
    segs = {
        "1": d.select(d.velocity < bnd.v_min),
        "2": d.select((d.velocity >= bnd.v_min) & (d.velocity < bnd.v_crit)),
        "3": d.select(d.velocity >= bnd.v_crit),
    }
    ranges = {"1": (0.0, bnd.v_min), "2": (bnd.v_min, bnd.v_crit), "3": (bnd.v_crit, float(d.velocity[-1]))}
    for k, sd in segs.items():
        need = 2 if k == "3" else 4
        if len(sd) < need:
            raise ValueError(
                f"segment {k} ({ranges[k][0]:.4g}-{ranges[k][1]:.4g} deg/s) holds {len(sd)} set-point(s), fewer than its "
                f"{need} parameters; move the boundaries (--edges VMIN,VCRIT) or use --scheme whole"
            )
    # Per-segment splines, each pinned to the overall spline at its boundaries (continuity); a segment
    # too short for its own spline uses the overall one.
    t_min, t_crit = float(bnd.spline(bnd.v_min)), float(bnd.spline(bnd.v_crit))
    pins = {"1": [(bnd.v_min, t_min)], "2": [(bnd.v_min, t_min), (bnd.v_crit, t_crit)], "3": [(bnd.v_crit, t_crit)]}
    splines = {}
    for k, sd in segs.items():
        try:
            splines[k] = fit_smoothing_spline(sd.velocity, sd.torque, sd.torque_se if sd.has_weights else None,
                                              log_x=(k == "1"), pins=pins[k])
        except ValueError:
            splines[k] = bnd.spline
    sines = {k: fit_sum_of_sines(splines[k], max(ranges[k][0], float(d.velocity[0])), ranges[k][1]) for k in segs}
    decel = data.select((data.branch == "decel") & (data.velocity > 0) & (data.velocity < bnd.v_min)).sorted()
    decel_curve = None
    if len(decel) >= 4:
        decel_curve = fit_tangent_branch(splines["1"], decel.velocity, decel.torque, bnd.v_min,
                                         decel.torque_se if decel.has_weights else None)
        sines["1 decel"] = fit_sum_of_sines(decel_curve, float(decel.velocity[0]), bnd.v_min)
        segs["1 decel"] = decel
        ranges["1 decel"] = (0.0, bnd.v_min)
    return Smoothed(bnd, segs, ranges, splines, sines, decel_curve)


def identify_piecewise(
    data: StribeckData, method: str = "gapso", *, key: PRNGKeyArray, n_seeds: int = 1, refine: bool = False,
    bounds: str | None = None, edges: tuple[float, float] | None = None, target: str = "data",
    continuity_weight: float = 3.0, **settings,
) -> Identification:
    """The paper's segmented identification (see module docstring). ``edges=(v_min, v_crit)`` [deg/s]
    overrides detection (e.g. the paper's stated (0.05, 1.2)). ``target`` is "data" or "sines"."""
    if target not in ("data", "sines"):
        raise ValueError(f"target must be 'data' or 'sines', got {target!r}")
    d = _main_branch(data)
    sm = smooth_segments(data, edges)
    bnd, segs_data, ranges, sines, decel_curve = sm.boundaries, sm.segments, sm.ranges, sm.sines, sm.decel_curve
    keys = jax.random.split(key, 4)
    med_se = float(np.median(_weights(d)))
    sd_anchor = med_se / continuity_weight if continuity_weight > 0 else None

    def tf(name):
        return None if target == "data" else sines[name]

    common = dict(method=method, n_seeds=n_seeds, refine=refine, bounds=bounds, settings=settings, data_for_bounds=d)
    s1 = _fit_segment("1", "stribeck", "accel", segs_data["1"], ranges["1"], key=keys[0], target_fn=tf("1"), **common)
    tau_vmin = float(curve("stribeck", jnp.asarray(s1.x), jnp.asarray(bnd.v_min)))
    s2 = _fit_segment("2", "stribeck", "accel", segs_data["2"], ranges["2"], key=keys[1], target_fn=tf("2"),
                      anchor=None if sd_anchor is None else (bnd.v_min, tau_vmin, sd_anchor), **common)
    tau_vcrit = float(curve("stribeck", jnp.asarray(s2.x), jnp.asarray(bnd.v_crit)))
    s3 = _fit_segment("3", "coulomb_viscous", "accel", segs_data["3"], ranges["3"], key=keys[2], target_fn=tf("3"),
                      anchor=None if sd_anchor is None else (bnd.v_crit, tau_vcrit, sd_anchor), **common)
    segments = [s1]
    jumps = {
        "v_min": float(curve("stribeck", jnp.asarray(s2.x), jnp.asarray(bnd.v_min))) - tau_vmin,
        "v_crit": float(curve("coulomb_viscous", jnp.asarray(s3.x), jnp.asarray(bnd.v_crit))) - tau_vcrit,
    }
    if decel_curve is not None:
        sdec = _fit_segment("1 decel", "stribeck", "decel", segs_data["1 decel"], ranges["1 decel"], key=keys[3],
                            target_fn=tf("1 decel"),
                            anchor=None if sd_anchor is None else (bnd.v_min, tau_vmin, sd_anchor), **common)
        segments.append(sdec)
        jumps["v_min_decel"] = float(curve("stribeck", jnp.asarray(sdec.x), jnp.asarray(bnd.v_min))) - tau_vmin
    segments += [s2, s3]
    return Identification("piecewise", method, target, tuple(segments), bnd, sines, decel_curve, data, jumps)


def identify(data: StribeckData, scheme: str = "piecewise", method: str = "gapso", **kw) -> Identification:
    """Dispatch to :func:`identify_whole` or :func:`identify_piecewise`."""
    if scheme == "whole":
        kw.pop("edges", None)
        kw.pop("target", None)
        return identify_whole(data, method, **kw)
    if scheme == "piecewise":
        return identify_piecewise(data, method, **kw)
    raise ValueError(f"unknown scheme {scheme!r}; choose 'whole' or 'piecewise'")
