"""The sweep SPEC (JSON): which scenario, which parameters over which box, which plan, which outputs.

Schema (``?`` = optional)::

    {
      "scenario":  {<a simulate scenario, see lugre_jax.io>} | "path/to/scenario.json" (relative to the SPEC),
      "problem":   {"num_vars"?, "names": ["friction.Fs", "controller.ki", "reference.levels[0]", ...],
                    "bounds": [[lo, hi], ...]},          (SALib's problem dict; names are dotted paths)
      "sampler":   "sobol" | "lhs" | "grid",
      "n":         sobol: base points, a power of two (runs: n*(D+2), or n*(2D+2) with second_order);
                   lhs: points; grid: levels per name,
      "seed":      integer (sampling and bootstrap),
      "outputs":   ["dead_zone", "creep_amplitude", "band_fraction", "tracking_error", "stick_slip",
                    or {"metric": <one of those>, "name"?, "window"?, "band"?, "threshold"?}],
      "second_order"?: false (sobol),  "levels"?: [k per name] (grid),
      "stepping"?: {"solver": "bosh3"|"tsit5"|..., "dt": s}   a fast fixed step, or
                   {"solver"?: "tsit5"|"dopri5", "rtol": 1e-6, "atol"?: 1e-9}   each lane its own
                   error-controlled step (LaneAdaptive; a tolerance given); default: the
                   scenario's fixed solver section, else LaneAdaptive at its defaults,
      "fallback"?: {"rtol"?, "atol"?, "max_steps"?} | null   stiff Kvaerno5 re-solve of failed lanes,
      "chunk_size"?: points per chunk file (default 4096), "num_resamples"?: 100, "conf_level"?: 0.95,
      "accuracy"?: {"lanes"?: 8, "rtol"?: 0.01, "enforce"?: true} | null
                   before the run, ``lanes`` points spread over the box (a scrambled Sobol' design)
                   are solved by the fast stepping (with its fallback) and by a tight stiff solve;
                   the largest deviation of each output goes into summary.json and indices.json,
                   and a deviation above ``rtol`` times the output's largest magnitude on those
                   lanes refuses the sweep (ValueError naming SPEC.accuracy.rtol) unless
                   ``enforce`` is false; null: no check
    }
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import math
from pathlib import Path as FsPath
from typing import Any

import diffrax

from .._simulation import Adaptive, FixedStep, LaneAdaptive
from ..io import read_json
from ..scenario import FIXED_SOLVERS, LANE_SOLVERS, scenario_from_dict
from ._metrics import METRICS, AbstractMetric
from ._paths import Path, parse_path
from ._problem import check_problem
from ._sample import AbstractSampler, Grid, LatinHypercube, Saltelli

_TOP = {"scenario", "problem", "sampler", "n", "seed", "outputs", "second_order", "levels", "stepping",
        "fallback", "chunk_size", "num_resamples", "conf_level", "accuracy"}


# The stiff re-solve's defaults: looser than simulate's (1e-8/1e-10) because a metric over a
# window, not a trajectory, is kept; tight enough that its metrics agree with the fast step's.
STIFF_DEFAULT = dict(rtol=1e-6, atol=1e-9, max_steps=100_000)


@dataclasses.dataclass(frozen=True)
class AccuracyCheck:
    """The sweep's check of its fast stepping against a tight solve (SPEC key ``accuracy``)."""

    lanes: int = 8
    rtol: float = 0.01
    enforce: bool = True


