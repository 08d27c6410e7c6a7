"""Choices of a simulation, as objects (in the manner of diffrax's solvers, step-size controllers
and ``SaveAt``): how to step (:class:`FixedStep`, :class:`ExponentialBristle`, :class:`Adaptive`,
:class:`LaneAdaptive`), what to keep
(:class:`SaveAt`) and how to spread a batch over chunks and devices (:class:`Lanes`)."""

from __future__ import annotations

import abc
import math
from typing import Callable

import diffrax
import equinox as eqx


class AbstractStepping(eqx.Module):
    """How the ODE is stepped: :class:`FixedStep`, :class:`ExponentialBristle`, :class:`Adaptive` or
    :class:`LaneAdaptive`."""

    solver: eqx.AbstractVar[diffrax.AbstractSolver]

    @abc.abstractmethod
    def describe(self) -> str:
        ...


class FixedStep(AbstractStepping):
    """A constant step ``dt`` [s] of an explicit Runge-Kutta ``solver`` (any diffrax solver with a
    Butcher tableau: ``Tsit5``, ``Bosh3``, ``Heun``, ``Ralston``, ``Midpoint``, ``Dopri5``).

    The fast choice for batches: every lane costs the same and the stages are unrolled into one
    vectorised loop. Its accuracy is the user's to choose: check it with
    :func:`lugre_jax.check_stepping`, which re-solves a few lanes adaptively. ``dt=None`` (the
    default) is 2.5e-3 s or the sample period if that is shorter. A ``dt`` shorter than the sample
    period is rounded down to divide it; a longer one must be a whole multiple of it (samples
    between steps are cubic-Hermite interpolated). Discontinuities of the reference
    that fall between steps (e.g. a staircase whose steps are off the step grid) cost first-order
    local error there; the :class:`Adaptive` default lands on them.
    """

    solver: diffrax.AbstractSolver = eqx.field(static=True, default_factory=diffrax.Tsit5)
    dt: float | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        if not isinstance(self.solver, diffrax.AbstractERK) or not hasattr(self.solver, "tableau"):
            raise ValueError(f"FixedStep needs an explicit Runge-Kutta diffrax solver (Tsit5, Bosh3, Heun, "
                             f"Ralston, Midpoint, Dopri5), got {type(self.solver).__name__}")
        if self.dt is not None and not (isinstance(self.dt, (int, float)) and self.dt > 0):
            raise ValueError(f"FixedStep.dt must be a positive step in seconds (or None), got {self.dt!r}")

    def step_for(self, sample_hz: float) -> float:
        """The step [s] used at ``sample_hz``: ``dt``, or by default 2.5e-3 s capped at the sample period."""
        return step_for(self, sample_hz)

    def check(self, sample_hz: float) -> None:
        """``ValueError`` unless the step fits the sample grid of ``sample_hz`` (divides the sample
        period, or spans a whole number of samples)."""
        step_plan(step_for(self, sample_hz), sample_hz)

    @property
    def evals_per_step(self) -> int:
        """Right-hand-side evaluations per step (an FSAL tableau's last stage is the next k0)."""
        tableau = self.solver.tableau
        return len(tableau.a_lower) + (0 if tableau.fsal else 1)

    def describe(self) -> str:
        return f"FixedStep({type(self.solver).__name__}(), dt={self.dt!r})" if self.dt else \
            f"FixedStep({type(self.solver).__name__}())"


