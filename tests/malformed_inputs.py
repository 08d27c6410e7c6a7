"""Malformed and unusual inputs for every command, shared by ``tests/test_cli_errors.py`` (in-process,
in CI) and this script, which runs each case as a real ``lugre-jax`` process and writes the table
``docs/errors.md`` (command, exit code, message, traceback, outputs left behind)::

    python tests/malformed_inputs.py [--out docs/errors.md] [--only ID,...]

Each case builds its input files in a fresh folder and returns the argument list; every output path
it names lies in that folder, so "outputs left" is the folder's new files after the command.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from pathlib import Path
from typing import Callable

import numpy as np

# ---------------------------------------------------------------------------------- valid inputs


def _cli_module() -> list[str]:
    """The installed ``lugre-jax`` entry point's module when present (it sets process options before
    the package is imported), else the package's CLI module."""
    root = Path(__file__).resolve().parents[1]
    return ["-m", "lugre_jax_cli"] if (root / "lugre_jax_cli.py").exists() else ["-m", "lugre_jax.cli"]


def recording_text(n: int = 400, dt: float = 0.01, seed: int = 0) -> str:
    """A plausible recording in paper units: a sine sweep with Coulomb + viscous friction and noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    pos = 20 * np.sin(0.5 * t)
    vel = 10 * np.cos(0.5 * t)
    tor = 1.0 * np.tanh(vel / 0.05) + 0.3 * vel + 0.01 * rng.standard_normal(n)
    rows = [f"{a:.6f},{b:.8g},{c:.8g},{d:.8g}" for a, b, c, d in zip(t, pos, vel, tor)]
    return "time_s,position_deg,velocity_deg_s,torque_nm\n" + "\n".join(rows) + "\n"


def stribeck_text(seed: int = 0) -> str:
    """Steady-state data from a Stribeck curve (Fc 1, Fs 2, vs 0.05 deg/s, sigma2 0.5), 3 samples per set-point."""
    rng = np.random.default_rng(seed)
    lines = ["velocity_deg_s,torque_nm,branch"]
    for v in np.geomspace(0.005, 1.5, 20):
        for _ in range(3):
            f = 1 + (2 - 1) * math.exp(-(v / 0.05) ** 2) + 0.5 * v + 0.02 * rng.standard_normal()
            lines.append(f"{v:.6g},{f:.6g},accel")
    return "\n".join(lines) + "\n"


EPOS_HEAD = ("Date:;2020-07-08 21:24:28\r\nMax. samples:;4\r\nRecorded samples:;4\r\nSampling period:;51.200\r\n"
             ";Velocity actual value averaged;Torque actual value averaged\r\nms;rpm;%\r\n")


def epos_text(rpm: float, pct: float) -> str:
    return EPOS_HEAD + "".join(f"{i * 51.2:.1f};{-rpm};{-(pct + 0.1 * (i % 2))}\r\n" for i in range(4))


GOOD_PARAMS = {"J": 0.13, "Fc": 1.0, "Fs": 1.5, "vs": 0.2, "sigma2": 0.3, "sigma0": 100.0, "sigma1": 2.0}

SCENARIO = {"friction": "paper", "joint": {"J": 0.128},
            "controller": {"type": "velocity_pid", "kp": 8.0, "ki": 60.0},
            "reference": {"type": "velocity_step", "velocity_deg_s": 0.02}, "duration_s": 1.0, "sample_hz": 100}

# ----------------------------------------------------------------------------------- the cases


@dataclasses.dataclass(frozen=True)
class Case:
    id: str
    kind: str  # the input class, as the table shows it
    make: Callable[[Path], list[str]]  # builds inputs in the folder, returns argv (without "lugre-jax")
    code: int = 2  # expected exit code
    slow: bool = False  # needs real work before it fails (subprocess table only)


def _w(d: Path, name: str, text: str | bytes) -> str:
    p = d / name
    p.parent.mkdir(parents=True, exist_ok=True)
    (p.write_bytes if isinstance(text, bytes) else p.write_text)(text)
    return str(p)


def _rec_lines() -> list[str]:
    return recording_text().splitlines()


def _diag(d: Path, text: str | bytes, *extra: str) -> list[str]:
    return ["diagnose", _w(d, "rec.csv", text), "--out", str(d / "out" / "report.json"), "--quiet", *extra]


def _diag_params(d: Path, params) -> list[str]:
    text = params if isinstance(params, str) else json.dumps(params)
    return _diag(d, recording_text(), "--params", _w(d, "p.json", text))


def _with(**kw) -> dict:
    p = dict(GOOD_PARAMS)
    p.update(kw)
    return p


def _rec_edit(fn) -> str:
    lines = _rec_lines()
    fn(lines)
    return "\n".join(lines) + "\n"


def _set_cell(lines, row, col, value):
    cells = lines[row].split(",")
    cells[col] = value
    lines[row] = ",".join(cells)


def _irregular() -> str:
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.001, 0.05, 400))
    rows = [f"{x:.6f},{20 * math.sin(0.5 * x):.6g},{10 * math.cos(0.5 * x):.6g},{math.tanh(math.cos(0.5 * x)):.6g}"
            for x in t]
    return "time_s,position_deg,velocity_deg_s,torque_nm\n" + "\n".join(rows) + "\n"


def _still() -> str:
    rows = [f"{0.01 * i:.2f},5,0,{0.1 * math.sin(i):.4f}" for i in range(400)]
    return "time_s,position_deg,velocity_deg_s,torque_nm\n" + "\n".join(rows) + "\n"


def _dup_torque() -> str:
    lines = _rec_lines()
    return "\n".join([lines[0] + ",torque_nm"] + [ln + ",0" for ln in lines[1:]]) + "\n"


def _constant_torque() -> str:
    lines = _rec_lines()
    return "\n".join([lines[0]] + [",".join(ln.split(",")[:3] + ["0.5"]) for ln in lines[1:]]) + "\n"


def _strib_dup() -> str:
    lines = stribeck_text().splitlines()
    return "\n".join([lines[0] + ",torque_nm"] + [ln + ",0" for ln in lines[1:]]) + "\n"


def _ident(d: Path, text: str | bytes | None = None, *extra: str, data: str | None = None) -> list[str]:
    src = data if data is not None else _w(d, "data.csv", stribeck_text() if text is None else text)
    return ["identify", src, "--out", str(d / "out" / "result.json"), "--scheme", "whole", "--method", "pso",
            "--quiet", *extra]


def _strib_edit(fn) -> str:
    lines = stribeck_text().splitlines()
    fn(lines)
    return "\n".join(lines) + "\n"


def _epos_folder(d: Path, bad: str | None = None) -> str:
    f = d / "epos"
    f.mkdir()
    for rpm, pct in ((1, 30), (2, 31), (5, 33), (10, 36), (20, 40)):
        _w(f, f"{rpm}.csv", epos_text(rpm, pct))
    if bad is not None:
        _w(f, "3.csv", bad)
    return str(f)


def _simulate(d: Path, scenario, *extra: str, out: str | None = None) -> list[str]:
    text = scenario if isinstance(scenario, str) else json.dumps(scenario)
    return ["simulate", _w(d, "scenario.json", text), "--out", out or str(d / "out" / "traj.csv"), *extra]


def _scen(**kw) -> dict:
    s = json.loads(json.dumps(SCENARIO))
    for k, v in kw.items():
        s[k] = v
    return s


def _existing_dir(d: Path) -> str:
    (d / "taken").mkdir()
    return str(d / "taken")


def _existing_file(d: Path) -> str:
    return _w(d, "taken.txt", "x")


def _foreign_folder(d: Path) -> str:
    _w(d, "mine/notes.txt", "keep me")
    return str(d / "mine")


def _other_command_folder(d: Path) -> str:
    """A finished result of another command (its MANIFEST.json names it)."""
    _w(d, "theirs/MANIFEST.json", json.dumps({"complete": True, "meta": {"command": "reproduce"}, "files": {}}))
    return str(d / "theirs")


# A folder no file can be created in, even by root (a pseudo file system): the "read-only --out" tries.
UNWRITABLE = "/proc"

# A passive LuGre set (sigma2 >= sigma1 |Fs - Fc| / min(Fc, Fs) over the whole box).
SWEEP_SPEC = {"scenario": dict(SCENARIO, friction={"model": "lugre", "Fc": 1.0, "Fs": 1.5, "vs": 0.05, "sigma0": 100.0,
                                                   "sigma1": 1.0, "sigma2": 1.0}),
              "problem": {"names": ["friction.Fc", "controller.kp"], "bounds": [[0.9, 1.1], [4, 16]]},
              "sampler": "sobol", "n": 4, "seed": 0, "outputs": ["dead_zone"], "stepping": {"solver": "bosh3", "dt": 0.01}}


def _sweep(d: Path, *extra: str, out: str | None = None, **kw) -> list[str]:
    spec = dict(SWEEP_SPEC, **kw)
    return ["sweep", _w(d, "spec.json", json.dumps(spec)), "--out", out or str(d / "out"), "--quiet", *extra]


def _emps(d: Path, *extra: str, out: str | None = None) -> list[str]:
    return ["emps", "--out", out or str(d / "out"), "--quiet", *extra]


CASES: list[Case] = [
    # --- recording CSV (diagnose)
    Case("rec-undecodable", "recording: undecodable bytes (0xff)",
         lambda d: _diag(d, recording_text().encode()[:200] + b"\xff\xfe" + recording_text().encode()[200:])),
    Case("rec-latin1", "recording: Latin-1 header (non-UTF-8)",
         lambda d: _diag(d, recording_text().replace("torque_nm", "torque_nm_\xb0").encode("latin-1"))),
    Case("rec-10-rows", "recording: 10 rows", lambda d: _diag(d, "\n".join(_rec_lines()[:11]) + "\n")),
    Case("rec-never-moves", "recording: the joint never moves", lambda d: _diag(d, _still())),
    Case("rec-irregular-time", "recording: irregular time steps (1-50 ms)", lambda d: _diag(d, _irregular())),
    Case("rec-gap", "recording: one 10-sample gap in time",
         lambda d: _diag(d, "\n".join(_rec_lines()[:200] + _rec_lines()[210:]) + "\n")),
    Case("rec-dup-column", "recording: duplicated torque_nm column (copy all zeros)",
         lambda d: _diag(d, _dup_torque())),
    Case("rec-renamed-column", "recording: column renamed (torque -> torque_Nm)",
         lambda d: _diag(d, recording_text().replace("torque_nm", "torque_Nm"))),
    Case("rec-no-kinematics", "recording: neither position_deg nor velocity_deg_s (both renamed)",
         lambda d: _diag(d, recording_text().replace("position_deg", "pos").replace("velocity_deg_s", "vel"))),
    Case("rec-semicolons", "recording: ';'-separated", lambda d: _diag(d, recording_text().replace(",", ";"))),
    Case("rec-tabs", "recording: tab-separated", lambda d: _diag(d, recording_text().replace(",", "\t"))),
    Case("rec-nan", "recording: NaN cell", lambda d: _diag(d, _rec_edit(lambda ls: _set_cell(ls, 50, 3, "nan")))),
    Case("rec-inf", "recording: inf cell", lambda d: _diag(d, _rec_edit(lambda ls: _set_cell(ls, 60, 2, "inf")))),
    Case("rec-text-cell", "recording: non-numeric cell",
         lambda d: _diag(d, _rec_edit(lambda ls: _set_cell(ls, 70, 1, "12x5")))),
    Case("rec-row-cut", "recording: row cut short",
         lambda d: _diag(d, _rec_edit(lambda ls: ls.__setitem__(80, ls[80][:8])))),
    Case("rec-extra-cell", "recording: row with an extra cell",
         lambda d: _diag(d, _rec_edit(lambda ls: ls.__setitem__(90, ls[90] + ",1")))),
    Case("rec-time-backwards", "recording: time goes backwards",
         lambda d: _diag(d, _rec_edit(lambda ls: _set_cell(ls, 100, 0, "0.5")))),
    Case("rec-constant-torque", "recording: torque constant (disconnected sensor)",
         lambda d: _diag(d, _constant_torque())),
    Case("rec-empty", "recording: empty file", lambda d: _diag(d, "")),
    Case("rec-missing", "recording: no such file",
         lambda d: ["diagnose", str(d / "nope.csv"), "--out", str(d / "out" / "r.json")]),
    Case("rec-is-folder", "recording: a folder given",
         lambda d: ["diagnose", _existing_dir(d), "--out", str(d / "out" / "r.json")]),
    # --- diagnose outputs and options
    Case("diag-out-dir", "diagnose: --out names an existing folder",
         lambda d: ["diagnose", _w(d, "rec.csv", recording_text()), "--out", _existing_dir(d)]),
    Case("diag-out-parent-file", "diagnose: --out inside a path that is a file",
         lambda d: ["diagnose", _w(d, "rec.csv", recording_text()), "--out", _existing_file(d) + "/r.json"]),
    Case("diag-plots-file", "diagnose: --plots names an existing file",
         lambda d: _diag(d, recording_text(), "--plots", _existing_file(d))),
    Case("diag-plots-foreign", "diagnose: --plots a non-empty folder not made by diagnose",
         lambda d: _diag(d, recording_text(), "--plots", _foreign_folder(d))),
    Case("diag-out-not-json", "diagnose: --out without .json",
         lambda d: ["diagnose", _w(d, "rec.csv", recording_text()), "--out", str(d / "report.txt")]),
    Case("diag-alpha", "diagnose: --alpha 2", lambda d: _diag(d, recording_text(), "--alpha", "2")),
    Case("diag-candidates", "diagnose: unknown --candidates",
         lambda d: _diag(d, recording_text(), "--candidates", "gravity,warp_drive")),
    Case("diag-block", "diagnose: --block-s -1", lambda d: _diag(d, recording_text(), "--block-s", "-1")),
    Case("diag-resolution", "diagnose: --resolution -0.1",
         lambda d: _diag(d, recording_text(), "--resolution", "-0.1")),
    # --- --params JSON
    Case("par-J0", "--params: J = 0", lambda d: _diag_params(d, _with(J=0))),
    Case("par-vs0", "--params: vs = 0", lambda d: _diag_params(d, _with(vs=0))),
    Case("par-Fc-neg", "--params: Fc = -1", lambda d: _diag_params(d, _with(Fc=-1))),
    Case("par-1e300", "--params: values 1e300", lambda d: _diag_params(d, {k: 1e300 for k in GOOD_PARAMS})),
    Case("par-string", "--params: a string value", lambda d: _diag_params(d, _with(sigma0="100"))),
    Case("par-bool", "--params: a boolean value", lambda d: _diag_params(d, _with(J=True))),
    Case("par-nan", "--params: NaN", lambda d: _diag_params(d, json.dumps(GOOD_PARAMS).replace("2.0", "NaN"))),
    Case("par-Fs-below-Fc", "--params: Fs < Fc, no reason given", lambda d: _diag_params(d, _with(Fs=0.5))),
    Case("par-unknown-key", "--params: unknown key", lambda d: _diag_params(d, _with(sigma3=1.0))),
    Case("par-missing-key", "--params: missing key",
         lambda d: _diag_params(d, {k: v for k, v in GOOD_PARAMS.items() if k != "sigma0"})),
    Case("par-not-json", "--params: not JSON", lambda d: _diag_params(d, "{'J': 1}")),
    Case("par-array", "--params: a JSON array", lambda d: _diag_params(d, [1, 2, 3])),
    Case("par-model", "--params: unknown friction_model", lambda d: _diag_params(d, _with(friction_model="Dahl"))),
    Case("par-units", "--params: 1000x too large for the recording (wrong units)",
         lambda d: _diag_params(d, _with(Fc=1e4, Fs=1.5e4, sigma2=3e3))),
    # --- Stribeck CSV / EPOS (identify)
    Case("str-undecodable", "Stribeck CSV: undecodable bytes",
         lambda d: _ident(d, stribeck_text().encode()[:100] + b"\xff" + stribeck_text().encode()[100:])),
    Case("str-semicolons", "Stribeck CSV: ';'-separated", lambda d: _ident(d, stribeck_text().replace(",", ";"))),
    Case("str-dup-column", "Stribeck CSV: duplicated column",
         lambda d: _ident(d, _strib_dup())),
    Case("str-renamed", "Stribeck CSV: column renamed",
         lambda d: _ident(d, stribeck_text().replace("velocity_deg_s", "velocity"))),
    Case("str-nan", "Stribeck CSV: NaN torque",
         lambda d: _ident(d, _strib_edit(lambda ls: ls.__setitem__(5, ls[5].replace(ls[5].split(",")[1], "nan"))))),
    Case("str-row-cut", "Stribeck CSV: row cut short",
         lambda d: _ident(d, _strib_edit(lambda ls: ls.__setitem__(7, ls[7].split(",")[0])))),
    Case("str-branch", "Stribeck CSV: unknown branch",
         lambda d: _ident(d, _strib_edit(lambda ls: ls.__setitem__(9, ls[9].replace("accel", "up"))))),
    Case("str-few-points", "Stribeck CSV: 3 set-points",
         lambda d: _ident(d, "velocity_deg_s,torque_nm\n0.1,1\n0.2,1.1\n0.4,1.2\n")),
    Case("str-header-only", "Stribeck CSV: header only", lambda d: _ident(d, "velocity_deg_s,torque_nm\n")),
    Case("str-missing", "Stribeck CSV: no such file", lambda d: _ident(d, data=str(d / "nope.csv"))),
    Case("epos-bad-number", "EPOS folder: a file with a non-numeric cell",
         lambda d: _ident(d, data=_epos_folder(d, EPOS_HEAD + "0.0;-3;-32\r\n51.2;-3;abc\r\n"))),
    Case("epos-units", "EPOS folder: a file in rad/s",
         lambda d: _ident(d, data=_epos_folder(d, epos_text(3, 32).replace("ms;rpm;%", "ms;rad/s;%")))),
    Case("epos-empty-folder", "EPOS folder: no .csv files", lambda d: _ident(d, data=_existing_dir(d))),
    Case("id-out-dir", "identify: --out names an existing folder",
         lambda d: ["identify", _w(d, "data.csv", stribeck_text()), "--out", _existing_dir(d)]),
    Case("id-plot-not-png", "identify: --plot not .png", lambda d: _ident(d, None, "--plot", str(d / "fig.pdf"))),
    Case("id-plot-is-out", "identify: --plot names the --out JSON",
         lambda d: ["identify", _w(d, "data.csv", stribeck_text()), "--out", str(d / "r.json"),
                    "--plot", str(d / "r.json")]),
    Case("id-edges", "identify: --edges not two numbers",
         lambda d: ["identify", _w(d, "data.csv", stribeck_text()), "--out", str(d / "r.json"), "--edges", "0.1"]),
    Case("id-seeds", "identify: --seeds 0", lambda d: _ident(d, None, "--seeds", "0")),
    # --- reproduce
    Case("rep-out-file", "reproduce: --out is an existing file", lambda d: ["reproduce", "--out", _existing_file(d)]),
    Case("rep-out-foreign", "reproduce: --out a non-empty folder not made by reproduce",
         lambda d: ["reproduce", "--out", _foreign_folder(d)]),
    Case("rep-only", "reproduce: unknown --only item",
         lambda d: ["reproduce", "--out", str(d / "out"), "--only", "fig99"]),
    Case("rep-seeds", "reproduce: --seeds -1", lambda d: ["reproduce", "--out", str(d / "out"), "--seeds", "-1"]),
    Case("rep-cache-inside", "reproduce: --setup-cache inside --out",
         lambda d: ["reproduce", "--out", str(d / "out"), "--setup-cache", str(d / "out" / "setup.json")]),
    Case("rep-data", "reproduce: --data with semicolons",
         lambda d: ["reproduce", "--out", str(d / "out"), "--data", _w(d, "s.csv", stribeck_text().replace(",", ";"))]),
    # --- simulate (scenario JSON: validated by the scenario loader)
    Case("sim-out-dir-plot", "simulate: --plot p.png --out EXISTING_DIR",
         lambda d: _simulate(d, SCENARIO, "--plot", str(d / "p.png"), out=_existing_dir(d))),
    Case("sim-not-json", "simulate: scenario not JSON", lambda d: _simulate(d, "{friction: paper}")),
    Case("sim-solver-name", "simulate: unknown solver name",
         lambda d: _simulate(d, _scen(solver={"method": "fixed", "name": "rk99"}))),
    Case("sim-dt-multiple", "simulate: dt not a multiple of the sample period",
         lambda d: _simulate(d, _scen(solver={"method": "fixed", "dt": 0.015}))),
    Case("sim-J0", "simulate: J = 0", lambda d: _simulate(d, _scen(joint={"J": 0}))),
    Case("sim-string", "simulate: a string duration", lambda d: _simulate(d, _scen(duration_s="10"))),
    Case("sim-too-large", "simulate: 20 million samples (a 1.5 GB CSV) without --force",
         lambda d: _simulate(d, _scen(duration_s=200000.0, solver={"method": "fixed"}))),
    Case("sim-memory", "simulate: 2 billion samples with --force (hundreds of GB in memory)",
         lambda d: _simulate(d, _scen(duration_s=2.0e7, solver={"method": "fixed"}), "--force")),
    Case("sim-step-budget", "simulate: 20000 s on the default adaptive stepping (beyond its max_steps)",
         lambda d: _simulate(d, _scen(duration_s=20000.0))),
    Case("sim-out-unwritable", "simulate: --out in a folder nothing can be written to",
         lambda d: _simulate(d, SCENARIO, out=f"{UNWRITABLE}/traj.csv")),
    Case("sim-out-not-csv", "simulate: --out without .csv", lambda d: _simulate(d, SCENARIO, out=str(d / "traj.txt"))),
    # --- every command: output paths checked before any work (same rule, same message)
    Case("emps-out-file", "emps: --out is an existing file", lambda d: _emps(d, out=_existing_file(d))),
    Case("emps-out-unwritable", "emps: --out in a folder nothing can be written to",
         lambda d: _emps(d, out=f"{UNWRITABLE}/emps_out")),
    Case("emps-out-foreign", "emps: --out a non-empty folder not made by emps", lambda d: _emps(d, out=_foreign_folder(d))),
    Case("emps-out-other", "emps: --out holds another command's result (reproduce's MANIFEST.json)",
         lambda d: _emps(d, out=_other_command_folder(d))),
    Case("emps-data-folder", "emps: --data names a folder", lambda d: _emps(d, "--data", _existing_dir(d))),
    Case("sweep-out-file", "sweep: --out is an existing file", lambda d: _sweep(d, out=_existing_file(d))),
    Case("sweep-out-unwritable", "sweep: --out in a folder nothing can be written to",
         lambda d: _sweep(d, out=f"{UNWRITABLE}/sweep_out")),
    Case("sweep-out-foreign", "sweep: --out a non-empty folder that is not a sweep", lambda d: _sweep(d, out=_foreign_folder(d))),
    Case("sweep-huge-n", 'sweep: "n" 1073741824 (32 GiB of samples)', lambda d: _sweep(d, n=2 ** 30)),
    Case("sweep-max-chunks", "sweep: --max-chunks 0", lambda d: _sweep(d, "--max-chunks", "0")),
    Case("bench-out-dir", "bench: --out names an existing folder", lambda d: ["bench", "--out", _existing_dir(d)]),
    Case("bench-out-unwritable", "bench: --out in a folder nothing can be written to",
         lambda d: ["bench", "--out", f"{UNWRITABLE}/bench.json"]),
    Case("id-out-unwritable", "identify: --out in a folder nothing can be written to",
         lambda d: ["identify", _w(d, "data.csv", stribeck_text()), "--out", f"{UNWRITABLE}/r.json"]),
    Case("rep-out-unwritable", "reproduce: --out in a folder nothing can be written to",
         lambda d: ["reproduce", "--out", f"{UNWRITABLE}/rep"]),
    Case("rep-out-other", "reproduce: --out holds another command's result (an emps MANIFEST.json)",
         lambda d: ["reproduce", "--out", _w(d, "theirs/MANIFEST.json", json.dumps(
             {"complete": True, "meta": {"command": "emps"}, "files": {}})).rsplit("/", 1)[0]]),
    Case("diag-out-unwritable", "diagnose: --out in a folder nothing can be written to",
         lambda d: ["diagnose", _w(d, "rec.csv", recording_text()), "--out", f"{UNWRITABLE}/r.json", "--quiet"]),
    Case("sim-undecodable", "simulate: undecodable bytes",
         lambda d: ["simulate", _w(d, "s.json", json.dumps(SCENARIO).encode() + b"\xff"),
                    "--out", str(d / "out" / "t.csv")]),
]


# ------------------------------------------------------------------------------------- running


def files_under(d: Path) -> set[str]:
    return {str(p.relative_to(d)) for p in d.rglob("*")}


def run_subprocess(case: Case, d: Path, timeout: float = 600) -> dict:
    """Run ``lugre-jax ARGS`` as a process in a fresh folder ``d``; the result row of the table."""
    import subprocess
    import sys

    argv = case.make(d)
    before = files_under(d)
    r = subprocess.run([sys.executable, *_cli_module(), *argv], capture_output=True, text=True,
                       timeout=timeout, cwd=Path(__file__).resolve().parents[1])
    left = sorted(files_under(d) - before)
    return dict(id=case.id, kind=case.kind, command=argv[0], code=r.returncode, expected=case.code,
                stderr=r.stderr.strip().replace(str(d), "DIR"), stdout=r.stdout.strip(),
                traceback="Traceback" in r.stderr, left=left,
                argv=[a.replace(str(d), "DIR") for a in argv])


def run_interrupt(sig_name: str, d: Path) -> dict:
    """``reproduce --quick --only fig08`` interrupted once its temporary folder holds a file."""
    import signal
    import subprocess
    import sys
    import time

    sig = getattr(signal, sig_name)
    argv = ["reproduce", "--quick", "--quiet", "--only", "fig08", "--out", str(d / "out")]
    # SIGINT back to its default in the child: a shell's background job inherits it ignored, and the
    # CLI keeps an inherited SIG_IGN (as nohup asks), so the signal would be ignored, not lost.
    p = subprocess.Popen([sys.executable, *_cli_module(), *argv], cwd=Path(__file__).resolve().parents[1],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    while p.poll() is None and not any(f for s in d.glob(".out.incomplete-*") for f in s.iterdir()):
        time.sleep(0.2)
    ended_early = p.poll() is not None
    if not ended_early:
        p.send_signal(sig)
    _, err = p.communicate(timeout=600)
    if ended_early:
        err = "NOT INTERRUPTED: reproduce ended before the signal could be sent: " + err.strip()
    return dict(id=f"interrupt-{sig_name}", kind=f"{sig_name} during reproduce, after its first file was written",
                command="reproduce", code=p.returncode, expected=128 + sig, stderr=err.strip().replace(str(d), "DIR"),
                stdout="", traceback="Traceback" in err, left=sorted(files_under(d)), argv=argv)


def _md(s: str) -> str:
    return s.replace("|", "\\|").replace("\n", " / ")


def write_table(rows: list[dict], path: Path, header: str) -> None:
    n_tb = sum(r["traceback"] for r in rows)
    n_left = sum(bool(r["left"]) for r in rows)
    n_ok = sum(r["code"] == r["expected"] and not r["traceback"] and not r["left"]
               and len(r["stderr"].splitlines()) == 1
               for r in rows)
    lines = [header, "",
             f"**{len(rows)} inputs tried: {n_ok} end with the expected exit code (2; 130/143 when interrupted) and "
             f"one line; {n_tb} tracebacks; "
             f"{n_left} left an output behind.**", "",
             "| # | Input class | Command | Exit | Message (stderr; DIR = the case's folder) | Outputs left |",
             "|---|---|---|---|---|---|"]
    for i, r in enumerate(rows, 1):
        msg = r["stderr"].splitlines()[-1] if r["stderr"] else "(none)"
        if r["traceback"]:
            msg = "TRACEBACK: " + msg
        lines.append(f"| {i} | {_md(r['kind'])} | `{r['command']}` | {r['code']} | {_md(msg)} | "
                     f"{_md(', '.join(r['left'])) or 'none'} |")
    path.write_text("\n".join(lines) + "\n")


HEADER = """# Malformed input: what each command says

