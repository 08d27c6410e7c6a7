"""Library of candidate missing physics for the joint of Li et al. (Electronics 2020, 9, 284).

The paper's joint model (eq. 1-2, 9) assumes gravity compensated (G = 0), a rigid transmission, a
symmetric LuGre friction with the Stribeck exponent fixed at 2, and constant parameters. Each
candidate below relaxes one of those assumptions; each is a final equinox Module with an ``id``, a
plain-language ``explanation`` and parameters whose bounds are multiples of data scales (so the same
library works on deg/N*m recordings and on SI recordings such as EMPS).

All torques are in the recording's torque unit; angles in the recording's position unit.
"""

from __future__ import annotations

import hashlib
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import jax.scipy.linalg as jsl
import numpy as np

from ..friction import LuGre, Stribeck
from ._model import AbstractCandidate, Terms, cparam, friction_torque, presliding_length

TWO_PI = 2 * np.pi


def _zeros(kin):
    return jnp.zeros_like(kin.v)


class PositionRipple(AbstractCandidate):
    """Torque ripple periodic in position (cogging, gear-mesh, bearing or screw-lead errors)."""

    amplitude: jax.Array = cparam("T", 0.0, 1.0)
    period: jax.Array = cparam("P", 1e-4, 2.0, log=True)
    phase: jax.Array = cparam("1", -3 * np.pi, 3 * np.pi)
    id: ClassVar[str] = "position_ripple"
    searches_residual: ClassVar[bool] = True
    key_params: ClassVar[dict] = {"amplitude": 0.0}

    def implausible(self, ctx):
        span = ctx.scales["P"]
        if span < 2 * float(self.period):
            return f"fewer than two periods ({float(self.period):.3g}) in the position span {span:.3g}"
        res = ctx.position_resolution
        if float(self.period) < 8 * res:
            return "period within a few encoder steps"
        return self._single_speed(ctx)

    def _single_speed(self, ctx):
        """A torque that repeats with position is there at every speed: a fit whose gain on the
        residual lives in one speed quartile is the baseline's misfit of that regime, not a ripple
        (a short-period 'ripple' can take the slowest plateau's stick-slip and lose in every faster
        band)."""
        kin, r = ctx.kin, ctx.residual
        if kin is None or r is None:
            return None
        r = np.asarray(r, float)
        moving = r != 0  # the resolved samples (the residual is 0 elsewhere)
        if moving.sum() < 40:
            return None
        s = np.asarray(self.extra_torque(kin, None, None, None))[moving]
        speed = np.abs(np.asarray(kin.v, float))[moving]
        band = np.searchsorted(np.quantile(speed, [0.25, 0.5, 0.75]), speed)
        gain = np.bincount(band, weights=2 * r[moving] * s - s * s, minlength=4)
        if np.sum(gain > 0) < 2:
            return (f"lowers the residual in {int(np.sum(gain > 0))} of 4 speed quartiles only: a torque "
                    "that repeats with position shows at every speed")
        return None
    explanation: ClassVar[str] = (
        "A torque that repeats with joint position (period in position units): cogging of the motor, "
        "gear-mesh or screw-lead error, or a bearing defect. It adds A*sin(2*pi*theta/period + phase) "
        "to the joint torque whatever the speed or direction.")

    def prepare(self, terms, kin):
        return terms

    def extra_torque(self, kin, terms, F, inertial):
        return self.amplitude * jnp.sin(TWO_PI * kin.theta / self.period + self.phase)

    def initial_guesses(self, ctx):
        out = []
        for pk in ctx.position_peaks[:3]:
            out.append(PositionRipple(pk["amplitude"], pk["period"], pk["phase"]))
        return out

    def applicable(self, ctx):
        return len(ctx.position_peaks) > 0

    def describe(self, ctx):
        A, P, ph = float(self.amplitude), float(self.period), float(self.phase)
        return {"amplitude": A, "period": P, "phase_rad": float(np.mod(ph, TWO_PI)),
                "units": {"amplitude": ctx.units["torque"], "period": ctx.units["position"]}}


