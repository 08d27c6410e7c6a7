"""Inverse joint model and its fit, for diagnosing model-reality mismatch on a recording.

Joint of Li et al. (Electronics 2020, 9, 284), eq. (1)-(2) with the LuGre friction of eq. (9):
``tau = J*theta_dd + F_LuGre(z, theta_d) + offset (+ candidate physics)``.

Why the INVERSE model (z driven by the measured velocity, torque predicted sample by sample) and not a
forward simulation of the closed loop:

* the residual ``tau_measured - tau_predicted`` is LINEAR in the torque noise: each residual sample is
  that sample's noise plus whatever physics is missing there, so residual structure can be located
  in time, velocity, position and direction, and standard (block-corrected) statistics apply;
* there is NO CLOSED-LOOP DRIFT: a forward simulation integrates small model errors into position and
  velocity errors that the controller then reacts to, smearing a local mismatch over the whole run
  and making the residual depend on the (unknown) controller;
* it needs only the recording, not the controller, and it is cheap (one ``lax.scan``), so the model
  can be fitted by gradient (Levenberg-Marquardt) in seconds on 100k samples.

The price is errors-in-variables: velocity and acceleration are taken as measured (acceleration from
low-passed velocity by central differences, as the EMPS benchmark does). With encoder-grade position
that error is small compared to the torque noise.

Bristle state: ``dz/dt = v - sigma0*|v|*z/g(v)`` relaxes with rate ``sigma0*|v|/g(v)``, which at high
speed exceeds the sampling rate (stiff). Holding ``v`` at the mid-interval value, the ODE is linear in
``z`` and is integrated EXACTLY over each sample interval:
``z+ = z*exp(-r*h) + v*h*phi1(r*h)``, ``phi1(x) = (1 - exp(-x))/x`` -- unconditionally stable, exact
for piecewise-constant velocity, and differentiable in every parameter.

Units: whatever the recording's are (the model is unit-agnostic); for CSV recordings the paper's
(deg, deg/s, N*m; J in N*m*s^2/deg, sigma0 in N*m/deg, sigma1/sigma2 in N*m*s/deg), for EMPS SI.
"""

from __future__ import annotations

import abc
import dataclasses
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .. import _fit
from ..friction import (AbstractFrictionModel, CoulombViscous, LuGre, Stribeck, bristle_coefficients,
                        stribeck_curve)
from .._results import RESULTS, promote, result_name
from .._types import Array, Float
from ._config import DiagnoseConfig


class Kinematics(eqx.Module):
    """Measured joint kinematics on the sample grid (recording units)."""

    t: Float[Array, " n"]
    theta: Float[Array, " n"]
    v: Float[Array, " n"]
    a: Float[Array, " n"]
    h: Float[Array, " n-1"]  # sample intervals
    dpath: Float[Array, " n-1"]  # position increments that drive the bristle state
    z0_sign: Float[Array, ""]  # direction of the initial bristle deflection (0: starts at rest)


def kinematics_of(rec) -> Kinematics:
    """Kinematics of a recording. The bristle state is driven by the POSITION increments, not by the
    integral of the velocity: LuGre's z is a function of the path (dz/dtheta = 1 - sigma0*sign(v)*z/g),
    so integrating it along the measured position keeps z exact to the encoder's resolution, while
    integrating a noisy velocity makes z a random walk."""
    v = np.asarray(rec.velocity)
    V = float(np.percentile(np.abs(v), 99)) or 1.0
    s0 = float(np.sign(v[0])) if abs(v[0]) > 0.02 * V else 0.0
    return Kinematics(
        jnp.asarray(rec.time), jnp.asarray(rec.position), jnp.asarray(rec.velocity),
        jnp.asarray(rec.acceleration), jnp.asarray(np.diff(rec.time)),
        jnp.asarray(np.diff(np.asarray(rec.position, float))), jnp.asarray(s0),
    )


class Terms(eqx.Module):
    """What candidate physics may change before friction is evaluated: the friction law and the
    velocity that drives it (e.g. the load-side velocity behind a backlash)."""

    friction: AbstractFrictionModel
    v_friction: Float[Array, " n"]
    friction_gain: Float[Array, " n"]  # multiplies the friction torque (engagement, warming, ...)
    dpath: Float[Array, " n-1"]  # position increments driving the bristles (see kinematics_of)


@dataclasses.dataclass(frozen=True)
class Context:
    """What a candidate may read to guess its start, judge its fit and describe itself.

    ``rec``: the conditioned recording; ``kin``: its kinematics; ``baseline``: the current joint
    model; ``residual``: its residual (0 on unresolved samples); ``scales``: data scales
    (:func:`data_scales`); ``position_peaks``: the residual's position-periodogram peaks, strongest
    first; ``time_peak_hz``: its time periodogram's strongest ordinate; ``friction_torque`` and
    ``inertial_torque``: the current model's parts per sample; ``n_reversals``; ``to_rad``: the
    position unit in radians; ``position_resolution``: encoder step or position noise;
    ``accel_bandwidth_hz``: bandwidth of the conditioned acceleration; ``config``: the diagnosis's
    settings (:class:`DiagnoseConfig`)."""

    rec: object
    kin: "Kinematics"
    baseline: "JointModel"
    residual: np.ndarray
    scales: dict
    position_peaks: list
    time_peak_hz: float
    friction_torque: np.ndarray
    inertial_torque: np.ndarray
    n_reversals: int
    to_rad: float
    position_resolution: float = 0.0
    accel_bandwidth_hz: float = float("inf")
    config: DiagnoseConfig = dataclasses.field(default_factory=DiagnoseConfig)

    @property
    def units(self) -> dict:
        return self.rec.units

    def replace(self, **kw) -> "Context":
        return dataclasses.replace(self, **kw)