@dataclasses.dataclass(frozen=True)
class SweepSpec:
    """A checked SPEC. ``raw`` is its normalised JSON (the scenario inlined): what the DIR's hash
    is taken of."""

    raw: dict
    system: Any
    duration_s: float
    sample_hz: float
    names: tuple[str, ...]
    bounds: Any
    paths: tuple[Path, ...]
    sampler: AbstractSampler
    n: int
    seed: int
    outputs: tuple[AbstractMetric, ...]
    fast: FixedStep | LaneAdaptive
    stiff: Adaptive | None
    chunk_size: int
    num_resamples: int
    conf_level: float
    accuracy: AccuracyCheck | None = AccuracyCheck()

    @property
    def problem(self) -> dict:
        return {"num_vars": len(self.names), "names": list(self.names), "bounds": self.bounds.tolist()}

    @property
    def output_names(self) -> tuple[str, ...]:
        return tuple(m.name for m in self.outputs)

    def digest(self) -> str:
        # a SPEC without a stepping key runs the default, which is part of what its outputs depend
        # on: a folder swept with another default is not resumed with this one
        raw = self.raw if "stepping" in self.raw else self.raw | {"default_stepping": self.fast.describe()}
        return hashlib.sha256(json.dumps(raw, sort_keys=True).encode()).hexdigest()


def _int(d, key, where, default=None, lo=1):
    v = d.get(key, default)
    if isinstance(v, bool) or not isinstance(v, int) or v < lo:
        raise ValueError(f"{where}.{key}: expected an integer >= {lo}, got {v!r}")
    return v


def _pos(d, key, where, default):
    v = d.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
        raise ValueError(f"{where}.{key}: expected a positive number, got {v!r}")
    return float(v)


def _fast_stepping(s, where, sample_hz) -> FixedStep | LaneAdaptive:
    """SPEC ``stepping``: ``{"solver"?, "dt"?}`` a fixed step (dt 2.5e-3 s by default),
    ``{"solver"?, "rtol", "atol"?}`` (a tolerance given) :class:`LaneAdaptive`."""
    lane = isinstance(s, dict) and ("rtol" in s or "atol" in s)
    if isinstance(s, dict) and not lane and not sorted(set(s) - {"solver", "dt"}):
        name = s.get("solver", "tsit5")
        if name not in FIXED_SOLVERS:
            raise ValueError(f"{where}.solver: expected one of {', '.join(FIXED_SOLVERS)}, got {name!r}")
        fast = FixedStep(FIXED_SOLVERS[name](), dt=_pos(s, "dt", where, 2.5e-3))
        try:
            fast.check(sample_hz)
        except ValueError as e:
            raise ValueError(f"{where}.dt: {e}") from None
        return fast
    if lane and not sorted(set(s) - {"solver", "rtol", "atol"}):
        name = s.get("solver", "tsit5")
        if name not in LANE_SOLVERS:
            raise ValueError(f"{where}.solver: expected one of {', '.join(LANE_SOLVERS)} with rtol/atol, got {name!r}")
        d = LaneAdaptive()
        return LaneAdaptive(LANE_SOLVERS[name](), rtol=_pos(s, "rtol", where, d.rtol), atol=_pos(s, "atol", where, d.atol))
    raise ValueError(f"{where}: expected {{\"solver\": one of {', '.join(FIXED_SOLVERS)}, \"dt\": seconds}} (a fixed "
                     f"step) or {{\"solver\"?: one of {', '.join(LANE_SOLVERS)}, \"rtol\", \"atol\"?}} (each lane "
                     f"its own adaptive step)")