class Gravity(AbstractCandidate):
    """Uncompensated gravity load G(theta) = A*sin(theta + phase), eq. (1) with G != 0."""

    amplitude: jax.Array = cparam("T", 0.0, 2.0)
    phase: jax.Array = cparam("1", -3 * np.pi, 3 * np.pi)
    to_rad: jax.Array = eqx.field(converter=jnp.asarray, default=np.pi / 180)
    id: ClassVar[str] = "gravity"
    key_params: ClassVar[dict] = {"amplitude": 0.0}

    def implausible(self, ctx):
        span = ctx.scales["P"] * float(self.to_rad)
        if span < np.pi / 6:
            # over less than 30 deg a sine of the angle is a line (a spring or a position-dependent
            # friction would fit as well): the amplitude is not identifiable
            return f"position span {span * 180 / np.pi:.3g} deg < 30 deg: a sine cannot be told from a line"
        if float(self.amplitude) > 2 * ctx.scales["T"]:
            return "amplitude above twice the largest measured torque"
        G = float(self.amplitude) * np.sin(np.asarray(ctx.rec.position) * float(self.to_rad) + float(self.phase))
        if G.std() < ctx.config.gravity_min_variation * abs(G.mean()):
            # where the joint spends its time the sine is flat: the fit is a constant torque, which
            # an offset or a direction asymmetry explains as well; the angle dependence is not shown
            return (f"over the recording's positions the fitted gravity varies by {G.std():.2g} around "
                    f"{G.mean():.2g}: a constant torque, not a load that changes with the angle")
        return None
    explanation: ClassVar[str] = (
        "An uncompensated gravity (or spring-balancer) torque G(theta) = A*sin(theta + phase) that "
        "depends on the joint angle with a period of one revolution: the paper assumes the arm's "
        "gravity compensator removes it (G = 0, section 3.1); this says it does not, fully.")

    def prepare(self, terms, kin):
        return terms

    def extra_torque(self, kin, terms, F, inertial):
        return self.amplitude * jnp.sin(kin.theta * self.to_rad + self.phase)

    def initial_guesses(self, ctx):
        th = np.asarray(ctx.rec.position) * ctx.to_rad
        r = ctx.residual
        X = np.column_stack([np.sin(th), np.cos(th), np.ones_like(th)])
        b, *_ = np.linalg.lstsq(X, r, rcond=None)
        A = float(np.hypot(b[0], b[1]))
        ph = float(np.arctan2(b[1], b[0]))
        return [Gravity(A, ph, ctx.to_rad)]

    def applicable(self, ctx):
        return ctx.rec.rotary

    def describe(self, ctx):
        return {"amplitude": float(self.amplitude), "phase_rad": float(np.mod(self.phase, TWO_PI)),
                "units": {"amplitude": ctx.units["torque"]}}


class Asymmetry(AbstractCandidate):
    """Direction-dependent friction: Fc+ != Fc- (equivalently a torque offset) and sigma2+ != sigma2-."""

    offset: jax.Array = cparam("T", -1.0, 1.0)
    dsigma2: jax.Array = cparam("T/V", -1.0, 1.0)
    id: ClassVar[str] = "asymmetry"
    key_params: ClassVar[dict] = {"offset": 0.0, "dsigma2": 0.0}
    explanation: ClassVar[str] = (
        "Friction is not the same in both directions: the Coulomb level is Fc + offset when moving "
        "positive and Fc - offset when moving negative (indistinguishable, while sliding, from a "
        "constant torque offset such as a sensor bias or unbalanced load), and the viscous coefficient "
        "is sigma2 + dsigma2 / sigma2 - dsigma2.")

    def prepare(self, terms, kin):
        return terms

    def extra_torque(self, kin, terms, F, inertial):
        return self.offset + self.dsigma2 * jnp.abs(kin.v)

    def initial_guesses(self, ctx):
        v, r = np.asarray(ctx.rec.velocity), ctx.residual
        X = np.column_stack([np.ones_like(v), np.abs(v)])
        b, *_ = np.linalg.lstsq(X, r, rcond=None)
        return [Asymmetry(float(b[0]), float(b[1]))]

    def applicable(self, ctx):
        return True

    def describe(self, ctx):
        u = ctx.units
        return {"offset": float(self.offset), "dsigma2": float(self.dsigma2),
                "Fc_plus_minus_Fc_minus": 2 * float(self.offset),
                "units": {"offset": u["torque"], "dsigma2": f"{u['torque']}*{u['time']}/{u['position']}"}}