class AbstractCandidate(eqx.Module):
    """A piece of physics that extends the joint model's predicted torque.

    Final subclasses declare their parameters with :func:`cparam` (bounds relative to data scales),
    a class-level ``id`` and plain-language ``explanation``.
    """

    @abc.abstractmethod
    def prepare(self, terms: Terms, kin: Kinematics) -> Terms:
        """Modify the friction law / friction velocity (identity for purely additive physics)."""

    @abc.abstractmethod
    def extra_torque(self, kin: Kinematics, terms: Terms, friction_torque, inertial_torque) -> Float[Array, " n"]:
        """Additive torque [recording torque unit] (zeros for physics acting through ``prepare``);
        ``terms`` are the prepared friction terms, for physics that re-evaluates part of the friction."""

    # True when the starting points are searched on the residual (a period, a frequency): the
    # calibration then repeats that search on every null draw (look-elsewhere effect)
    searches_residual: ClassVar[bool] = False

    @abc.abstractmethod
    def initial_guesses(self, ctx: Context) -> list["AbstractCandidate"]:
        """Starting points for fitting this candidate, from the data scales and located residual."""

    @abc.abstractmethod
    def applicable(self, ctx: Context) -> bool:
        """Whether the candidate makes sense for this recording/baseline (e.g. gravity needs angles)."""

    # (profiled, linear): a parameter the torque depends on only through events it moves between
    # samples (a dead band's width: the fit's objective is flat between them, so LM leaves it where
    # it starts), found by a profile over a fine grid around its value instead, with the parameter
    # the torque is proportional to solved by least squares at each grid value (:func:`fit`)
    profiled: ClassVar[tuple[str, str] | None] = None

    # parameters that must differ from these null values, by >= 3 standard errors of the joint fit,
    # for the candidate to be named (identifiable on the recording's excitation)
    key_params: ClassVar[dict] = {}

    def implausible(self, ctx: Context) -> str | None:
        """Why the FITTED candidate is not physically plausible on this recording, or None."""
        return None

    # True for a linear time-invariant response to the motion: at the motion's spectral lines it is
    # confounded with a linear error of the conditioned kinematics (a filter's gain or delay), so it
    # is identifiable only against that error's lines (:func:`._attribute.kinematic_lines`)
    linear_in_motion: ClassVar[bool] = False

    def beyond_resolution(self, ctx: Context) -> bool:
        """Whether the FITTED candidate is implausible because its shape lies beyond what the
        conditioned kinematics resolve: it then fits structure the smoothing leaves, which the
        other candidates of the selection step must not be credited with either."""
        return False

    @abc.abstractmethod
    def describe(self, ctx: Context) -> dict:
        """Parameters in plain units plus derived quantities (e.g. period, amplitude) for the report."""


def cparam(scale: str, lo: float, hi: float, log: bool = False, **kw):
    """A candidate parameter with bounds ``[lo, hi]`` in multiples of data scale ``scale``.

    Scales (from :func:`data_scales`): ``T`` torque, ``V`` velocity, ``A`` acceleration, ``P`` position
    span, ``D`` duration, ``1`` dimensionless, ``T/V``, ``T/A``, ``T/P``, ``1/D``, ``fs`` sample rate.
    """
    return eqx.field(converter=jnp.asarray, metadata=dict(scale=scale, rel_bounds=(lo, hi), log=log), **kw)


def data_scales(rec) -> dict[str, float]:
    tau = np.asarray(rec.torque)
    v = np.abs(np.asarray(rec.velocity))
    a = np.abs(np.asarray(rec.acceleration))
    T = float(np.percentile(np.abs(tau - np.median(tau)), 99)) or 1.0
    V = float(np.percentile(v, 99)) or 1.0
    A = float(np.percentile(a, 99)) or 1.0
    P = float(np.ptp(rec.position)) or 1.0
    D = float(rec.time[-1] - rec.time[0])
    fs = 1.0 / float(np.median(np.diff(rec.time)))
    s = {"T": T, "V": V, "A": A, "P": P, "D": D, "1": 1.0, "fs": fs}
    s.update({"T/V": T / V, "T/A": T / A, "T/P": T / P, "1/D": 1.0 / D})
    return s


def lugre_torque(f: LuGre, v: Float[Array, " n"], h: Float[Array, " n-1"], z0=None,
                 dpath=None, z0_sign=None) -> Float[Array, " n"]:
    """LuGre torque along a measured motion, exact-exponential bristle update (see module doc).

    ``dpath``: the position increments over each interval (default ``v_mid*h``); z follows the path,
    ``g`` is evaluated at the mid-interval velocity. ``z0`` default: ``z0_sign*g/sigma0`` (steady
    sliding in the initial direction; 0 = at rest), with ``z0_sign`` default ``sign(v[0])``."""
    g = f.g(v)
    if z0 is None:
        s0 = jnp.sign(v[0]) if z0_sign is None else z0_sign
        z0 = s0 * g[0] / f.sigma0
    vint = 0.5 * (v[:-1] + v[1:])
    if dpath is None:
        dpath = vint * h
    e, c = bristle_coefficients(dpath, f.g(vint), f.sigma0)
    # z_{k+1} = e_k*z_k + c_k: affine in z with coefficients set by the measured velocity alone.
    # (jax.lax.associative_scan would make it log-depth, but compiles much slower under the LM's
    # forward-mode Jacobian; a one-shot diagnosis pays every compilation, so a sequential scan.)
    _, zs = jax.lax.scan(lambda z, ec: (ec[0] * z + ec[1],) * 2, z0, (e, c))
    z = jnp.concatenate([jnp.reshape(z0, (1,)), zs])
    dz = v - f.sigma0 * jnp.abs(v) * z / g
    return f.sigma0 * z + f.sigma1 * dz + f.sigma2 * v




def friction_torque(f: AbstractFrictionModel, v, h, dpath=None, z0_sign=None):
    if isinstance(f, LuGre):
        return lugre_torque(f, v, h, dpath=dpath, z0_sign=z0_sign)
    return f.steady_state(v)