class ExponentialBristle(AbstractStepping):
    """A constant step ``dt`` [s] of the explicit Runge-Kutta ``solver`` (as :class:`FixedStep`;
    default ``Tsit5``) in which the bristle state ``z`` is advanced exactly where it is stiff.

    The bristle equation is affine in ``z``, ``dz/dt = p(v) - q(v)*z`` (LuGre: ``p = v``,
    ``q = sigma0*|v|/g(v)``), and stiff where ``q`` is large (stiff bristles at speed). At each
    stage, and for the step's result, ``z`` is the exact solution from the step's start with the
    velocity frozen at the stage's mean velocity, ``z+ = exp(-q*tau)*z + p*tau*phi1(q*tau)``, which
    contracts however large ``q*dt`` is; where ``q*tau`` is small the solver's own stage is kept
    (blended smoothly), so a step without stiff bristles is the :class:`FixedStep` step. The
    velocity integrates the acceleration without the bristle damping, whose integral over a stage
    is ``sigma1*(z - z0)``, so the bristle's stiffness does not reach the mechanics either.

    The step is then not limited by ``sigma0*|v|/g(v)``; what still bounds it is the mechanics: the
    damping ``(sigma1 + sigma2 + kp)/J`` and, while the joint sticks, the pre-sliding spring
    ``sqrt(sigma0/J)``. Where the bristle is stiff the frozen velocity makes it second order in
    ``dt`` through slips, so at a given accuracy it needs a smaller step than an explicit step that
    is stable (docs/performance.md): choose it for lanes on which :class:`FixedStep` blows up at
    the step you can afford. Needs a friction law whose ``dz/dt`` is affine in ``z`` (every law in
    :mod:`lugre_jax.friction`); the observer state of :class:`LuGreCompensated` and a motor's
    current are stepped by the ``solver``. ``dt`` and the sample grid as :class:`FixedStep`.
    Differentiable in forward and reverse mode. Check its accuracy with
    :func:`lugre_jax.check_stepping`.
    """

    solver: diffrax.AbstractSolver = eqx.field(static=True, default_factory=diffrax.Tsit5)
    dt: float | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        if not isinstance(self.solver, diffrax.AbstractERK) or not hasattr(self.solver, "tableau"):
            raise ValueError(f"ExponentialBristle needs an explicit Runge-Kutta diffrax solver (Tsit5, Bosh3, "
                             f"Heun, Ralston, Midpoint, Dopri5), got {type(self.solver).__name__}")
        if self.dt is not None and not (isinstance(self.dt, (int, float)) and self.dt > 0):
            raise ValueError(f"ExponentialBristle.dt must be a positive step in seconds (or None), got {self.dt!r}")

    def step_for(self, sample_hz: float) -> float:
        """The step [s] used at ``sample_hz``: ``dt``, or by default 2.5e-3 s capped at the sample period."""
        return step_for(self, sample_hz)

    @property
    def evals_per_step(self) -> int:
        """Right-hand-side evaluations per step (an FSAL tableau's last stage is the next k0)."""
        tableau = self.solver.tableau
        return len(tableau.a_lower) + (0 if tableau.fsal else 1)

    def describe(self) -> str:
        return f"ExponentialBristle({type(self.solver).__name__}(), dt={self.dt!r})" if self.dt else \
            f"ExponentialBristle({type(self.solver).__name__}())"


# The steppings solved by the fixed-step loop of ``_fixed``.
FIXED_STEPPINGS = (FixedStep, ExponentialBristle)


def step_plan(dt: float, sample_hz: float) -> tuple[int, int]:
    """``(steps per sample, samples per step)`` for a fixed step ``dt`` [s]: either a step divides
    the sample period (rounded down to a divisor), or it spans a whole number of samples."""
    h_sample = 1.0 / sample_hz
    if dt <= h_sample * (1 + 1e-9):
        return max(1, math.ceil(h_sample / dt - 1e-9)), 1
    m = round(dt / h_sample)
    if abs(m * h_sample - dt) > 1e-9 * dt:
        raise ValueError(
            f"FixedStep.dt={dt!r} s is longer than the sample period 1/sample_hz={h_sample!r} s but not "
            "a whole multiple of it; choose dt <= 1/sample_hz, or dt = k/sample_hz for an integer k "
            "(the samples between steps are then interpolated)"
        )
    return 1, m


def step_for(stepping: FixedStep | ExponentialBristle, sample_hz: float) -> float:
    """:meth:`FixedStep.step_for` as a plain function, for code run on every call: reading a method
    off an equinox Module builds a bound-method Module each time."""
    return min(2.5e-3, 1.0 / sample_hz) if stepping.dt is None else float(stepping.dt)