def _outputs(spec_outputs, where) -> tuple[AbstractMetric, ...]:
    if not isinstance(spec_outputs, list) or not spec_outputs:
        raise ValueError(f"{where}: expected a non-empty list of metrics ({', '.join(METRICS)})")
    out = []
    for i, o in enumerate(spec_outputs):
        w = f"{where}[{i}]"
        o = {"metric": o} if isinstance(o, str) else o
        if not isinstance(o, dict) or o.get("metric") not in METRICS:
            got = o.get("metric") if isinstance(o, dict) else o
            raise ValueError(f"{w}: expected one of {', '.join(METRICS)} (or an object with 'metric'), got {got!r}")
        cls = METRICS[o["metric"]]
        allowed = {"metric", "name", "window"} | {"band_fraction": {"band"}, "stick_slip": {"threshold"}}.get(o["metric"], set())
        extra = sorted(set(o) - allowed)
        if extra:
            raise ValueError(f"{w}: unknown key '{extra[0]}' for {o['metric']} (expected: {', '.join(sorted(allowed))})")
        kw = {"name": o.get("name", o["metric"])}
        if not isinstance(kw["name"], str) or not kw["name"]:
            raise ValueError(f"{w}.name: expected a non-empty string, got {kw['name']!r}")
        if "window" in o:
            kw["window"] = _pos(o, "window", w, None)
            if kw["window"] > 1:
                raise ValueError(f"{w}.window: expected a fraction of the record in (0, 1], got {kw['window']}")
        for k in ("band", "threshold"):
            if k in o:
                kw[k] = _pos(o, k, w, None)
        out.append(cls(**kw))
    names = [m.name for m in out]
    dup = [n for n in names if names.count(n) > 1]
    if dup:
        raise ValueError(f"{where}: output name '{dup[0]}' appears twice; give one a 'name'")
    return tuple(out)