class JointModel(eqx.Module):
    """Inverse joint model: ``tau = J*a + F(v) + offset + sum(candidate torques)`` (recording units)."""

    J: Float[Array, ""]
    friction: AbstractFrictionModel
    offset: Float[Array, ""]
    candidates: tuple = ()

    def parts(self, kin: Kinematics):
        """(inertial torque, friction torque, total predicted torque)."""
        terms = Terms(self.friction, kin.v, jnp.ones_like(kin.v), kin.dpath)
        for c in self.candidates:
            terms = c.prepare(terms, kin)
        F = terms.friction_gain * friction_torque(terms.friction, terms.v_friction, kin.h, terms.dpath,
                                                  kin.z0_sign)
        inertial = self.J * kin.a
        tau = inertial + F + self.offset
        for c in self.candidates:
            tau = tau + c.extra_torque(kin, terms, F, inertial)
        return inertial, F, tau

    def predict(self, kin: Kinematics) -> Float[Array, " n"]:
        return self.parts(kin)[2]


# ---------------------------------------------------------------------------------------------
# Bounded parameter space: x = lo + (hi - lo)*sigmoid(u)  (or the same in log-space)


def _get(model, path):
    x = model
    for p in path:
        x = x[p] if isinstance(p, int) else getattr(x, p)
    return x


@dataclasses.dataclass(frozen=True)
class Spec:
    name: str
    path: tuple  # attribute names / tuple indices from the JointModel to the leaf
    lo: float
    hi: float
    log: bool = False

    def where(self, model):
        return _get(model, self.path)


# A start on (or within this share of) a bound is moved this far inside: LM has no gradient to
# leave a saturated sigmoid.
START_EDGE = 1e-6


class FitSpace:
    """Free parameters of a :class:`JointModel`, each mapped from an unbounded ``u`` by a sigmoid
    onto its bounds (in log space for ``Spec.log``): ``bounds`` is that
    :class:`~lugre_jax._fit.LogBoxTransform`.

    The paths are static (hashable, so compiled fits are reused across recordings of one shape);
    the bounds are data and travel as arrays.
    """

    def __init__(self, specs: list[Spec]):
        self.specs = list(specs)
        lo = np.array([s.lo for s in self.specs], float)
        hi = np.array([s.hi for s in self.specs], float)
        if np.any(lo >= hi):
            bad = [s.name for s in self.specs if not s.lo < s.hi]
            raise ValueError(f"empty bounds for {bad}")
        self.bounds = _fit.LogBoxTransform(lo, hi, [s.log for s in self.specs], edge=START_EDGE)
        self.paths = tuple(s.path for s in self.specs)

    @property
    def names(self):
        return [s.name for s in self.specs]

    def values(self, model: JointModel):
        return jnp.asarray([float(s.where(model)) for s in self.specs])

    def to_model(self, template: JointModel, u) -> JointModel:
        return _with_values(template, self.paths, self.bounds.to_box(u))

    def to_u(self, model: JointModel):
        return self.bounds.from_box(self.values(model))

    def as_dict(self, model: JointModel) -> dict[str, float]:
        return {s.name: float(s.where(model)) for s in self.specs}


def _with_values(template, paths, x):
    """``template`` with the leaves at ``paths`` set to the entries of ``x``."""
    return eqx.tree_at(lambda m: [_get(m, p) for p in paths], template, [x[i] for i in range(len(paths))])


def baseline_specs(model: JointModel, scales: dict, fit_offset: bool) -> list[Spec]:
    T, V, A, P = scales["T"], scales["V"], scales["A"], scales["P"]
    specs = [Spec("J", ("J",), 0.0, max(5 * T / A, 3 * float(model.J)))]
    f = model.friction
    specs += [Spec("Fc", ("friction", "Fc"), 0.0, 2 * T)]
    if isinstance(f, (LuGre, Stribeck)):
        specs += [Spec("Fs", ("friction", "Fs"), 0.0, 4 * T),
                  Spec("vs", ("friction", "vs"), 1e-4 * V, V, True)]
    specs += [Spec("sigma2", ("friction", "sigma2"), 0.0, max(5 * T / V, 3 * float(f.sigma2)))]
    if isinstance(f, LuGre):
        specs += [Spec("sigma0", ("friction", "sigma0"), T / (0.1 * P), T / (1e-8 * P), True),
                  Spec("sigma1", ("friction", "sigma1"), 0.0, 100 * T / V)]
    if fit_offset:
        specs += [Spec("offset", ("offset",), -T, T)]
    return specs


def candidate_specs(model: JointModel, k: int, scales: dict) -> list[Spec]:
    """Specs of the parameters of ``model.candidates[k]``."""
    c = model.candidates[k]
    out = []
    for fld in dataclasses.fields(c):
        md = fld.metadata
        if "rel_bounds" not in md:
            continue
        s = 1.0
        for part in md["scale"].split("*"):
            num, _, den = part.partition("/")
            s *= scales.get(num, 1.0) if num != "1" else 1.0
            if den:
                s /= scales[den] if den != "D" else scales["D"]
        lo, hi = md["rel_bounds"]
        name = fld.name
        out.append(Spec(f"{c.id}.{name}", ("candidates", k, name), lo * s, hi * s, md["log"]))
    return out


def clip_into(space: FitSpace, model: JointModel) -> JointModel:
    """Move every free parameter strictly inside its bounds."""
    return space.to_model(model, space.to_u(model))


# ---------------------------------------------------------------------------------------------
# Fitting


def _residual(x, paths, template, kin, tau, w, scale):
    """Weighted residual of the model with the parameters at ``paths`` set to ``x``."""
    return w * (tau - _with_values(template, paths, x).predict(kin)) / scale


def _residual_fn(u, args):
    """:func:`_residual` in the fit's unbounded coordinates ``u``."""
    paths, bounds, template, kin, tau, w, scale = args
    return _residual(bounds.to_box(u), paths, template, kin, tau, w, scale)