class Adaptive(AbstractStepping):
    """Error-controlled stepping: diffrax ``solver`` (default ``Tsit5``) with a PID step-size
    controller at ``rtol``/``atol``, stepping exactly onto the reference's discontinuities
    (``jump_ts``), at most ``max_steps`` steps, ``dtmax`` [s] the largest step.

    The paper's joint is only mildly stiff, and there the explicit ``Tsit5`` is as accurate as the
    implicit ``Kvaerno5`` at a small fraction of its cost (docs/performance.md). For stiff systems
    (a motor with its inductance, bristles with sigma0 near its upper bound) pass
    ``diffrax.Kvaerno5()``: ``Tsit5`` stays correct there but needs many small steps, and reports
    :data:`RESULT_SOLVER_FAILED` if it runs out of ``max_steps``.
    ``adjoint`` is diffrax's: the default differentiates in reverse mode (``jax.grad``); pass
    ``diffrax.ForwardMode()`` for ``jax.jacfwd`` (e.g. Levenberg-Marquardt's Jacobians).

    The default of :func:`simulate`. With the defaults, position agrees with a stiff scipy
    reference (LSODA, rtol 1e-11) to 1e-6 deg and torque to 1e-4 N*m on staircases with steps on
    and off the sample grid, ramps and sines (``tests/test_simulate_reference.py``). A lane whose
    solve fails reports :data:`RESULT_SOLVER_FAILED` (``throw=False``); under ``vmap`` every lane
    takes the slowest lane's steps.
    """

    solver: diffrax.AbstractSolver = eqx.field(static=True, default_factory=diffrax.Tsit5)
    rtol: float = eqx.field(static=True, default=1e-8)
    atol: float = eqx.field(static=True, default=1e-10)
    max_steps: int = eqx.field(static=True, default=200_000)
    dt0: float = eqx.field(static=True, default=1e-4)
    dtmax: float = eqx.field(static=True, default=0.02)
    adjoint: diffrax.AbstractAdjoint = eqx.field(static=True, default_factory=diffrax.RecursiveCheckpointAdjoint)

    def __check_init__(self):
        if not isinstance(self.solver, diffrax.AbstractAdaptiveSolver):
            raise ValueError(f"Adaptive needs an adaptive diffrax solver (e.g. Tsit5, Kvaerno5), got "
                             f"{type(self.solver).__name__}")
        for name in ("rtol", "atol", "dt0", "dtmax"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0):
                raise ValueError(f"Adaptive.{name} must be a positive number, got {v!r}")
        if not (isinstance(self.max_steps, int) and self.max_steps > 0):
            raise ValueError(f"Adaptive.max_steps must be a positive integer, got {self.max_steps!r}")

    def describe(self) -> str:
        return (f"Adaptive({type(self.solver).__name__}(), rtol={self.rtol!r}, atol={self.atol!r}, "
                f"max_steps={self.max_steps!r})")


class LaneAdaptive(AbstractStepping):
    """Error-controlled stepping with a step size of each lane's own, for batches: explicit
    ``solver`` (``Tsit5`` or ``Dopri5``) at ``rtol``/``atol`` (largest component error per step,
    relative to the state's size), steps landing on the reference's discontinuities
    (``jump_times``), at most ``dtmax`` [s] (rounded to whole sample periods), ``dt0`` the first
    step, at most ``max_steps`` step attempts.

    Under ``vmap`` :class:`Adaptive` (diffrax) makes every lane pay the bookkeeping of diffrax's
    general loop on every step; here a step is the unrolled stages, an embedded error estimate and
    an integral controller, and samples are cubic-Hermite interpolated from the step's end values
    and slopes. A lane that runs out of ``max_steps`` (or whose step collapses) reports
    :data:`RESULT_SOLVER_FAILED`. Forward mode differentiation (``jax.jvp``, ``jax.jacfwd``) works;
    reverse mode does not (a ``while_loop``): use :class:`FixedStep` or :class:`Adaptive` for
    ``jax.grad``. The default stepping of a batch of concrete arrays (:func:`default_stepping`). At
    its defaults every lane of the scipy-loop benchmark is within 1e-6 deg of a tight solve. Whole
    trajectories on XLA:CPU come 2.5-3x as fast as with :class:`Adaptive`; with ``SaveAt(fn=...)``
    only the function's values are written per sample (the positions alone: 2.5x faster again),
    and with ``SaveAt(mean=...)`` nothing is (docs/performance.md).
    """

    solver: diffrax.AbstractSolver = eqx.field(static=True, default_factory=diffrax.Tsit5)
    rtol: float = eqx.field(static=True, default=1e-6)
    atol: float = eqx.field(static=True, default=1e-9)
    dtmax: float = eqx.field(static=True, default=0.04)
    dt0: float = eqx.field(static=True, default=1e-3)
    max_steps: int = eqx.field(static=True, default=200_000)

    def __check_init__(self):
        if not isinstance(self.solver, (diffrax.Tsit5, diffrax.Dopri5)):
            raise TypeError(f"LaneAdaptive needs diffrax.Tsit5() or diffrax.Dopri5(), got "
                            f"{type(self.solver).__name__}")
        for name in ("rtol", "atol", "dt0", "dtmax"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0):
                raise ValueError(f"LaneAdaptive.{name} must be a positive number, got {v!r}")
        if not (isinstance(self.max_steps, int) and self.max_steps > 0):
            raise ValueError(f"LaneAdaptive.max_steps must be a positive integer, got {self.max_steps!r}")

    def describe(self) -> str:
        return (f"LaneAdaptive({type(self.solver).__name__}(), rtol={self.rtol!r}, atol={self.atol!r}, "
                f"dtmax={self.dtmax!r})")


