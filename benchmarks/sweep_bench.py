"""Sweep performance: a Sobol' sweep of the 20 s stick-slip scenario (experiments/scenarios/
stick_slip_pi.json, paper friction, PI kp 8 / ki 60, 0.02 deg/s) over six parameters
(experiments/scenarios/sweep_bench.json: n = 2**17 base points -> 1,048,576 simulations), against
SALib + a scipy ``solve_ivp`` loop timed on a subset and extrapolated; 1 vs 2 devices; 1 vs 2
processes (jax.distributed on localhost).

    python benchmarks/sweep_bench.py [--n 131072] [--n-compare 16384] [--subset 20] [--out FILE.json]

Every sweep runs as its own ``lugre-jax sweep`` process, timed wall-clock from start to exit
(start-up, compilation from the persistent cache, which a warm-up run fills, the sweep and its
analysis and files) with its peak resident memory (``wait4``). The machine's load
(``/proc/loadavg``) is recorded before and after each measurement.
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import os
import platform
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "experiments" / "scenarios" / "sweep_bench.json"


def _load():
    return Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else None


def _spec(n: int, tmp: Path, name: str) -> Path:
    d = json.loads(SPEC.read_text())
    d["n"] = n
    d["scenario"] = str(SPEC.parent / d["scenario"])
    p = tmp / f"{name}.json"
    p.write_text(json.dumps(d))
    return p


def _cli(spec: Path, out: Path, *extra) -> list[str]:
    return [sys.executable, "-m", "lugre_jax.cli", "sweep", str(spec), "--out", str(out), "--no-progress",
            "--no-figures", *extra]


def _run(cmds: list[list[str]]) -> dict:
    """Start the commands together; wall time until all exit, peak RSS of each (MB)."""
    load0 = _load()
    t0 = time.perf_counter()
    procs = [subprocess.Popen(c, stdout=subprocess.PIPE, stderr=subprocess.PIPE) for c in cmds]
    rss, outs = [], []
    for p in procs:
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        out, err = p.stdout.read().decode(), p.stderr.read().decode()
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(p.args)} failed ({p.returncode}): {err[-2000:]}")
        rss.append(ru.ru_maxrss / 1024)
        outs.append(json.loads(out.strip().splitlines()[-1]))
    wall = time.perf_counter() - t0
    return dict(wall_s=wall, peak_rss_mb=rss, load_before=load0, load_after=_load(), summaries=outs)


# ---- the scipy baseline: the same closed loop as plain Python floats, LSODA ----

def _paper_segments():
    import lugre_jax as lj

    f = lj.paper_friction()
    segs = [{k: float(getattr(s, k)) for k in ("Fc", "Fs", "vs", "sigma0", "sigma1", "sigma2")} for s in f.segments]
    return segs, [float(e) for e in np.asarray(f.edges)], float(f.blend)


def _scipy_one(x, names, segs, edges, blend, J, v_cmd, T, hz):
    """One simulation with scipy (LSODA, rtol 1e-6, atol 1e-9) of the stick-slip scenario with the
    point ``x`` written into the paper's segmented LuGre friction and the PI gains."""
    from scipy.integrate import solve_ivp

    segs = copy.deepcopy(segs)
    kp, ki = 8.0, 60.0
    for name, val in zip(names, x):
        if name.startswith("friction.segments["):
            k = int(name.split("[")[1].split("]")[0])
            segs[k][name.rsplit(".", 1)[1]] = float(val)
        elif name == "controller.kp":
            kp = float(val)
        elif name == "controller.ki":
            ki = float(val)
    s01 = segs[0]["sigma0"]

    def seg(s, z1, v):  # torque and dz/dt of one segment, state in segment-1 units
        c = s["sigma0"] / s01
        z = z1 / c
        g = s["Fc"] + (s["Fs"] - s["Fc"]) * math.exp(-(abs(v) / s["vs"]) ** 2)
        dz = v - s["sigma0"] * abs(v) * z / g
        return s["sigma0"] * z + s["sigma1"] * dz + s["sigma2"] * v, c * dz

    def rhs(t, y):
        theta, omega, z, xi = y
        a = abs(omega)
        f, dz = seg(segs[0], z, omega)
        for k in range(1, len(segs)):
            e = edges[k - 1]
            fn, dzn = seg(segs[k], z, omega)
            w = min(max((a - e * (1 - blend)) / (2 * blend * e), 0.0), 1.0)
            w = w * w * (3 - 2 * w)
            f, dz = f + w * (fn - f), dz + w * (dzn - dz)
        err = v_cmd - omega
        tau = kp * err + ki * xi
        return [omega, (tau - f) / J, dz, err]

    ts = np.arange(int(round(T * hz)) + 1) / hz
    sol = solve_ivp(rhs, (0.0, T), [0.0, 0.0, 0.0, 0.0], method="LSODA", t_eval=ts, rtol=1e-6, atol=1e-9)
    return ts, sol