Every command checks its arguments and every output path before it starts work, most of them
before JAX and the package are even imported (`lugre-jax --help`, an argument error or an unusable
`--out` answers in about 0.2 s: docs/performance.md). Bad input ends the command with exit code 2
and one line on stderr, "lugre-jax COMMAND: error: ...", naming the flag or the file, the line or
key, and what was expected; nothing is written. Ctrl-C ends a command with exit code 130, SIGTERM
with 143, one line, nothing half-written (`tests/test_interrupt.py`; the last two rows below).

**Outputs, the same rule for every command** (`lugre_jax/_cli/_outputs.py`):

- A file (`--out R.json`, `--out T.csv`, `--plot F.png`) may be new or an existing regular file,
  which is replaced atomically once the command has succeeded. Refused: a folder at that path, a
  parent path that is a file, the wrong suffix, a folder nothing can be written in (tried, so a
  read-only file system shows), two outputs on one path.
- A folder (`reproduce --out`, `emps --out`, `diagnose --plots`) may be new, empty, or an earlier
  result of the same command: it holds a `MANIFEST.json` (every file with its size and SHA-256,
  written last) that names the command. It is replaced as a whole when the new run has finished.
  Any other folder is refused, so no file the user put there is deleted.
- A sweep's folder (`sweep --out`) is kept and resumed when it holds a sweep of the same SPEC (its
  `sweep_state.json`, written first); a folder of another SPEC, or one that is not a sweep, is
  refused. A finished sweep also gets the `MANIFEST.json` every command's result has.