class ThermalDrift(AbstractCandidate):
    """Friction drifting in time (warm-up): F(t) = F*(1 + rate*(t - t_mid))."""

    rate: jax.Array = cparam("1/D", -1.0, 1.0)
    id: ClassVar[str] = "thermal_drift"
    key_params: ClassVar[dict] = {"rate": 0.0}
    explanation: ClassVar[str] = (
        "Friction changes during the recording, as lubricant warms up and thins (or the joint cools): "
        "the whole friction torque is scaled by 1 + rate*(t - t_mid); rate*duration is the relative "
        "change from start to end.")

    def prepare(self, terms, kin):
        tm = 0.5 * (kin.t[0] + kin.t[-1])
        return eqx.tree_at(lambda x: x.friction_gain, terms, terms.friction_gain * (1 + self.rate * (kin.t - tm)))

    def extra_torque(self, kin, terms, F, inertial):
        return _zeros(kin)

    def initial_guesses(self, ctx):
        t = np.asarray(ctx.rec.time)
        x = (t - 0.5 * (t[0] + t[-1])) * ctx.friction_torque
        rate = float(np.dot(x, ctx.residual) / max(np.dot(x, x), 1e-300))
        return [ThermalDrift(rate)]

    def applicable(self, ctx):
        return True

    def describe(self, ctx):
        D = ctx.scales["D"]
        return {"rate": float(self.rate), "relative_change_over_recording": float(self.rate) * D,
                "units": {"rate": f"1/{ctx.units['time']}"}}


class StribeckShape(AbstractCandidate):
    """Stribeck exponent delta != 2 in g(v) = Fc + (Fs - Fc)*exp(-|v/vs|^delta), eq. (9)-(10)."""

    delta: jax.Array = cparam("1", 0.3, 6.0)
    id: ClassVar[str] = "stribeck_shape"
    key_params: ClassVar[dict] = {"delta": 2.0}
    explanation: ClassVar[str] = (
        "The fall from static to Coulomb friction has a different shape than the paper's Gaussian "
        "(exponent 2 in eq. 9-10): g(v) = Fc + (Fs - Fc)*exp(-|v/vs|^delta). delta < 2 is a sharper "
        "initial drop with a longer tail, delta > 2 a flatter plateau then a steeper fall.")

    def prepare(self, terms, kin):
        return eqx.tree_at(lambda x: x.friction.delta, terms, self.delta)

    def extra_torque(self, kin, terms, F, inertial):
        return _zeros(kin)

    def initial_guesses(self, ctx):
        return [StribeckShape(d) for d in (1.0, 1.5, 3.0)]

    def applicable(self, ctx):
        return isinstance(ctx.baseline.friction, (LuGre, Stribeck))

    def describe(self, ctx):
        return {"delta": float(self.delta)}


def spaced_starts(shapes, correlation: float, batch: int = 16) -> list[int]:
    """Of trial shapes along one parameter (rows, in its order), the fewest starts, first and last
    included, such that each start's shape correlates at least ``correlation`` with the next one's
    (on these samples): the shape is then never far from a start, whatever the recording's sampling
    and excitation make of the parameter (a fixed spacing in the parameter is too coarse on one
    recording and wasteful on another). Depends on the kinematics alone, not on the residual, so
    every null draw sees the same starts. ``shapes`` is an array, or ``(shape_of, m)``: the ``m``
    rows made ``batch`` at a time by ``shape_of(indices)``, so that a fine grid on a long recording
    need not be held whole."""
    if isinstance(shapes, tuple):
        shape_of, m = shapes
    else:
        arr = np.asarray(shapes)
        shape_of, m = (lambda idx: arr[idx]), len(arr)

    def unit(idx):
        x = np.asarray(shape_of(np.asarray(idx)), float)
        norm = np.linalg.norm(x, axis=1)
        return x / np.where(norm > 0, norm, 1.0)[:, None]

    picks, i = [0], 0
    ui = unit([0])[0]
    while i < m - 1:
        # the last shape before the first one below the bound (the next one, where even it is below)
        last, j = None, m - 1
        for j0 in range(i + 1, m, batch):
            idx = np.arange(j0, min(j0 + batch, m))
            u = unit(idx)
            below = np.flatnonzero(u @ ui < correlation)
            if below.size:
                k = int(below[0])
                if k > 0:
                    last = (idx[k - 1], u[k - 1])
                j, ui = last if last is not None else (idx[k], u[k])
                break
            last = (idx[-1], u[-1])
        picks.append(int(j))
        i = int(j)
    return picks