def spec_from_dict(d: Any, where: str = "SPEC", base_dir: FsPath | None = None) -> SweepSpec:
    """Check a parsed SPEC against its scenario; every error is one ``ValueError`` line naming
    ``where`` and the key."""
    if not isinstance(d, dict):
        raise ValueError(f"{where}: expected a JSON object, got {type(d).__name__}")
    extra = sorted(set(d) - _TOP)
    if extra:
        raise ValueError(f"{where}: unknown key '{extra[0]}' (expected one of: {', '.join(sorted(_TOP))})")
    for k in ("scenario", "problem", "sampler", "n", "seed", "outputs"):
        if k not in d:
            raise ValueError(f"{where}: missing required key '{k}'")
    raw = copy.deepcopy(d)
    scen = d["scenario"]
    if isinstance(scen, str):
        p = FsPath(scen) if base_dir is None or FsPath(scen).is_absolute() else FsPath(base_dir) / scen
        try:
            scen = read_json(p, "scenario JSON file")
        except ValueError as e:
            raise ValueError(f"{where}.scenario: {e}") from None
        except OSError as e:
            raise ValueError(f"{where}.scenario: cannot read {p} ({e.strerror})") from None
        raw["scenario"] = scen
    try:
        system, opts = scenario_from_dict(scen)
    except ValueError as e:
        raise ValueError(f"{where}.scenario: {e}") from None
    names, bounds = check_problem(d["problem"], f"{where}.problem")
    paths = []
    for i, name in enumerate(names):
        p = parse_path(name, system, f"{where}.problem.names[{i}]")
        if p.bounds is not None and not (p.bounds[0] <= bounds[i, 0] and bounds[i, 1] <= p.bounds[1]):
            raise ValueError(f"{where}.problem.bounds[{i}] ({name}): [{bounds[i, 0]:g}, {bounds[i, 1]:g}] leaves the "
                             f"parameter's range [{p.bounds[0]:g}, {p.bounds[1]:g}] {p.unit or ''}".rstrip())
        paths.append(p)
    # Two names writing the same number would silently keep only the last.
    keys = [(p.steps, p.element) for p in paths]
    for i, k in enumerate(keys):
        if keys.index(k) != i:
            raise ValueError(f"{where}.problem.names[{i}] '{names[i]}': the same parameter as names[{keys.index(k)}]")
    n = d["n"]
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ValueError(f"{where}.n: expected a positive integer, got {n!r}")
    kind = d["sampler"]
    if kind == "sobol":
        so = d.get("second_order", False)
        if not isinstance(so, bool):
            raise ValueError(f"{where}.second_order: expected true or false, got {so!r}")
        sampler: AbstractSampler = Saltelli(calc_second_order=so)
    elif kind == "lhs":
        sampler = LatinHypercube()
    elif kind == "grid":
        lv = d.get("levels")
        if lv is not None and (not isinstance(lv, list) or not all(isinstance(k, int) and not isinstance(k, bool) for k in lv)):
            raise ValueError(f"{where}.levels: expected a list of integers (one per name), got {lv!r}")
        sampler = Grid(tuple(lv) if lv else None)
    else:
        raise ValueError(f"{where}.sampler: expected \"sobol\", \"lhs\" or \"grid\", got {kind!r}")
    for k in ("second_order",):
        if k in d and kind != "sobol":
            raise ValueError(f"{where}.{k}: only for the sobol sampler")
    if "levels" in d and kind != "grid":
        raise ValueError(f"{where}.levels: only for the grid sampler")
    bad = sampler.check_n(n, len(names))
    if bad:
        raise ValueError(f"{where}.n: {bad}")
    seed = d["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"{where}.seed: expected an integer >= 0, got {seed!r}")
    outputs = _outputs(d["outputs"], f"{where}.outputs")
    if "stepping" in d:
        fast = _fast_stepping(d["stepping"], f"{where}.stepping", opts["sample_hz"])
    elif isinstance(opts.get("stepping"), FixedStep):
        fast = opts["stepping"]
    else:
        # Each lane its own step: accurate on every lane without a fallback, and on stiff corners of
        # a box faster than a fixed step that must re-solve them (docs/sweeps.md, Performance).
        fast = LaneAdaptive()
    fb = d.get("fallback", {})
    if fb is None:
        stiff = None
    elif isinstance(fb, dict) and not sorted(set(fb) - {"rtol", "atol", "max_steps"}):
        w = f"{where}.fallback"
        stiff = Adaptive(diffrax.Kvaerno5(), rtol=_pos(fb, "rtol", w, STIFF_DEFAULT["rtol"]),
                         atol=_pos(fb, "atol", w, STIFF_DEFAULT["atol"]),
                         max_steps=_int(fb, "max_steps", w, STIFF_DEFAULT["max_steps"]))
    else:
        raise ValueError(f"{where}.fallback: expected null or {{\"rtol\", \"atol\", \"max_steps\"}}")
    chunk = _int(d, "chunk_size", where, 4096)
    nres = _int(d, "num_resamples", where, 100, lo=2)
    conf = d.get("conf_level", 0.95)
    if isinstance(conf, bool) or not isinstance(conf, (int, float)) or not 0 < conf < 1:
        raise ValueError(f"{where}.conf_level: expected a number in (0, 1), got {conf!r}")
    acc = d.get("accuracy", {})
    if acc is None:
        accuracy = None
    elif isinstance(acc, dict) and not sorted(set(acc) - {"lanes", "rtol", "enforce"}):
        enforce = acc.get("enforce", True)
        if not isinstance(enforce, bool):
            raise ValueError(f"{where}.accuracy.enforce: expected true or false, got {enforce!r}")
        accuracy = AccuracyCheck(_int(acc, "lanes", f"{where}.accuracy", 8),
                                 _pos(acc, "rtol", f"{where}.accuracy", 0.01), enforce)
    else:
        raise ValueError(f'{where}.accuracy: expected null or {{"lanes", "rtol", "enforce"}}')
    return SweepSpec(raw, system, opts["duration_s"], opts["sample_hz"], tuple(names), bounds, tuple(paths),
                     sampler, n, seed, outputs, fast, stiff, chunk, nres, float(conf), accuracy)


def load_spec(path) -> SweepSpec:
    """Read and check a SPEC file; errors are one line starting with the file's path."""
    path = FsPath(path)
    try:
        d = read_json(path, "SPEC file")
    except OSError as e:
        raise ValueError(f"{path}: cannot read ({e.strerror})") from None
    return spec_from_dict(d, f"{path}: SPEC", path.parent)