@eqx.filter_jit
def _lm(x0, paths, bounds, template, kin, tau, w, scale, max_steps):
    x, sol = _fit.least_squares(lambda x: _residual(x, paths, template, kin, tau, w, scale), x0, bounds,
                                rtol=1e-7, atol=1e-9, max_steps=max_steps)
    return x, jnp.all(jnp.isfinite(sol.value)), sol.result, sol.stats["num_steps"]


# Compiled functions see the kinematics padded to a multiple of BUCKET samples, so recordings of
# different lengths share their compilations (compiling the fits takes longer than running them).
# The padding holds the joint still at its last position and time (zero velocity, acceleration and
# path; intervals of the mean length), and every model is causal along the samples, so the samples
# before it are unchanged; its samples carry zero weight and are cut from every output.
BUCKET = 8192


def bucket(n: int) -> int:
    return -(-int(n) // BUCKET) * BUCKET


def pad_kinematics(kin: Kinematics) -> Kinematics:
    n = kin.v.shape[0]
    p = bucket(n) - n
    if p == 0:
        return kin

    def ext(x, value):
        return jnp.concatenate([x, jnp.full((p,), value, dtype=x.dtype)])

    return Kinematics(ext(kin.t, kin.t[-1]), ext(kin.theta, kin.theta[-1]), ext(kin.v, 0.0), ext(kin.a, 0.0),
                      ext(kin.h, jnp.mean(kin.h)), ext(kin.dpath, 0.0), kin.z0_sign)


def pad(x, n: int | None = None):
    """A per-sample array padded with zeros to its bucket (or to ``n``)."""
    x = jnp.asarray(x)
    m = bucket(x.shape[0]) if n is None else n
    return jnp.concatenate([x, jnp.zeros((m - x.shape[0],) + x.shape[1:], dtype=x.dtype)]) if m > x.shape[0] else x


@eqx.filter_jit
def _predict(model, kin):
    return model.predict(kin)


@eqx.filter_jit
def _parts_padded(model, kin):
    return model.parts(kin)


def _parts(model, kin):
    """(inertial torque, friction torque, total predicted torque) of ``model`` along ``kin``."""
    n = kin.v.shape[0]
    return tuple(x[:n] for x in _parts_padded(model, pad_kinematics(kin)))


def predict(model: JointModel, kin: Kinematics) -> Float[np.ndarray, " n"]:
    n = kin.v.shape[0]
    return np.asarray(_predict(model, pad_kinematics(kin)))[:n]


def static_curve_basis(model: JointModel, specs: list[Spec], v) -> np.ndarray:
    """Derivatives of the friction's steady-state curve, signed by the direction of motion, with
    respect to the baseline's static parameters among ``specs`` (n x k; the dynamic ones have none):
    the shapes along the speed axis that a change of the baseline's own parameters can make."""
    paths = tuple(sp.path for sp in specs if sp.path[0] == "friction")
    if not paths:
        return np.zeros((np.size(v), 0))
    v = jnp.asarray(v, float)

    def folded(x):
        return _with_values(model, paths, x).friction.steady_state(v) * jnp.sign(v)

    x0 = jnp.asarray([float(_get(model, p)) for p in paths])
    G = np.asarray(jax.jacfwd(folded)(x0))
    return G[:, np.any(G != 0, axis=0)]


# A profiled parameter's grid: this factor either side of its value (the candidates' starts are a
# factor ~3 apart, so the nearest start is within it of the optimum), in steps of PROFILE_STEP (the
# width is then known to ~2 %, well inside its standard error on a concealed effect). One grid length
# for every call (one compilation); clipped by a bound, the grid is finer.
PROFILE_SPAN = 3.0
PROFILE_STEP = 1.04
PROFILE_POINTS = int(np.ceil(2 * np.log(PROFILE_SPAN) / np.log(PROFILE_STEP))) + 1


def profiled_paths(model: JointModel) -> dict[int, tuple[tuple, tuple]]:
    """Candidate index -> the paths of its (profiled, linear) parameters
    (``AbstractCandidate.profiled``), for the candidates that declare them."""
    return {k: tuple(("candidates", k, name) for name in type(c).profiled)
            for k, c in enumerate(model.candidates) if type(c).profiled is not None}


@eqx.filter_jit
def _profile_columns(model, k, names, values, kin):
    """Predicted torque with candidate ``k``'s profiled parameter at each of ``values`` and its
    linear parameter at 1 (rows), and with the linear parameter at 0 (the torque without it)."""
    p_name, g_name = names
    c = model.candidates[k]

    def at(p, g):
        return eqx.tree_at(lambda m: (getattr(m.candidates[k], p_name), getattr(m.candidates[k], g_name)),
                           model, (jnp.asarray(p, getattr(c, p_name).dtype),
                                   jnp.asarray(g, getattr(c, g_name).dtype))).predict(kin)

    return jax.vmap(lambda p: at(p, 1.0))(values), at(values[0], 0.0)


def _profiled(model: JointModel, space: FitSpace, kin: Kinematics, tau, weights) -> tuple[JointModel, bool]:
    """``model`` with each candidate's profiled parameter (``profiled``) moved to the best value of
    a log grid around it within its bounds, the linear parameter solved by weighted least squares
    (clipped to its bounds) at each; the current value is on the grid, so the weighted error never
    rises. Parameters the fit holds fixed (not in ``space``) are left. Also returns whether any
    profiled value moved."""
    by_path = {s.path: s for s in space.specs}
    moved = False
    for k, (path_p, path_g) in profiled_paths(model).items():
        sp, sg = by_path.get(path_p), by_path.get(path_g)
        if sp is None or sg is None:
            continue
        c, names = model.candidates[k], (path_p[-1], path_g[-1])
        p0 = float(getattr(c, names[0]))
        lo, hi = max(sp.lo, p0 / PROFILE_SPAN), min(sp.hi, p0 * PROFILE_SPAN)
        values = np.concatenate([[p0], np.geomspace(lo, hi, PROFILE_POINTS)]) if lo < hi else np.array([p0, p0])
        n_kin = kin.v.shape[0]
        with_g, without = _profile_columns(model, k, names, jnp.asarray(values), pad_kinematics(kin))
        X = np.asarray(with_g)[:, :n_kin] - np.asarray(without)[None, :n_kin]
        r = np.asarray(tau, float) - np.asarray(without)[:n_kin]
        w = np.asarray(weights, float)
        xx, xr = np.einsum("ij,j,ij->i", X, w, X), X @ (w * r)
        g = np.clip(xr / np.maximum(xx, 1e-300), sg.lo, sg.hi)
        sse = np.einsum("ij,j,ij->i", r[None] - g[:, None] * X, w, r[None] - g[:, None] * X)
        sse = np.where(np.isfinite(sse), sse, np.inf)
        i = int(np.argmin(sse))
        if not np.isfinite(sse[i]):
            continue
        moved = moved or values[i] != p0
        model = eqx.tree_at(lambda m: (getattr(m.candidates[k], names[0]), getattr(m.candidates[k], names[1])),
                            model, (jnp.asarray(values[i], getattr(c, names[0]).dtype),
                                    jnp.asarray(g[i], getattr(c, names[1]).dtype)))
    return model, moved


def _lm_fit(model, space, kin, tau, w, scale, max_steps):
    x, ok, result, steps = _lm(space.values(model), space.paths, space.bounds, model, pad_kinematics(kin), pad(tau),
                               pad(w), scale, max_steps)
    if not bool(ok):
        return model, {"result": result_name(RESULTS.nonfinite), "steps": int(steps)}
    return _with_values(model, space.paths, x), {"result": result_name(promote(result)), "steps": int(steps)}


def fit(model: JointModel, space: FitSpace, kin: Kinematics, tau, weights, max_steps: int = 200):
    """Levenberg-Marquardt (:func:`lugre_jax._fit.least_squares`) on the weighted residual; returns
    (model, info).

    ``weights`` is 1 on training samples and 0 on held-out ones. A solver failure is reported in
    ``info['result']`` (never a silent NaN): the model returned is then the best finite one seen.
    A candidate's profiled parameter (``AbstractCandidate.profiled``) is set by a profile on the
    same weighted samples before LM and again after it (the baseline LM moved shifts its optimum),
    with LM repeated when that moves it.
    """
    tau = jnp.asarray(tau)
    w = jnp.asarray(weights, dtype=tau.dtype)
    scale = jnp.asarray(float(np.std(np.asarray(tau)[np.asarray(weights) > 0])) or 1.0)
    profiles = bool(profiled_paths(model))
    if profiles:
        model, _ = _profiled(model, space, kin, tau, weights)
    fitted, info = _lm_fit(model, space, kin, tau, w, scale, max_steps)
    if profiles and info["result"] != result_name(RESULTS.nonfinite):
        again, moved = _profiled(fitted, space, kin, tau, weights)
        if moved:
            fitted, info2 = _lm_fit(again, space, kin, tau, w, scale, max_steps)
            info = {"result": info2["result"], "steps": info["steps"] + info2["steps"]}
    return fitted, info


@eqx.filter_jit
def _jac_u(u, paths, bounds, template, kin, tau, w, scale):
    return jax.jacfwd(_residual_fn)(u, (paths, bounds, template, kin, tau, w, scale))


# A parameter within this share of its box (in the fit's, log or linear, units) from a bound is
# held there by the bound, not by the data: LM in sigmoid coordinates stops short of a bound.
SATURATED = 1e-4


def standard_errors(model: JointModel, space: FitSpace, kin: Kinematics, tau, weights,
                    kappa: float = 1.0, nuisance=None) -> dict[str, tuple[float, float]]:
    """Each free parameter's value and standard error from the weighted least-squares Jacobian
    (:func:`lugre_jax._fit.covariance` on the training samples, noise variance from the residual
    times the long-run variance factor ``kappa``): name -> (value, se). Parameters at a bound, or
    along a direction the data do not inform, get se = inf. ``nuisance``: columns (n, m) fitted
    alongside (one Gauss-Newton step from ``model``): each value is then what remains of it with
    the nuisance fitted too, and its standard error counts the directions it shares with them."""
    tau = jnp.asarray(tau)
    w = jnp.asarray(weights, dtype=tau.dtype)
    u = space.to_u(model)
    Jm = np.asarray(_jac_u(u, space.paths, space.bounds, model, pad_kinematics(kin), pad(tau), pad(w),
                           jnp.asarray(1.0)))[: tau.shape[0]]
    p = Jm.shape[1]
    if nuisance is not None:
        Jm = np.column_stack([Jm, np.asarray(w)[:, None] * np.asarray(nuisance, float).reshape(tau.shape[0], -1)])
    r = np.asarray(w) * (np.asarray(tau) - np.asarray(predict(model, kin)))
    train = np.asarray(weights) > 0
    c = _fit.covariance(Jm[train], r[train], variance_factor=kappa)
    # the covariance is in u; dx/du carries it to the parameters (the transform is elementwise)
    vals, dxdu = (np.asarray(a) for a in jax.jvp(space.bounds.to_box, (u,), (jnp.ones_like(u),)))
    with np.errstate(invalid="ignore"):
        se = np.where(space.bounds.at_bounds(vals, SATURATED), np.inf, np.abs(dxdu) * c.standard_errors[:p])
    if nuisance is not None:
        du = np.linalg.lstsq(Jm[train], -r[train], rcond=None)[0][:p]
        vals = np.asarray(space.bounds.to_box(u + jnp.asarray(du, dtype=u.dtype)))
    return {s.name: (float(v), float(e)) for s, v, e in zip(space.specs, vals, se)}


# ---------------------------------------------------------------------------------------------
# Validation split: interleaved time blocks


def block_ids(t: np.ndarray, block_s: float | None = None, min_blocks: int = 25) -> np.ndarray:
    """Index of the ~``block_s``-long time block of every sample (default ~1 s, at least 25 blocks)."""
    t = np.asarray(t)
    D = t[-1] - t[0]
    block_s = block_length(t, block_s, min_blocks)
    return np.minimum(((t - t[0]) / block_s).astype(int), int(D / block_s))


def block_length(t: np.ndarray, block_s: float | None = None, min_blocks: int = 25) -> float:
    """The length of :func:`block_ids`' blocks: ``block_s``, or ~1 s with at least ``min_blocks``."""
    return float(block_s) if block_s is not None else min(1.0, float(t[-1] - t[0]) / min_blocks)


VALIDATION_EVERY, VALIDATION_PHASE = 5, 2
_PHASE_SEED = 0


def block_phase(blocks: np.ndarray, every: int = VALIDATION_EVERY) -> np.ndarray:
    """The phase (cross-validation fold) of every sample's time block: each run of ``every``
    consecutive blocks gives each phase one block, in an order drawn at random (seeded) per run.
    Interleaved as ``blocks % every`` is, so no regime is lost to a phase, but an excitation periodic
    in a whole number of blocks (a point-to-point move every 5 s with 1-s blocks) does not put all of
    its reversals, steps and the ringing after them in the same phase: each lands in a phase at
    random, so every phase's held-out test sees its share of them."""
    b = np.asarray(blocks, int)
    runs = int(b.max()) // every + 1 if b.size else 0
    order = np.argsort(np.random.default_rng(_PHASE_SEED).random((runs, every)), axis=1)
    # no two neighbouring blocks in one phase (a held-out stretch twice a block's length, a regime the
    # fit may not see): a run that would begin with the phase the run before it ends with swaps its
    # first two blocks
    for k in range(1, runs):
        if order[k, 0] == order[k - 1, -1]:
            order[k, :2] = order[k, 1::-1]
    return order.ravel()[b]


def validation_mask(blocks: np.ndarray, every: int = VALIDATION_EVERY, phase: int = VALIDATION_PHASE) -> np.ndarray:
    """True on held-out samples: the time blocks of ``phase`` (:func:`block_phase`; one in every
    ``every``, interleaved, so no regime is lost; :func:`phase_off_events` chooses it)."""
    return block_phase(blocks, every) == phase


def event_starts(mask: np.ndarray) -> np.ndarray:
    """True where a run of ``mask`` begins (an event: a reversal, a burst of acceleration)."""
    m = np.asarray(mask, bool)
    return m & ~np.concatenate([[False], m[:-1]])


def phases_holding_events(blocks: np.ndarray, events, every: int = VALIDATION_EVERY, *, max_share: float,
                          alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """Per block phase: the largest share of any kind of event (``events``: boolean masks of event
    starts) that falls in it, and whether that phase holds too many of some kind -- more than
    ``max_share`` of them, and more than chance alignment allows (binomial tail below ``alpha``, so a
    handful of events is not judged; :class:`DiagnoseConfig`'s ``max_event_share`` and
    ``event_alpha``)."""
    from scipy.stats import binom

    phase = block_phase(blocks, every)
    worst, held = np.zeros(every), np.zeros(every, bool)
    for ev in events:
        ev = np.asarray(ev, bool)
        n = int(ev.sum())
        if n == 0:
            continue
        k = np.bincount(phase[ev], minlength=every)[:every]
        worst = np.maximum(worst, k / n)
        held |= (k > max_share * n) & (binom.sf(k - 1, n, 1.0 / every) < alpha)
    return worst, held


def phase_off_events(worst: np.ndarray, held: np.ndarray, default: int = VALIDATION_PHASE) -> int:
    """The held-out phase of the interleaved blocks from :func:`phases_holding_events`' ``(worst,
    held)``: ``default``, unless it holds too many of some kind of event the fit must see (e.g. the
    reversals); then the phase whose largest share is least, the nearest to ``default`` on ties.

    The phases are drawn at random per run of blocks (:func:`block_phase`), so a phase holds most
    events only by chance or when there are few of them (the binomial tail then decides): without
    the rule, a fit on the other phases would not see them."""
    if not held[default]:
        return default
    return min(range(len(worst)), key=lambda j: (worst[j], abs(j - default), j))


# ---------------------------------------------------------------------------------------------
# Baseline construction


def stribeck_ls_grid(cols, v, y, V: float):
    """For each Stribeck speed vs on a grid (1e-3 to 0.5 of the speed scale ``V``): (vs, beta, SSE)
    of the linear least squares of ``y`` on ``cols`` plus ``sign(v)*exp(-(v/vs)^2)`` (last)."""
    for vs in V * np.logspace(-3, -0.3, 12):
        X = np.column_stack(list(cols) + [np.sign(v) * np.exp(-(v / vs) ** 2)])
        b, *_ = np.linalg.lstsq(X, y, rcond=None)
        yield vs, b, float(np.sum((y - X @ b) ** 2))


def initial_baseline(rec, friction: str = "lugre", fit_offset: bool = False) -> JointModel:
    """A starting baseline from linear least squares on ``J*a + Fc*sign(v) + sigma2*v (+ offset)``
    plus a 1-D search for the Stribeck velocity; sigma0 from a pre-sliding displacement of 1e-4 of
    the position span."""
    v, a, y = rec.velocity, rec.acceleration, rec.torque
    sc = data_scales(rec)
    cols = [a, np.sign(v), v] + ([np.ones_like(v)] if fit_offset else [])
    X = np.column_stack(cols)
    beta, *_ = np.linalg.lstsq(X, y, rcond=None)
    J = max(beta[0], 1e-3 * sc["T/A"])
    Fc = max(beta[1], 1e-3 * sc["T"])
    s2 = max(beta[2], 1e-4 * sc["T/V"])
    off = beta[3] if fit_offset else 0.0
    if friction == "coulomb_viscous":
        return JointModel(jnp.asarray(J), CoulombViscous(Fc=Fc, sigma2=s2), jnp.asarray(off))
    best = (np.inf, Fc, Fc, 0.1 * sc["V"])
    for vs, b, sse in stribeck_ls_grid(cols, v, y, sc["V"]):
        if sse < best[0] and b[1] > 0:
            best = (sse, b[1], b[1] + max(b[-1], 0.0), vs)
    _, Fc, Fs, vs = best
    sigma0 = max(Fs, Fc) / (1e-4 * sc["P"])
    if friction == "stribeck":
        return JointModel(jnp.asarray(J), Stribeck(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2), jnp.asarray(off))
    return JointModel(jnp.asarray(J), LuGre(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2, sigma0=sigma0,
                                            sigma1=0.1 * s2, require_passive=False), jnp.asarray(off))


def _stribeck_curve(v, Fc, Fs, vs, s2, off=0.0):
    """The steady-state friction curve plus a torque offset, as a NumPy array."""
    return np.asarray(stribeck_curve(v, Fc, Fs, vs, s2)) + off


def steady_state_samples(rec, noise: float, min_s: float = 0.3) -> np.ndarray:
    """Samples of constant-speed stretches at steady friction: moving, the velocity within 10 % of
    itself (plus the noise) for ``min_s`` seconds around the sample, and, of each such stretch
    lasting at least 1 s, the later half only if the torque has no trend there (bristles settled:
    a slow stretch may still be in pre-sliding)."""
    from scipy.ndimage import maximum_filter1d, minimum_filter1d

    v, y = np.asarray(rec.velocity), np.asarray(rec.torque)
    t = np.asarray(rec.time)
    V = float(np.percentile(np.abs(v), 99)) or 1.0
    dt = float(np.median(np.diff(t)))
    k = max(3, int(min_s / dt))
    vmax, vmin = maximum_filter1d(v, k), minimum_filter1d(v, k)
    steady = ((vmax - vmin) <= 0.1 * np.abs(v) + 4 * noise) & (np.abs(v) > 1e-3 * V) \
        & (np.sign(vmax) == np.sign(vmin))
    out = np.zeros_like(steady)
    d = np.diff(np.concatenate([[0], steady.astype(int), [0]]))
    for a, b in zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)):
        if (b - a) * dt < 1.0:
            continue
        h = a + (b - a) // 2
        yy, tt = y[h:b], t[h:b]
        slope = np.polyfit(tt - tt.mean(), yy, 1)[0]
        se = max(noise, 1e-12) * np.sqrt(12.0 / yy.size) / max(tt[-1] - tt[0], dt)
        if abs(slope) * (tt[-1] - tt[0]) <= max(4 * se * (tt[-1] - tt[0]), 0.02 * abs(np.median(yy))):
            out[h:b] = True
    return out