@eqx.filter_jit
def _backlash_shapes(widths, kin, terms, F):
    """Each width's backlash torque at share 1 (rows), in one compiled pass."""
    return jax.vmap(lambda w: Backlash(w, jnp.ones_like(w)).extra_torque(kin, terms, F, None))(widths)


def play_operator(theta, width):
    """Load-side angle behind a dead band of total ``width`` (play/backlash operator)."""
    half = 0.5 * width

    def step(tl, th):
        tn = jnp.clip(tl, th - half, th + half)
        return tn, tn

    _, tl = jax.lax.scan(step, theta[0], theta[1:])
    return jnp.concatenate([theta[:1], tl])


def engaged_fraction(theta, width):
    """Per sample, the fraction of the motor's travel over the preceding interval that reached the
    load through a dead band of total ``width`` (1 = engaged, 0 = crossing the gap)."""
    tl = play_operator(theta, width)
    dm = jnp.diff(theta)
    dl = jnp.diff(tl)
    small = jnp.abs(dm) < 1e-12
    frac = jnp.where(small, 1.0, jnp.clip(dl / jnp.where(small, 1.0, dm), 0.0, 1.0))
    # centred on the sample (mean of the intervals before and after it): assigning each interval to
    # its end sample delays the modelled dip by half a sample, which a fit then pays for with a
    # wider gap
    mid = 0.5 * (frac[:-1] + frac[1:])
    return jnp.concatenate([frac[:1], mid, frac[-1:]])


class Backlash(AbstractCandidate):
    """Dead band at reversals: the load, and the share of the friction behind the gap, disengage
    while the gap is crossed; the load-side bristles hold their state meanwhile, so that share of the
    friction also lags the motor by the gap after re-engagement."""

    width: jax.Array = cparam("P", 1e-7, 0.02, log=True)
    share: jax.Array = cparam("1", 1e-4, 1.0, log=True)
    id: ClassVar[str] = "backlash"
    key_params: ClassVar[dict] = {"width": 0.0, "share": 0.0}
    # the torque changes with the width only where a sample's gap crossing ends: profiled
    profiled: ClassVar[tuple[str, str] | None] = ("width", "share")

    def implausible(self, ctx):
        res = ctx.position_resolution
        if float(self.width) < 4 * res:
            return f"width {float(self.width):.3g} within four steps of the position resolution {res:.3g}"
        f = ctx.baseline.friction
        if isinstance(f, LuGre):
            # a gap narrower than the bristles' pre-sliding length acts within the same travel after
            # a reversal as the bristle state's own transition, where the inverse model's error
            # from the conditioned kinematics also lives: it cannot be told from either
            x_pre = presliding_length(f)
            if float(self.width) < x_pre:
                return (f"width {float(self.width):.3g} below the bristles' pre-sliding length "
                        f"max(Fs, Fc)/sigma0 = {x_pre:.3g}")
        return None
    explanation: ClassVar[str] = (
        "Backlash (dead band) in the transmission: after every reversal the motor turns through a gap "
        "of the given width before it re-engages the load, and during that travel the friction on the "
        "load side of the gap (the given share of the joint's friction: output bearings, seals) is not "
        "felt at the actuator. Seen as a friction drop of share*F for a short time after each reversal.")

    def prepare(self, terms, kin):
        return terms

    def extra_torque(self, kin, terms, F, inertial):
        # Split friction: (1 - share)*F on the motor side, as without backlash; the load side moves
        # only when engaged (velocity frac*v, so its bristles hold their state in the gap) and is felt
        # only then.
        frac = engaged_fraction(kin.theta, self.width)
        # the load side's bristles follow the load's path: the motor's path through the play operator
        dpath_load = jnp.diff(play_operator(jnp.cumsum(jnp.concatenate([kin.theta[:1], terms.dpath])),
                                            self.width))
        F_load = terms.friction_gain * friction_torque(terms.friction, terms.v_friction * frac, kin.h,
                                                       dpath_load, kin.z0_sign)
        return self.share * (frac * F_load - F)

    def initial_guesses(self, ctx):
        # share by least squares on the located residual, for each start width
        P = ctx.scales["P"]
        kin = ctx.kin
        terms = Terms(ctx.baseline.friction, kin.v, jnp.ones_like(kin.v), kin.dpath)
        F = jnp.asarray(ctx.friction_torque)
        r = np.asarray(ctx.residual)
        # a gap's width has nothing to do with the position span: widths from the smallest plausible
        # one (four steps of the position resolution) up to the bound, on a grid fine enough (a
        # factor 1.1) that neighbouring shapes correlate well above the starts' bound
        lo = max(4 * ctx.position_resolution, 1e-6 * P)
        widths = np.geomspace(lo, 0.02 * P, max(int(np.ceil(np.log(0.02 * P / lo) / np.log(1.1))) + 1, 2))
        shapes = np.asarray(_backlash_shapes(jnp.asarray(widths), kin, terms, F))
        out = []
        for i in spaced_starts(shapes[:, r != 0], ctx.config.start_correlation):
            x = shapes[i]
            share = float(np.dot(x, r) / max(np.dot(x, x), 1e-300))
            out.append(Backlash(float(widths[i]), float(np.clip(share, 2e-4, 0.9))))
        return out

    def applicable(self, ctx):
        return ctx.n_reversals >= 4

    def describe(self, ctx):
        return {"width": float(self.width), "share": float(self.share),
                "units": {"width": ctx.units["position"], "share": "1 (fraction of the friction)"}}


