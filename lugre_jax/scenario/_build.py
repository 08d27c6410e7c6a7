"""Scenario files for ``lugre-jax simulate`` and sweeps: JSON -> :class:`lugre_jax.System`, with
errors that name the key and what was expected. Above the simulator (it builds systems from
``friction``, ``plant``, ``control`` and ``_simulation``); ``lugre_jax.io`` only reads the JSON.

Units are the paper's: deg, deg/s, N*m, s. Schema (``?`` = optional)::

    {
      "friction":   "paper" | {"model": "lugre", "Fc", "Fs", "vs", "sigma0", "sigma1", "sigma2", "delta"?}
                   | {"model": "segmented", "edges": [deg/s, ...], "segments": [<lugre>, ...], "blend"?: 0.1}
                     (one edge fewer than segments, ascending and positive; each segment a
                     "lugre" object, its "model" key optional),
      "joint":      {"J", "gravity_nm"?, "gravity_phase_deg"?},
      "motor"?:     {"R"?, "L"?, "Ke"?, "Km"?, "gear_ratio"?, "u_max"?, "neglect_inductance"?},
      "controller": {"type": "open_loop", "bias"?, "gain"?, "rate"?}
                  | {"type": "open_loop_voltage", "bias"?, "gain"?}   (needs "motor")
                  | {"type": "velocity_pid", "kp", "ki"?, "kd"?, "tf"?}
                  | {"type": "position_pid", "kpp", "kp", "ki"?, "kd"?, "kip"?, "tf"?}
                  | {"type": "lugre_compensated", "inner": <velocity_pid|position_pid>,
                     "observer": <friction>, "k_obs"?, "J_ff"?},
      "reference":  {"type": "velocity_steps", "levels": [deg/s...], "dwell_s"?, "t0"?}
                  | {"type": "velocity_step", "velocity_deg_s", "t0"?}
                  | {"type": "ramp", "v_final", "ramp_s"}
                  | {"type": "position_sine", "amplitude_deg", "frequency_hz"},
      "duration_s", "sample_hz"?: 100,
      "initial"?:   {"theta"?, "omega"?, "z"?},
      "solver"?:    {"method"?: "adaptive" (default) | "fixed", "name"?, "dt"?, "rtol"?, "atol"?,
                     "max_steps"?}
    }

``reference`` may also be ``{"type": "velocity_table", "times_s": [s...], "velocities_deg_s": [...]}``
(piecewise linear; a repeated time is a step). ``solver`` becomes a stepping object:
``"adaptive"`` -> :class:`lugre_jax.Adaptive` (``name`` one of tsit5 (default), dopri5, kvaerno5
for stiff systems, kvaerno3;
``rtol``, ``atol``, ``max_steps``), ``"fixed"`` -> :class:`lugre_jax.FixedStep` (``name`` one of
tsit5, bosh3, heun, ralston, midpoint, dopri5; ``dt`` [s], default 2.5e-3 s or the sample period if
shorter). Without a ``solver`` section the scenario is solved adaptively (correct by default).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import diffrax
import numpy as np

from .. import control as C
from .._simulation import N_STATES, STATE_NAMES, Adaptive, FixedStep, System
from ..friction import LuGre, Segmented
from ..plant import DCMotor, IdealTorque, Joint, paper_friction
from ..io import read_json


class ScenarioError(ValueError):
    """A scenario that cannot be used; the message names the key and what was expected."""


def _num(d: dict, key: str, where: str, default: Any = None, *, positive=False, nonneg=False):
    if key not in d:
        if default is None:
            raise ScenarioError(f"{where}: missing required key '{key}' (a number)")
        return default
    v = d[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ScenarioError(f"{where}.{key}: expected a finite number, got {v!r}")
    if positive and not v > 0:
        raise ScenarioError(f"{where}.{key}: expected a number > 0, got {v!r}")
    if nonneg and v < 0:
        raise ScenarioError(f"{where}.{key}: expected a number >= 0, got {v!r}")
    return float(v)


def _obj(d: Any, where: str) -> dict:
    if not isinstance(d, dict):
        raise ScenarioError(f"{where}: expected an object {{...}}, got {type(d).__name__}")
    return d


def _only(d: dict, allowed: set[str], where: str) -> None:
    extra = sorted(set(d) - allowed)
    if extra:
        raise ScenarioError(f"{where}: unknown key '{extra[0]}' (expected one of: {', '.join(sorted(allowed))})")


_LUGRE_KEYS = {"model", "Fc", "Fs", "vs", "sigma0", "sigma1", "sigma2", "delta"}


def _lugre(d: dict, where: str) -> LuGre:
    _only(d, _LUGRE_KEYS, where)
    kw = {k: _num(d, k, where, nonneg=True) for k in ("Fc", "Fs", "sigma0", "sigma1", "sigma2")}
    kw["vs"] = _num(d, "vs", where, positive=True)
    kw["delta"] = _num(d, "delta", where, 2.0, positive=True)
    if kw["Fs"] < kw["Fc"]:
        raise ScenarioError(f"{where}.Fs: expected a static friction >= Fc = {kw['Fc']!r} N*m (the "
                            f"Stribeck curve falls from Fs to Fc), got {kw['Fs']!r}")
    # a scenario (or a sweep over it) may hold a non-passive set on purpose (the paper's segment 1):
    # built silently, so that a CLI error stays one line
    return LuGre(**kw, require_passive=False)


def parse_friction(spec: Any, where: str = "friction"):
    """``"paper"``, a LuGre object, or a segmented object -> friction model."""
    if spec == "paper":
        return paper_friction()
    d = _obj(spec, where)
    model = d.get("model")
    if model == "lugre":
        return _lugre(d, where)
    if model == "segmented":
        _only(d, {"model", "edges", "segments", "blend"}, where)
        segs = d.get("segments")
        if not isinstance(segs, list) or not segs:
            raise ScenarioError(f"{where}.segments: expected a non-empty list of lugre objects")
        models = tuple(_lugre({"model": "lugre", **_obj(s, f"{where}.segments[{i}]")},
                              f"{where}.segments[{i}]") for i, s in enumerate(segs))
        edges = d.get("edges")
        if (not isinstance(edges, list) or len(edges) != len(models) - 1
                or not all(isinstance(e, (int, float)) and e > 0 for e in edges)
                or list(edges) != sorted(edges)):
            raise ScenarioError(
                f"{where}.edges: expected {len(models) - 1} ascending positive velocities [deg/s] "
                f"(one fewer than segments), got {edges!r}"
            )
        blend = _num(d, "blend", where, 0.1, nonneg=True)
        return Segmented(models, np.asarray(edges, float), blend=blend)
    raise ScenarioError(f"{where}.model: expected \"lugre\" or \"segmented\" (or friction: \"paper\"), got {model!r}")


def _controller(d: Any, where: str = "controller"):
    d = _obj(d, where)
    kind = d.get("type")
    if kind == "open_loop":
        _only(d, {"type", "bias", "gain", "rate"}, where)
        return C.OpenLoop(bias=_num(d, "bias", where, 0.0), gain=_num(d, "gain", where, 0.0),
                          rate=_num(d, "rate", where, 0.0))
    if kind == "open_loop_voltage":
        _only(d, {"type", "bias", "gain"}, where)
        return C.OpenLoopVoltage(bias=_num(d, "bias", where, 0.0), gain=_num(d, "gain", where, 0.0))
    if kind == "velocity_pid":
        _only(d, {"type", "kp", "ki", "kd", "tf"}, where)
        return C.VelocityPID(kp=_num(d, "kp", where, nonneg=True), ki=_num(d, "ki", where, 0.0, nonneg=True),
                             kd=_num(d, "kd", where, 0.0, nonneg=True), tf=_num(d, "tf", where, 1e-2, positive=True))
    if kind == "position_pid":
        _only(d, {"type", "kpp", "kp", "ki", "kd", "kip", "tf"}, where)
        return C.PositionPID(kpp=_num(d, "kpp", where, nonneg=True), kp=_num(d, "kp", where, nonneg=True),
                             ki=_num(d, "ki", where, 0.0, nonneg=True), kd=_num(d, "kd", where, 0.0, nonneg=True),
                             kip=_num(d, "kip", where, 0.0, nonneg=True), tf=_num(d, "tf", where, 1e-2, positive=True))
    if kind == "lugre_compensated":
        _only(d, {"type", "inner", "observer", "k_obs", "J_ff"}, where)
        if "inner" not in d or "observer" not in d:
            raise ScenarioError(f"{where}: lugre_compensated needs 'inner' (a velocity_pid or position_pid) and 'observer' (a friction model)")
        inner = _controller(d["inner"], f"{where}.inner")
        if not isinstance(inner, (C.VelocityPID, C.PositionPID)):
            raise ScenarioError(f"{where}.inner.type: expected \"velocity_pid\" or \"position_pid\"")
        return C.LuGreCompensated(inner=inner, observer=parse_friction(d["observer"], f"{where}.observer"),
                                  k_obs=_num(d, "k_obs", where, 1.0, nonneg=True), J_ff=_num(d, "J_ff", where, 0.0, nonneg=True))
    raise ScenarioError(
        f"{where}.type: expected one of \"open_loop\", \"open_loop_voltage\", \"velocity_pid\", "
        f"\"position_pid\", \"lugre_compensated\", got {kind!r}"
    )


def _reference(d: Any, where: str = "reference"):
    d = _obj(d, where)
    kind = d.get("type")
    if kind == "velocity_steps":
        _only(d, {"type", "levels", "dwell_s", "t0"}, where)
        lv = d.get("levels")
        if not isinstance(lv, list) or not lv or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in lv):
            raise ScenarioError(f"{where}.levels: expected a non-empty list of velocities [deg/s], got {lv!r}")
        return C.VelocitySteps(np.asarray(lv, float), _num(d, "dwell_s", where, np.inf, positive=True),
                               _num(d, "t0", where, 0.0, nonneg=True))
    if kind == "velocity_step":
        _only(d, {"type", "velocity_deg_s", "t0"}, where)
        return C.VelocitySteps(np.asarray([_num(d, "velocity_deg_s", where)]), np.inf, _num(d, "t0", where, 0.0, nonneg=True))
    if kind == "ramp":
        _only(d, {"type", "v_final", "ramp_s"}, where)
        return C.VelocityRamp(_num(d, "v_final", where), _num(d, "ramp_s", where, positive=True))
    if kind == "position_sine":
        _only(d, {"type", "amplitude_deg", "frequency_hz"}, where)
        return C.PositionSine(_num(d, "amplitude_deg", where), _num(d, "frequency_hz", where, positive=True))
    if kind == "velocity_table":
        _only(d, {"type", "times_s", "velocities_deg_s"}, where)
        cols = {}
        for k in ("times_s", "velocities_deg_s"):
            v = d.get(k)
            if (not isinstance(v, list) or not v
                    or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v)):
                raise ScenarioError(f"{where}.{k}: expected a non-empty list of finite numbers, got {v!r}")
            cols[k] = v
        t = cols["times_s"]
        if len(t) != len(cols["velocities_deg_s"]):
            raise ScenarioError(f"{where}: times_s and velocities_deg_s must have the same length "
                                f"({len(t)} and {len(cols['velocities_deg_s'])})")
        if t[0] < 0 or any(b < a for a, b in zip(t, t[1:])):
            raise ScenarioError(f"{where}.times_s: expected non-decreasing times >= 0 s")
        return C.VelocityTable(np.asarray(t, float), np.asarray(cols["velocities_deg_s"], float))
    raise ScenarioError(
        f"{where}.type: expected one of \"velocity_steps\", \"velocity_step\", \"ramp\", \"position_sine\", "
        f"\"velocity_table\", got {kind!r}"
    )


# The solver names files may use (scenario "solver.name", sweep SPEC "stepping.solver").
FIXED_SOLVERS = {"tsit5": diffrax.Tsit5, "bosh3": diffrax.Bosh3, "heun": diffrax.Heun, "ralston": diffrax.Ralston,
                 "midpoint": diffrax.Midpoint, "dopri5": diffrax.Dopri5}
ADAPTIVE_SOLVERS = {"kvaerno5": diffrax.Kvaerno5, "kvaerno3": diffrax.Kvaerno3, "tsit5": diffrax.Tsit5,
                    "dopri5": diffrax.Dopri5}
# explicit with an embedded error estimate: what lugre_jax.LaneAdaptive runs (sweep SPEC "stepping"
# with a tolerance)
LANE_SOLVERS = {"tsit5": diffrax.Tsit5, "dopri5": diffrax.Dopri5}


def _stepping(s: Any, sample_hz: float):
    """The ``solver`` section -> a stepping object (names in a file map to diffrax solvers)."""
    s = _obj(s, "solver")
    _only(s, {"method", "dt", "name", "rtol", "atol", "max_steps"}, "solver")
    method = s.get("method", "adaptive")
    if method not in ("fixed", "adaptive"):
        raise ScenarioError(f"solver.method: expected \"adaptive\" or \"fixed\", got {method!r}")
    names = FIXED_SOLVERS if method == "fixed" else ADAPTIVE_SOLVERS
    name = s.get("name", "tsit5")
    if name not in names:
        raise ScenarioError(f"solver.name: expected one of {', '.join(sorted(names))} for method "
                            f"\"{method}\", got {name!r}")
    if method == "fixed":
        for k in ("rtol", "atol", "max_steps"):
            if k in s:
                raise ScenarioError(f"solver.{k}: only for method \"adaptive\" (a fixed step has no tolerance)")
        fixed = FixedStep(names[name](), dt=_num(s, "dt", "solver", None, positive=True) if "dt" in s else None)
        try:
            fixed.check(sample_hz)
        except ValueError as e:
            raise ScenarioError(f"solver.dt: {e}") from None
        return fixed
    if "dt" in s:
        raise ScenarioError("solver.dt: only for method \"fixed\" (the adaptive solver chooses its steps)")
    d = Adaptive()
    return Adaptive(names[name](), rtol=_num(s, "rtol", "solver", d.rtol, positive=True),
                    atol=_num(s, "atol", "solver", d.atol, positive=True),
                    max_steps=int(_num(s, "max_steps", "solver", d.max_steps, positive=True)))


TOP_KEYS = {"friction", "joint", "motor", "controller", "reference", "duration_s", "sample_hz", "initial", "solver"}


def scenario_from_dict(d: Any) -> tuple[System, dict]:
    """Build ``(System, run_options)`` from a parsed scenario; raises :class:`ScenarioError`."""
    d = _obj(d, "scenario")
    _only(d, TOP_KEYS, "scenario")
    for k in ("friction", "joint", "controller", "reference", "duration_s"):
        if k not in d:
            raise ScenarioError(f"scenario: missing required key '{k}'")
    friction = parse_friction(d["friction"])
    j = _obj(d["joint"], "joint")
    _only(j, {"J", "gravity_nm", "gravity_phase_deg"}, "joint")
    g = _num(j, "gravity_nm", "joint", 0.0)
    joint = Joint(J=_num(j, "J", "joint", positive=True), gravity_nm=g if g != 0 else 0.0,
                  gravity_phase_deg=_num(j, "gravity_phase_deg", "joint", 0.0))
    controller = _controller(d["controller"])
    if "motor" in d:
        m = _obj(d["motor"], "motor")
        _only(m, {"R", "L", "Ke", "Km", "gear_ratio", "u_max", "neglect_inductance"}, "motor")
        neglect = m.get("neglect_inductance", False)
        if not isinstance(neglect, bool):
            raise ScenarioError(f"motor.neglect_inductance: expected true or false, got {neglect!r}")
        dm = DCMotor()
        actuator = DCMotor(
            R=_num(m, "R", "motor", float(dm.R), positive=True), L=_num(m, "L", "motor", float(dm.L), positive=True),
            Ke=_num(m, "Ke", "motor", float(dm.Ke), positive=True), Km=_num(m, "Km", "motor", float(dm.Km), positive=True),
            gear_ratio=_num(m, "gear_ratio", "motor", float(dm.gear_ratio), positive=True),
            u_max=_num(m, "u_max", "motor", float(dm.u_max), positive=True), neglect_inductance=neglect,
        )
    else:
        if controller.voltage:
            raise ScenarioError("controller.type: open_loop_voltage needs a 'motor' section")
        actuator = IdealTorque()
    reference = _reference(d["reference"])
    y0 = np.zeros(N_STATES)
    if "initial" in d:
        ini = _obj(d["initial"], "initial")
        _only(ini, {"theta", "omega", "z"}, "initial")
        for k in ("theta", "omega", "z"):
            y0[STATE_NAMES.index(k)] = _num(ini, k, "initial", 0.0)
    opts: dict[str, Any] = dict(duration_s=_num(d, "duration_s", "scenario", positive=True),
                                sample_hz=_num(d, "sample_hz", "scenario", 100.0, positive=True))
    n = opts["duration_s"] * opts["sample_hz"]
    if abs(n - round(n)) > 1e-9 * max(1.0, n):
        raise ScenarioError(f"scenario.duration_s*sample_hz must be a whole number of samples, got {n}")
    if n > 5e7:
        raise ScenarioError(f"scenario: {int(n)} samples is too many; lower sample_hz or duration_s")
    if "solver" in d:
        opts["stepping"] = _stepping(d["solver"], opts["sample_hz"])
    system = System(friction=friction, joint=joint, controller=controller, reference=reference,
                    actuator=actuator, y0=y0)
    return system, opts


def load_scenario(path: str | Path) -> tuple[System, dict]:
    """Read a scenario JSON file; errors name the file, and line/column for JSON syntax errors."""
    path = Path(path)
    try:
        d = read_json(path, "scenario JSON file")
    except ValueError as e:
        raise ScenarioError(str(e)) from None
    except OSError as e:
        raise ScenarioError(f"{path}: cannot read ({e.strerror})") from None
    try:
        return scenario_from_dict(d)
    except ScenarioError as e:
        raise ScenarioError(f"{path}: {e}") from None