class SaveAt(eqx.Module):
    """What :func:`simulate` returns for each lane (as diffrax's ``SaveAt``). At most one of
    ``fn``, ``reduce`` and ``mean`` is given.

    * ``SaveAt()``: the whole :class:`Solution` at every sample.
    * ``SaveAt(fn=g)``: as diffrax's ``fn``, ``g`` applied at every saved time: ``g(sample)`` of
      each :class:`Sample`, the outputs stacked along a leading sample axis, returned as a
      :class:`SampleValues` (``value``, and the lane's ``result`` code). ``g`` sees what
      ``SaveAt(mean=g)`` sees, and its values equal the :class:`Solution`'s at the same samples.
    * ``SaveAt(reduce=f)``: ``f(solution)`` of each lane, computed inside the jitted call (e.g. a
      loss or a control metric), so memory no longer grows with the number of samples. The lane's
      ``Solution.result`` is visible to ``f``: combine with :func:`trajectory_loss`.
    * ``SaveAt(mean=g)``: a :class:`SampleMean`, the mean of ``g(sample)`` over every sample,
      accumulated inside the time loop: nothing of the trajectory is stored, and a gradient's
      backward pass reads no trajectory of cotangents; the fast path for losses that are means over
      samples (``Sample.index`` looks up measured data).
    """

    fn: Callable | None = eqx.field(static=True, default=None)
    reduce: Callable | None = eqx.field(static=True, default=None)
    mean: Callable | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        given = [name for name in ("fn", "reduce", "mean") if getattr(self, name) is not None]
        for name in given:
            f = getattr(self, name)
            if not callable(f):
                raise TypeError(f"SaveAt.{name} must be a function, got {type(f).__name__}")
        if len(given) > 1:
            raise ValueError(f"SaveAt: give one of fn (a function of each Sample, stacked over samples), "
                             f"reduce (a function of the whole Solution) or mean (a function of one Sample, "
                             f"averaged over samples), got {' and '.join(given)}")


class Lanes(eqx.Module):
    """How a batched call spreads its lanes: ``chunk_size`` lanes at a time (``lax.map`` over
    ``vmap``-ed chunks, so memory stays bounded) and over host devices (``shard``: ``True`` always,
    ``False`` never, ``None`` when the call has enough work to pay for the split; see
    docs/performance.md). An implicit solver (``Adaptive(diffrax.Kvaerno5())``) is never split:
    its linear solves fail inside ``shard_map``.

    ``chunk_size=None`` chooses from the device the call runs on: on a CPU 200 lanes (a step's
    working set stays in cache); on a GPU or TPU as many lanes as half its free memory holds (every
    lane in one chunk when they fit), so that its cores are filled. Results do not depend on the
    chunking: a fixed step gives the same numbers to 1e-12 relative whatever ``chunk_size``
    (``tests/test_lanes_layout.py``)."""

    chunk_size: int | None = eqx.field(static=True, default=None)
    shard: bool | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        if self.chunk_size is not None and not (isinstance(self.chunk_size, int) and self.chunk_size > 0):
            raise ValueError(f"Lanes.chunk_size must be a positive integer or None, got {self.chunk_size!r}")