def _compliance_response(a, h, fn, zeta):
    """e'' of the load-minus-motor angle e for a load on a spring (natural freq fn [Hz], damping zeta)
    driven by the motor acceleration a (held over each sample: exact zero-order-hold discretisation)."""
    w = TWO_PI * fn
    A = jnp.array([[0.0, 1.0], [-w * w, -2 * zeta * w]])
    B = jnp.array([0.0, -1.0])
    Ad = jsl.expm(A * h)
    Bd = jnp.linalg.solve(A, (Ad - jnp.eye(2)) @ B)

    def step(x, ak):
        return Ad @ x + Bd * ak, x

    _, xs = jax.lax.scan(step, jnp.zeros(2), a)
    return -w * w * xs[:, 0] - 2 * zeta * w * xs[:, 1] - a


@eqx.filter_jit
def _compliance_shapes(fns, a, h, zeta):
    """Each natural frequency's compliance response (rows), in one compiled pass."""
    return jax.vmap(lambda f: _compliance_response(a, h, f, zeta))(fns)


_STARTS_MEMO: dict = {}


def compliance_starts(kin, fs: float, correlation: float, zeta: float = 0.1) -> list[float]:
    """Natural frequencies to start the compliance's fit from, 0.5 Hz up to 20 Hz (and below 0.35
    of the sampling rate ``fs``): :func:`spaced_starts` over a grid 2 % apart, the responses at
    damping ``zeta`` to the recording's acceleration. A lightly damped response rings for many
    periods, so on a long excitation it decorrelates within a few per cent of fn (at 0.5 Hz
    neighbours 4 % apart already correlate below 0.8): a fixed list leaves a spring between two
    starts with a fraction of its gain. The starts depend on the kinematics alone; every null
    draw's search reads the same ones (kept per acceleration, as each draw asks again)."""
    a = np.asarray(kin.a, float)
    h = float(np.mean(np.asarray(kin.h, float)))
    hi = min(20.0, 0.35 * float(fs))
    if hi <= 0.5:
        return []
    key = (hashlib.blake2b(a.tobytes(), digest_size=16).hexdigest(), h, hi, float(correlation), float(zeta))
    if key not in _STARTS_MEMO:
        grid = np.geomspace(0.5, hi, int(np.ceil(np.log(hi / 0.5) / np.log(1.02))) + 1)
        aj, batch = jnp.asarray(a), 16

        def shape_of(idx):
            # padded to one batch's size: one compilation per recording
            full = np.concatenate([idx, np.full(batch - idx.size, idx[-1])]) if idx.size < batch else idx
            return np.asarray(_compliance_shapes(jnp.asarray(grid[full]), aj, h, zeta))[:idx.size]

        picks = spaced_starts((shape_of, grid.size), correlation, batch=batch)
        if len(_STARTS_MEMO) > 8:
            _STARTS_MEMO.clear()
        _STARTS_MEMO[key] = [float(grid[i]) for i in picks]
    return list(_STARTS_MEMO[key])