def static_curve_fit(rec, noise: float, fit_offset: bool):
    """(Fc, Fs, vs, sigma2, offset, n_bins) from the binned steady-state torque, or None if the
    recording has too few constant-speed stretches (fewer than 4 velocity bins per direction)."""
    from scipy.optimize import least_squares

    m = steady_state_samples(rec, noise)
    v, y = np.asarray(rec.velocity)[m], np.asarray(rec.torque)[m]
    if v.size < 100:
        return None
    lv = np.log(np.abs(v))
    edges = np.linspace(lv.min(), lv.max() + 1e-12, 31)
    bv, by, bw = [], [], []
    for sgn in (1, -1):
        for lo, hi in zip(edges[:-1], edges[1:]):
            sel = (np.sign(v) == sgn) & (lv >= lo) & (lv < hi)
            if sel.sum() >= 20:
                bv.append(np.median(v[sel]))
                by.append(np.median(y[sel]))
                bw.append(np.sqrt(sel.sum()))
    bv, by, bw = np.array(bv), np.array(by), np.array(bw)
    if (bv > 0).sum() < 4 or (bv < 0).sum() < 4:
        return None
    Fc0 = float(np.median(np.abs(by)))
    best = None
    for vs0 in np.abs(bv).max() * np.logspace(-3, -0.3, 8):
        x0 = [Fc0, 0.3 * Fc0, np.log(vs0), 0.0] + ([0.0] if fit_offset else [])

        def res(x):
            Fc, dF, lvs, s2 = x[:4]
            off = x[4] if fit_offset else 0.0
            return bw * (_stribeck_curve(bv, Fc, Fc + dF, np.exp(lvs), s2, off) - by)

        lo = [0, 0, np.log(1e-4 * np.abs(bv).max()), -np.inf] + ([-np.inf] if fit_offset else [])
        hi = [np.inf, np.inf, np.log(np.abs(bv).max()), np.inf] + ([np.inf] if fit_offset else [])
        x0 = np.clip(x0, np.array(lo) + 1e-9, np.array(hi) - 1e-9)
        r = least_squares(res, x0, bounds=(lo, hi))
        if best is None or r.cost < best.cost:
            best = r
    Fc, dF, lvs, s2 = best.x[:4]
    off = float(best.x[4]) if fit_offset else 0.0
    return float(Fc), float(Fc + dF), float(np.exp(lvs)), float(max(s2, 0.0)), off, int(bv.size)