Outputs are staged beside their targets and moved into place only when the whole command succeeded.
Only a process killed outright (SIGKILL, power loss) can leave something: a hidden
`.NAME.incomplete-XXXX` file or folder beside the target, which has no `MANIFEST.json` and is never
mistaken for a result.

**Resources and defects.** A sweep whose arrays would not fit in the machine's memory is refused in
one line with the figure and the largest `"n"` that fits. Running out of memory anywhere else is one
line (exit 2), any other unexpected error one line (exit 1; `LUGRE_JAX_TRACEBACK=1` shows the
traceback): no traceback reaches the user.

**Progress.** `--quiet` silences it in every command (`--no-progress` is accepted as the same
flag). On a terminal it is drawn as bars; when stderr is a file or a pipe, each bar becomes a plain
line with done/total, percent, elapsed time and ETA, at most every 20 s and when it ends.

Inputs that are accepted as they are: a UTF-8 byte-order mark, Windows (CRLF) line ends, blank lines,
`#` comment lines in a Stribeck CSV, trailing commas and `was ...` annotations in EPOS exports
(checked by the property tests in `tests/test_loaders_hypothesis.py`).

This table is generated by `python tests/malformed_inputs.py` (each case a real `lugre-jax` process;
the same cases run in-process in CI, `tests/test_cli_errors.py`; the early checks themselves, the
memory guard and the progress lines in `tests/test_cli_outputs.py`). Paths are shown as `DIR/...`;
`/proc` stands for a folder nothing can be written in."""


FOOTER = """
## What does not hold yet