class Compliance(AbstractCandidate):
    """Elastic joint (two-mass): a load inertia J_load on a spring of natural frequency fn."""

    fn: jax.Array = cparam("fs", 1e-3, 0.4, log=True)
    zeta: jax.Array = cparam("1", 0.005, 1.0, log=True)
    J_load: jax.Array = cparam("T/A", 0.0, 5.0)
    id: ClassVar[str] = "compliance"
    searches_residual: ClassVar[bool] = True
    linear_in_motion: ClassVar[bool] = True
    # the load inertia is the effect's size; a natural frequency has no "no effect" value
    key_params: ClassVar[dict] = {"J_load": 0.0}

    def implausible(self, ctx):
        # the response is driven by the conditioned acceleration: above its bandwidth (where it passes
        # less than 1/sqrt(2) of a sine's) the fitted ringing is mostly the smoothing's, not a spring's
        fc = ctx.accel_bandwidth_hz
        if float(self.fn) > fc:
            return (f"natural frequency {float(self.fn):.3g} Hz not below the conditioned acceleration's "
                    f"bandwidth {fc:.3g} Hz")
        if float(self.J_load) > float(ctx.baseline.J):
            return "load inertia above the joint's whole inertia"
        if float(self.zeta) > 0.5:
            return "damping ratio above 0.5: no ringing to tell a spring from a filter"
        return None

    def beyond_resolution(self, ctx):
        return float(self.fn) > ctx.accel_bandwidth_hz

    explanation: ClassVar[str] = (
        "The transmission is elastic: part of the inertia (J_load) sits behind a spring, so it lags the "
        "motor and rings at the natural frequency fn (damping ratio zeta) after every change of "
        "acceleration. The actuator feels J_load times the load's acceleration, not the motor's.")

    def prepare(self, terms, kin):
        return terms

    def extra_torque(self, kin, terms, F, inertial):
        h = jnp.mean(kin.h)
        return self.J_load * _compliance_response(kin.a, h, self.fn, self.zeta)

    def initial_guesses(self, ctx):
        fns = compliance_starts(ctx.kin, ctx.scales["fs"], ctx.config.start_correlation)
        if ctx.time_peak_hz:
            fns = [ctx.time_peak_hz] + fns
        J0 = 0.05 * ctx.scales["T/A"]
        return [Compliance(f, 0.1, J0) for f in fns]

    def applicable(self, ctx):
        return True

    def describe(self, ctx):
        u = ctx.units
        return {"fn_hz": float(self.fn), "zeta": float(self.zeta), "J_load": float(self.J_load),
                "units": {"J_load": f"{u['torque']}*s^2/{u['position']}"}}


class LoadDependent(AbstractCandidate):
    """Friction growing with the transmitted torque: F_extra = mu*|J*a|*sign(v)."""

    mu: jax.Array = cparam("1", 0.0, 2.0)
    v_eps: jax.Array = eqx.field(converter=jnp.asarray, default=1e-3)
    id: ClassVar[str] = "load_dependent"
    key_params: ClassVar[dict] = {"mu": 0.0}
    explanation: ClassVar[str] = (
        "Friction grows with the torque the transmission carries (gear/screw contact normal force "
        "rises with load): an extra friction mu*|tau_transmitted|*sign(v), with the transmitted torque "
        "here the inertial torque J*a (the paper's joint has no other load once gravity is compensated).")

    def prepare(self, terms, kin):
        return terms

    def extra_torque(self, kin, terms, F, inertial):
        return self.mu * jnp.abs(inertial) * jnp.tanh(kin.v / self.v_eps)

    def initial_guesses(self, ctx):
        v_eps = 0.01 * ctx.scales["V"]
        x = np.abs(ctx.inertial_torque) * np.tanh(np.asarray(ctx.rec.velocity) / v_eps)
        mu = float(np.dot(x, ctx.residual) / max(np.dot(x, x), 1e-300))
        return [LoadDependent(max(mu, 1e-4), v_eps)]

    def applicable(self, ctx):
        return True

    def describe(self, ctx):
        return {"mu": float(self.mu)}


CANDIDATES: dict[str, type[AbstractCandidate]] = {
    c.id: c for c in (PositionRipple, Gravity, Asymmetry, ThermalDrift, StribeckShape, Backlash,
                      Compliance, LoadDependent)
}