def scipy_baseline(X, names, subset: int) -> dict:
    from lugre_jax import metrics as M

    segs, edges, blend = _paper_segments()
    J, v, T, hz = 0.128, 0.02, 20.0, 100.0
    pick = np.linspace(0, len(X) - 1, subset).round().astype(int)
    rows, t0 = [], time.perf_counter()
    for i in pick:
        ts, sol = _scipy_one(X[i], names, segs, edges, blend, J, v, T, hz)
        ok = sol.status == 0
        th = sol.y[0] if ok else np.full(ts.size, np.nan)
        ref = v * ts
        rows.append([float(M.dead_zone_lag(ts, th, v)), float(M.creep_amplitude(ts, th, ref, t_from=10.0))])
    per = (time.perf_counter() - t0) / subset
    return dict(points=pick.tolist(), outputs=rows, seconds_per_simulation=per)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=131072, help="Sobol' base points of the big run (x8 simulations)")
    ap.add_argument("--n-compare", type=int, default=16384, help="base points of the device/process comparisons")
    ap.add_argument("--subset", type=int, default=20, help="simulations of the scipy loop")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "sweep_bench.json"))
    ap.add_argument("--skip", default="", help="comma list of: big, devices, processes, scipy")
    a = ap.parse_args(argv)
    skip = set(filter(None, a.skip.split(",")))
    import lugre_jax as lj

    lj.configure()
    from lugre_jax.io import write_json
    from lugre_jax.sweep import load_spec, saltelli_sample, sobol_analyze

    tmp = Path(tempfile.mkdtemp(prefix="sweep_bench_"))
    res: dict = dict(command=" ".join([Path(sys.argv[0]).name] + sys.argv[1:]), host=platform.node(),
                     cpus=os.cpu_count(), spec=str(SPEC.relative_to(ROOT)), date=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()))
    try:
        # Warm-up: fills the persistent compilation cache for the chunk shape all runs share.
        _run([_cli(_spec(64, tmp, "warm"), tmp / "warm")])
        _run([_cli(_spec(64, tmp, "warm1"), tmp / "warm1", "--no-shard")])
        if "big" not in skip:
            p = _spec(a.n, tmp, "big")
            r = _run([_cli(p, tmp / "big")])
            r["simulations"] = r["summaries"][0]["n_points"]
            r["simulations_per_s"] = r["simulations"] / r["wall_s"]
            res["big"] = r
            print(f"big: {r['simulations']} simulations in {r['wall_s']:.1f} s, peak {max(r['peak_rss_mb']):.0f} MB, load {r['load_before']}")
        pc = _spec(a.n_compare, tmp, "cmp")
        if "devices" not in skip:
            res["one_device"] = _run([_cli(pc, tmp / "d1", "--no-shard")])
            res["two_devices"] = _run([_cli(pc, tmp / "d2")])
            print(f"devices: 1 -> {res['one_device']['wall_s']:.1f} s, 2 -> {res['two_devices']['wall_s']:.1f} s")
        if "processes" not in skip:
            with socket.socket() as s:
                s.bind(("localhost", 0))
                port = s.getsockname()[1]
            res["one_process"] = res.get("one_device") or _run([_cli(pc, tmp / "p1", "--no-shard")])
            res["two_processes"] = _run([_cli(pc, tmp / "p2", "--coordinator", f"localhost:{port}",
                                              "--num-processes", "2", "--process-id", str(k)) for k in (0, 1)])
            print(f"processes: 1 -> {res['one_process']['wall_s']:.1f} s, 2 -> {res['two_processes']['wall_s']:.1f} s")
            a1, a2 = np.load(tmp / "p2" / "outputs.npz"), np.load(tmp / ("d1" if "one_device" in res else "p1") / "outputs.npz")
            res["two_processes"]["identical_to_one"] = bool(np.array_equal(a1["Y"], a2["Y"], equal_nan=True))
        if "scipy" not in skip:
            spec = load_spec(_spec(a.n, tmp, "big"))
            t0 = time.perf_counter()
            X = saltelli_sample(spec.problem, a.n, seed=spec.seed, calc_second_order=False)
            t_ours_sample = time.perf_counter() - t0
            from SALib.analyze import sobol as salib_analyze
            from SALib.sample import sobol as salib_sample

            t0 = time.perf_counter()
            Xs = salib_sample.sample(dict(spec.problem), a.n, seed=spec.seed, calc_second_order=False)
            t_salib_sample = time.perf_counter() - t0
            base = scipy_baseline(Xs, list(spec.names), a.subset)
            n_sims = Xs.shape[0]
            sc = dict(salib_sample_s=t_salib_sample, ours_sample_s=t_ours_sample, identical_samples=bool(np.array_equal(X, Xs)),
                      scipy=base, scipy_extrapolated_s=base["seconds_per_simulation"] * n_sims, simulations=n_sims,
                      scipy_method="solve_ivp LSODA rtol 1e-6 atol 1e-9, pure-Python right-hand side, one process")
            big_out = tmp / "big" / "outputs.npz"
            if big_out.exists():
                with np.load(big_out) as z:
                    Y, status = z["Y"], z["status"]
                ours, ref = Y[base["points"]][:, :2], np.array(base["outputs"])
                # Relative to the scipy value, floored (a creep amplitude of 1e-6 deg is noise):
                # 0.01 s of dead zone, 1e-3 deg of creep.
                floor = np.array([0.01, 1e-3])
                sc["fast_step_vs_scipy"] = dict(
                    max_abs=dict(zip(("dead_zone_s", "creep_amplitude_deg"), np.nanmax(np.abs(ours - ref), axis=0).tolist())),
                    max_rel_floored=dict(zip(("dead_zone", "creep_amplitude"),
                                             np.nanmax(np.abs(ours - ref) / np.maximum(np.abs(ref), floor), axis=0).tolist())))
                if not np.any(status == 2):
                    t0 = time.perf_counter()
                    salib_analyze.analyze(dict(spec.problem), Y[:, 0], seed=spec.seed, calc_second_order=False)
                    sc["salib_analyze_one_output_s"] = time.perf_counter() - t0
                    t0 = time.perf_counter()
                    sobol_analyze(spec.problem, Y[:, 0], seed=spec.seed, calc_second_order=False)
                    sc["ours_analyze_one_output_s"] = time.perf_counter() - t0
            res["salib_scipy"] = sc
            print(f"scipy: {base['seconds_per_simulation'] * 1e3:.0f} ms/simulation -> {sc['scipy_extrapolated_s'] / 3600:.1f} h for {n_sims}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    write_json(a.out, res)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