# The data-driven starts can be decades from the best fit's basin; the grid of further starts that
# spans those decades is DiagnoseConfig's far_* (where its reason is given).


def initial_baselines(rec, friction: str = "lugre", fit_offset: bool = False, noise: float = 0.0,
                      rough: JointModel | None = None,
                      cfg: DiagnoseConfig | None = None) -> tuple[list[JointModel], list[JointModel]]:
    """Starting baselines (multi-start): ``(from the data, the grid of further starts)``.

    Fc, Fs, vs, sigma2 (and the offset) from the steady-state friction curve of the constant-speed
    stretches when the recording has them, else from the least-squares start of
    :func:`initial_baseline`; J by least squares of the torque left after the static curve against
    the acceleration; sigma0 from the pre-sliding displacement at reversals (Fs over the position
    travelled while the torque reverses), tried at x1/3, x1, x3; sigma1 for a bristle damping ratio
    of 0.5 and 0.1. The further starts: the grid ``cfg.far_*`` around the same J, Fc, sigma2 and
    offset (damping ratio 0.5); none for another friction model. J's accelerations: above
    ``cfg.big_acceleration`` of the acceleration scale (``cfg``: default :class:`DiagnoseConfig`).
    """
    cfg = DiagnoseConfig() if cfg is None else cfg
    rough = rough if rough is not None else initial_baseline(rec, friction, fit_offset)
    if friction != "lugre":
        return [rough], []
    sc = data_scales(rec)
    v, a, y = (np.asarray(x, float) for x in (rec.velocity, rec.acceleration, rec.torque))
    f0 = rough.friction
    st = static_curve_fit(rec, noise, fit_offset)
    if st is not None:
        Fc, Fs, vs, s2, off, _ = st
    else:
        Fc, Fs, vs, s2, off = (float(f0.Fc), float(f0.Fs), float(f0.vs), float(f0.sigma2),
                               float(rough.offset))
    vs = float(np.clip(vs, 2e-4 * sc["V"], 0.9 * sc["V"]))
    rest = y - _stribeck_curve(v, Fc, max(Fs, Fc), vs, s2, off)
    big = np.abs(a) > cfg.big_acceleration * sc["A"]
    J = float(np.dot(a[big], rest[big]) / max(np.dot(a[big], a[big]), 1e-300)) if big.sum() > 20 else float(rough.J)
    if not J > 0:
        J = float(rough.J)
    x_pre = presliding_displacement(rec, Fs)
    s0_data = max(Fs, Fc) / x_pre

    def start(Fc_, Fs_, vs_, s0, zeta):
        return JointModel(jnp.asarray(J), LuGre(Fc=Fc_, Fs=max(Fs_, Fc_ * 1.0001), vs=vs_, sigma2=s2, sigma0=s0,
                                                sigma1=2 * zeta * np.sqrt(s0 * J), require_passive=False),
                          jnp.asarray(off))

    # the grid's humps over the static curve's Coulomb level and over the least-squares start's: with
    # fewer resolved speeds than the curve has parameters the static fit can put the Coulomb level
    # near 0 (the hump's tail taking its place), and a grid around it alone holds no start with the
    # joint's friction level
    levels = [Fc] + ([float(f0.Fc)] if st is not None and not 0.5 < float(f0.Fc) / max(Fc, 1e-300) < 2.0 else [])
    humps = [(Fc, Fs, vs)] + [(c, k * c, q * sc["V"]) for c in levels for k in cfg.far_fs_over_fc
                              for q in cfg.far_vs_over_v]
    return ([start(Fc, Fs, vs, s0_data / k0, zeta) for k0 in (1.0, 1 / 3, 3.0) for zeta in (0.5, 0.1)],
            [start(Fc_, Fs_, vs_, max(Fs_, Fc_) / (x * sc["P"]), 0.5) for Fc_, Fs_, vs_ in humps
             for x in cfg.far_presliding_over_p])