- **No progress while `simulate` solves.** The solve is one compiled call: `simulate` prints its size
  and stepping, then the solver's time with compilation included (not reported apart, as `identify`
  does), then a progress bar while the CSV is written. On a terminal only.
- **Memory is not bounded by the CSV writer alone.** The writer formats 1M-row slices, but the whole
  trajectory is held in memory: 20 million samples (`"duration_s": 200000`, 100 Hz, `"solver":
  {"method": "fixed"}`, `--force`) took 95 s, 3.6 GB peak RSS (`/usr/bin/time -v`) and wrote 1.51 GB
  (the refusal's estimate, an upper bound, said 2.27 GB). Bounding it needs a simulation in time
  chunks. The default adaptive stepping cannot run longer than `max_steps * dtmax` (4000 s at
  100 Hz): refused before compiling (row above), not solved.
- **A SIGINT is ignored when the command was started with SIGINT ignored** (a background job of a
  non-interactive shell, `nohup`), as those ask; SIGTERM still ends it with 143. A table generated
  as a background job would show its SIGINT row as exit 0 (the run completed), so the interrupt rows
  and `tests/test_interrupt.py` give the child the default SIGINT.
- **Interrupts are tested automatically for `reproduce` only.** `simulate`, `identify` and `diagnose`
  were interrupted by hand (SIGINT and SIGTERM, 4-9 s into a run): 130 / 143, one line, nothing left.
- **One command checks part of its input only once the package has loaded** (a few seconds, before
  any work): `reproduce --data` (the CSV is read then). Sweep's SPEC, and whether a sweep folder
  holds the same SPEC, are checked then too.
- **Figures are checked by eye, not by a test:** Fig. 10c's reference lines are black/grey outside the
  traces' colour cycle; the diagnose velocity plot has fixed symlog ticks a decade apart.
"""


def main(argv=None) -> int:
    import argparse
    import datetime
    import tempfile

    ap = argparse.ArgumentParser(description="run the malformed-input cases and write docs/errors.md")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "errors.md"))
    ap.add_argument("--only", default=None, help="comma-separated case ids")
    a = ap.parse_args(argv)
    cases = [c for c in CASES if a.only is None or c.id in a.only.split(",")]
    try:
        load = " (load average at the start: " + " ".join(Path("/proc/loadavg").read_text().split()[:3]) + ")"
    except OSError:
        load = ""
    rows = []
    for c in cases:
        with tempfile.TemporaryDirectory() as tmp:
            r = run_subprocess(c, Path(tmp))
        rows.append(r)
        print(f"{c.id:<22} exit {r['code']}  {'TRACEBACK ' if r['traceback'] else ''}"
              f"{'LEFT ' + str(r['left']) + ' ' if r['left'] else ''}{(r['stderr'].splitlines() or [''])[-1][:150]}",
              flush=True)
    if a.only is None or "interrupt" in a.only:
        for sig_name in ("SIGINT", "SIGTERM"):
            with tempfile.TemporaryDirectory() as tmp:
                r = run_interrupt(sig_name, Path(tmp))
            rows.append(r)
            print(f"{r['id']:<22} exit {r['code']}  {r['stderr'][-150:]}  left {r['left']}", flush=True)
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    write_table(rows, Path(a.out), HEADER + f"\n\nGenerated {stamp} by `python tests/malformed_inputs.py`{load}.")
    if a.only is None:
        with open(a.out, "a") as fh:
            fh.write(FOOTER)
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    raise SystemExit(main())