def presliding_length(friction) -> float:
    """A LuGre friction's pre-sliding length ``max(Fs, Fc)/sigma0``: the travel over which the
    bristles deflect to their sliding level after a reversal."""
    return max(float(friction.Fs), float(friction.Fc)) / float(friction.sigma0)


def presliding_displacement(rec, Fs: float) -> float:
    """Median position travelled after a reversal until the torque has covered 63 % of its swing
    (the bristle deflection scale Fs/sigma0); 1e-3 of the position span if no clean reversal."""
    th, v, y = (np.asarray(x, float) for x in (rec.position, rec.velocity, rec.torque))
    P = float(np.ptp(th)) or 1.0
    sgn = np.sign(v)
    idx = np.flatnonzero(np.diff(sgn) != 0)
    dt = float(np.median(np.diff(rec.time)))
    w = max(5, int(0.5 / dt))
    out = []
    for i in idx:
        if i < w or i + w >= th.size:
            continue
        before, after = np.median(y[i - w:i - w // 2]), y[i:i + w]
        swing = np.median(y[i + w // 2:i + w]) - before
        if abs(swing) < Fs:  # not a full reversal of the friction
            continue
        frac = (after - before) / swing
        j = np.flatnonzero(frac > 0.63)
        if j.size:
            out.append(abs(th[i + j[0]] - th[i]))
    out = [x for x in out if x > 0]
    return float(np.median(out)) if len(out) >= 3 else 1e-3 * P


def model_params(model: JointModel) -> dict[str, float]:
    """All physical parameters of the baseline part, by name (recording units)."""
    out = {"J": float(model.J), "offset": float(model.offset)}
    f = model.friction
    for name in ("Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "delta"):
        if hasattr(f, name):
            out[name] = float(getattr(f, name))
    out["friction_model"] = type(f).__name__
    return out


def baseline_from_params(params: dict) -> JointModel:
    """Build a baseline from a params dict (as written in REPORT.json ``baseline.params``)."""
    known = {"J", "offset", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "delta", "friction_model"}
    unknown = set(params) - known
    if unknown:
        raise ValueError(f"--params: unknown parameter(s) {sorted(unknown)}; expected some of {sorted(known)}")
    kind = params.get("friction_model", "LuGre")
    try:
        if kind == "CoulombViscous":
            f = CoulombViscous(Fc=params["Fc"], sigma2=params["sigma2"])
        elif kind == "Stribeck":
            f = Stribeck(Fc=params["Fc"], Fs=params["Fs"], vs=params["vs"], sigma2=params["sigma2"],
                         delta=params.get("delta", 2.0))
        else:
            f = LuGre(Fc=params["Fc"], Fs=params["Fs"], vs=params["vs"], sigma2=params["sigma2"],
                      sigma0=params["sigma0"], sigma1=params["sigma1"], delta=params.get("delta", 2.0))
        return JointModel(jnp.asarray(float(params["J"])), f, jnp.asarray(float(params.get("offset", 0.0))))
    except KeyError as e:
        raise ValueError(f"--params: missing parameter {e.args[0]!r} for a {kind} baseline") from None
