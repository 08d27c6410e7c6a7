"""The reproduction report: one row per figure/table of Li et al., Electronics 2020, 9, 284, with the
paper's claim beside our measured number and a verdict (REPORT.md and report.json).

Rows are produced by small functions registered in :data:`ROWS` (``fn(results, setup) -> dict or
None``); other parts of the project (e.g. static identification: Table 1, Figs. 3b-6) can append
their own. A row function returns None when its scenario was not run (:func:`_of` wraps a row drawn
from one scenario's result).
"""

from __future__ import annotations

import datetime
import functools
import platform
from pathlib import Path

import numpy as np

from ..io import atomic_path, write_json


def _f(x, nd=3):
    if isinstance(x, str):
        return x
    if x is None or not np.isfinite(x):
        return str(x)
    if x == 0:
        return "0"
    if abs(x) >= 1e-2 and abs(x) < 1e4:
        return f"{x:.{nd}g}"
    return f"{x:.{nd - 1}e}"


def _row(id_, claim, ours, verdict, why, data=None, figure=None):
    return dict(id=id_, paper_claim=claim, ours=ours, verdict=verdict, why=why, data=data or {}, figure=figure)


def _of(name: str):
    """A row drawn from the result of ``name`` alone: the function takes (that result, setup) and the
    registered row is None where ``name`` was not run."""
    def wrap(fn):
        @functools.wraps(fn)
        def row(R, S):
            r = R.get(name)
            return None if r is None else fn(r, S)
        return row
    return wrap


@_of("table2")
def row_table2(t, S):
    p, r1, r2 = t["paper"], t["route1_paper_method"], t["route2_time_series"]
    Ji = t["J_implied_by_eq18"]
    ours = (f"eq. 17 step ({S.presliding['step_nm']:g} N*m, {ENC:g}-deg encoder): sigma0 = {_f(r1[1]['sigma0'], 4)} "
            f"(plant segment 1: {_f(S.presliding['truth_sigma0_segment1'], 4)}); step-size dependence "
            + ", ".join(f"{k} N*m -> {_f(v, 3) if not isinstance(v, str) else 'breaks away'}" for k, v in t["presliding_steps"].items())
            + f". eq. 18 sigma1 = {', '.join(_f(r1[k]['sigma1']) for k in (1, 2, 3))}. "
            + ("Time-series LM: skipped (--quick). " if r2 is None else
               f"Time-series LM (ramp, noise {t['recording']['noise_deg']:g} deg): " + "; ".join(
                   f"seg {k}: sigma0 = {_f(r2[k]['sigma0'], 4)} +- {_f(r2[k]['sigma0_se'], 2)}, sigma1 = {_f(r2[k]['sigma1'], 3)} +- "
                   f"{_f(r2[k]['sigma1_se'], 2)}" for k in (1, 2, 3)) + ". ")
            + f"Eq. 18 on Table 2 implies J = {', '.join(_f(Ji[k], 4) for k in (1, 2, 3))}.")
    why = ("A pre-sliding step only sees segment 1 (|v| ~ 0): it cannot give three sigma0 values. Steps above ~0.3 N*m "
           "drive the velocity past the 0.05 deg/s segment edge and the estimate collapses toward segment 2's sigma0. "
           "Segment-2/3 values need a recording in their velocity range (route 2). Table 2 is not self-consistent "
           f"with eq. 18 (segment 2 implies J = {_f(Ji[2], 3)}, not 0.128).")
    s0_err = abs(r1[1]["sigma0"] / S.presliding["truth_sigma0_segment1"] - 1)
    verdict = f"segment 1 sigma0 reproduced by eq. 17 ({s0_err:.1%} error)"
    if r2 is not None:
        rel = {k: r2[k]["sigma1_se"] / max(abs(r2[k]["sigma1"]), 1e-12) for k in (1, 2, 3)}
        # In simulation the paper's Table 2 *is* the truth (the plant), so the fit can be scored.
        z = [abs(r2[k][n] - p[k][n]) / r2[k][n + "_se"] for k in (1, 2, 3) for n in ("sigma0", "sigma1")]
        verdict += ("; time series: sigma1 relative SE " + ", ".join(f"{rel[k]:.0%}" for k in (1, 2, 3))
                    + f"; largest |error|/SE vs the truth {max(z):.1f}")
        import math

        p_max = 1 - (1 - math.erfc(max(z) / math.sqrt(2))) ** len(z)
        why += (f" The 6-parameter fit is ill-conditioned (cond(Fisher) = 1e{t['fit']['log10_cond_fisher']:.0f}); in this "
                f"noise realisation the largest error is {max(z):.1f} SE, which a linear Fisher bound would give with "
                f"probability {p_max:.0%}: its SEs are local and may understate the spread along the ridge.")
    return _row("Table 2", "sigma0 = 111.3, 29.94, 90.41 N*m/deg; sigma1 = 2.304, 0.3095, 4.761 N*m*s/deg (3 segments), "
                "from a pre-sliding step (eq. 17) and eq. 18", ours, verdict, why, t, "table2.png")


ENC = 1e-4


def row_table1(R, S):
    """Static parameters: the GA-PSO piecewise identification used by the compensator vs Table 1 (the
    data were drawn from Table 1 plus noise, so Table 1 is the truth here)."""
    from ..plant import TABLE1

    segs = S.static_params.get("GA-PSO piecewise", {}).get("segments")
    if not segs:
        return None
    parts = []
    for k, seg in enumerate(segs, start=1):
        Fc, Fs, vs, s2 = TABLE1[k]
        if Fs is None:
            parts.append(f"seg {k}: Fc {_f(seg['Fc'], 4)} ({Fc}), sigma2 {_f(seg['sigma2'], 3)} ({s2})")
        else:
            parts.append(f"seg {k}: Fc {_f(seg['Fc'], 4)} ({Fc}), Fs {_f(seg['Fs'], 4)} ({Fs}), vs {_f(seg['vs'], 3)} ({vs}), "
                         f"sigma2 {_f(seg['sigma2'], 3)} ({s2})")
    rms = {k: v["rms_nm"] for k, v in S.static_params.items()}
    return _row("Table 1 (as used here)", "GA-PSO piecewise static parameters, three segments",
                "identified from data/stribeck_paper_like.csv (ours (paper)): " + "; ".join(parts)
                + ". Static-fit RMS: " + ", ".join(f"{k} {_f(v)} N*m" for k, v in rms.items()),
                "recovered where the data inform (Fs, vs of segment 1; Fc, sigma2 of segment 2; Fc of segment 3)",
                "Segment 1's Fc and sigma2 (0-0.05 deg/s, where torque is ~Fs) are weakly determined by the data; see the "
                "static-identification helpers' Table 1 experiment for standard errors.", dict(segments=segs, rms=rms))


@_of("fig08")
def row_fig08(r, S):
    c = r["metrics"]["PID cascade (position + velocity)"]
    v = r["metrics"]["PID velocity loop only (Fig. 9c)"]
    ours = (f"cascade: dead zone {_f(c['dead_zone_s'])} s, creep amplitude {_f(c['creep_amplitude_deg'])} deg, "
            f"inside the +-0.001 deg/s cone {c['cone_fraction']:.0%} of the time; velocity loop alone: dead zone "
            f"{_f(v['dead_zone_s'])} s, creep {_f(v['creep_amplitude_deg'])} deg")
    o = r["metrics"].get("open loop (feedforward of identified F(v), no feedback)")
    if o is not None:
        ours += (f"; open loop (constant {o['torque_nm']:.3g} N*m = identified F(0.005 deg/s), no feedback): "
                 f"breaks away after {_f(o['breakaway_s'])} s and runs away to {_f(o['final_velocity_deg_s'])} deg/s "
                 f"at t = {r['settings']['duration_s']:g} s")
    verdict = "not reproduced" if c["creep_amplitude_deg"] < v["creep_amplitude_deg"] else "reproduced"
    why = ("We follow the text (both loops closed). The position loop's integral action removes the lag the velocity "
           "PI must build against ~6.4 N*m of friction, so the cascade is *better* than Fig. 9c, the opposite of the "
           "paper's remark that Fig. 9c is 'a bit better than the open-loop control in Fig. 8'. No stick-slip appears: "
           "with Table 2's sigma0 the pre-sliding range is Fs/sigma0 = 0.058 deg, and the PI's stiffness keeps the "
           "joint sliding smoothly once it breaks away. Read as open loop (the other reading of Fig. 8), a feedforward of the "
           "identified friction with no feedback cannot hold 0.005 deg/s at all: the Stribeck curve falls with "
           "velocity, so any torque that breaks the joint away accelerates it (no stable creep either).")
    return _row("Fig. 8", "0.005 deg/s step, position and velocity loops closed: errors and serious creeping",
                ours, verdict, why, r["metrics"], "fig08.png")


@_of("fig09")
def row_fig09ab(r, S):
    m = r["metrics"]["sine"]["PID"]
    at_rev = m["delay_after_reversal_s"] < 0.25  # a tenth of the 2.5 s period
    ours = (f"PID (cascade) RMS error {_f(m['rms_error_deg'])} deg, max {_f(m['max_error_deg'])} deg (amplitude 3 deg); "
            f"the maximum comes {_f(m['delay_after_reversal_s'])} s after a velocity reversal (a position peak), where "
            f"|v_ref| is {m['speed_at_max_error_frac']:.0%} of its maximum")
    return _row("Fig. 9a-b", "PID tracking of 3 sin(0.8 pi t) shows a small deviation and a large position error at the "
                "peaks (velocity reversals)", ours,
                "reproduced (the paper gives no number)" if at_rev else "partly: error not largest at the reversals",
                "At a reversal the friction torque flips sign (~2 x 6.4 N*m across the pre-sliding range) and the PI "
                "must rebuild it through its error, so the error peaks shortly after each position peak." if at_rev else
                "The largest error is not at the reversals: the inertia and viscous torque at peak velocity dominate.",
                m, "fig09.png")


@_of("fig09")
def row_fig09c(r, S):
    m = r["metrics"]["step"]["PID"]
    ours = (f"dead zone {_f(m['dead_zone_s'])} s (ki = {_f(S.ki, 4)} N*m/deg was chosen to give 2 s: this row is the "
            f"calibration, not a test); creep amplitude {_f(m['creep_amplitude_deg'])} deg")
    return _row("Fig. 9c", "velocity PID, 0.005 deg/s: creeping and a 2 s dead zone", ours, "calibrated",
                "The dead zone of a PI velocity loop is the residual friction / (ki * v): ~6.36 N*m / (ki * 0.005 deg/s).",
                m, "fig09.png")


def row_fig10ab(R, S):
    r, p = R.get("fig10"), R.get("fig09")
    if r is None or p is None:
        return None
    c, q = r["metrics"]["sine"]["GA-PSO piecewise"], p["metrics"]["sine"]["PID"]
    ratio = c["rms_error_deg"] / q["rms_error_deg"]
    ours = (f"compensated RMS {_f(c['rms_error_deg'])} deg (max {_f(c['max_error_deg'])}) vs PID {_f(q['rms_error_deg'])} "
            f"deg (max {_f(q['max_error_deg'])}): {ratio:.2f}x")
    return _row("Fig. 10a-b", "GA-PSO piecewise compensation: sine tracking obviously better, position error greatly "
                "decreased vs PID", ours, "reproduced" if ratio < 0.5 else ("partly" if ratio < 1 else "not reproduced"),
                "The observer supplies the friction torque the PI would otherwise have to build through its error.",
                dict(compensated=c, pid=q), "fig10.png")


@_of("fig10")
def row_fig10c(r, S):
    m = r["metrics"]["step"]
    dz = {k: v["dead_zone_s"] for k, v in m.items()}
    ours = "; ".join(f"{k}: {_f(v)} s" for k, v in dz.items())
    rms = {k: v["rms_nm"] for k, v in S.static_params.items()}
    claim_ok = dz["GA-PSO piecewise"] < 1.0 and dz["PSO whole"] > 1.5 and dz["GA whole"] > 1.5
    verdict = "reproduced" if claim_ok else ("partly: GA-PSO < 1 s reproduced" if dz["GA-PSO piecewise"] < 1.0 else "not reproduced")
    why = ("Dead zone = residual friction at 0.005 deg/s / (ki v). It follows how well each identified curve matches the "
           "plant near 0 deg/s, i.e. the optimiser's final loss (static-fit RMS: "
           + ", ".join(f"{k} {_f(v)} N*m" for k, v in rms.items())
           + "), not the algorithm's name: a PSO run that converges gives the same near-zero dead zone as GA-PSO. "
           "One run per method, as in the paper; see the seeds row.")
    return _row("Fig. 10c", "0.005 deg/s step, compensated: PSO- and GA-identified (whole) still ~2 s dead zone; GA-PSO "
                "(piecewise) under 1 s", ours, verdict, why, m, "fig10.png")


@_of("fig12")
def row_fig12(r, S):
    m = r["metrics"]
    parts = []
    for k in ("GA-PSO whole", "GA-PSO piecewise", "PID (no compensation)"):
        if k not in m:
            continue
        parts.append(f"{k}: max |velocity error| near 0.05 = {_f(m[k]['near 0.05 deg/s']['max_abs_velocity_error_deg_s'])}, "
                     f"near 1.2 = {_f(m[k]['near 1.2 deg/s']['max_abs_velocity_error_deg_s'])} deg/s")
    w, p = m["GA-PSO whole"], m["GA-PSO piecewise"]
    better = (p["near 0.05 deg/s"]["max_abs_velocity_error_deg_s"] < w["near 0.05 deg/s"]["max_abs_velocity_error_deg_s"]
              and p["near 1.2 deg/s"]["max_abs_velocity_error_deg_s"] < w["near 1.2 deg/s"]["max_abs_velocity_error_deg_s"])
    d = m.get("GA-PSO piecewise, observer sigma1 = 0")
    why = ("The bulge appears with the *piecewise* model, at 1.2 deg/s, although its steady-state curve matches the "
           "plant there: identified segment 2 carries its torque in sigma2*v, segment 3 in the bristle state "
           "(Fc ~4.5 N*m, sigma2 ~0), so in the blend band (1.08-1.32 deg/s) the observer's z must move fast from "
           "segment 2's deflection to segment 3's, and eq. 20's sigma1*dz/dt turns that into torque spikes"
           + (f" (observer sigma1 = 0: peak velocity error {_f(d['near 1.2 deg/s']['max_abs_velocity_error_deg_s'])} instead of "
              f"{_f(p['near 1.2 deg/s']['max_abs_velocity_error_deg_s'])} deg/s)" if d else "")
           + ". Same with dt = 5e-4 s and the adaptive Kvaerno5 solver: not a numerical artefact. A single whole curve "
           "has no switch; near 0.05 deg/s all are small.")
    return _row("Fig. 12", "ramp 0 -> 1.5 deg/s in 4 s: whole identification gives bulges near 0.05 and 1.2 deg/s; "
                "piecewise none", "; ".join(parts), "reproduced" if better else "not reproduced", why, m, "fig12.png")


@_of("fig13")
def row_fig13(r, S):
    m = r["metrics"]
    ours = "; ".join(f"{k}: dead zone {_f(v['dead_zone_s'])} s, creep {_f(v['creep_amplitude_deg'])} deg, in cone "
                     f"{v['cone_fraction']:.0%}, |v error| <= 0.001 in 2nd half {v['band_fraction_second_half']:.0%}, "
                     f"within +-10% {v['rel_band10_fraction_second_half']:.0%}" for k, v in m.items())
    dzs = [v["dead_zone_s"] for v in m.values()]
    mono = all(a <= b for a, b in zip(dzs, dzs[1:]))
    why = ("The lag grows as velocity falls (dead zone ~ F(v)/(ki v)), as the paper says; but there is no "
           "'crawling and jumping': after breakaway the PI holds a smooth slide. At 0.001 deg/s the joint stays in "
           "pre-sliding for the whole record (0.03 deg < Fs/sigma0 = 0.058 deg). The +-0.001 deg/s band is met even "
           "without compensation at 0.001 deg/s because it contains 0; the +-10% column is the stricter test.")
    return _row("Fig. 13", "velocity PID at 0.1, 0.01, 0.005, 0.001 deg/s: good at 0.1; creep grows as velocity falls; "
                "spec: 0.005 deg/s within +-0.001 deg/s", ours, "partly" if mono else "not reproduced", why, m, "fig13.png")


@_of("fig14")
def row_fig14(r, S):
    m = r["metrics"]
    g, p = m["GA whole"], m["GA-PSO piecewise"]
    ours = (f"GA whole: dead zone {_f(g['dead_zone_s'])} s, creep {_f(g['creep_amplitude_deg'])} deg; GA-PSO piecewise: "
            f"dead zone {_f(p['dead_zone_s'])} s, creep {_f(p['creep_amplitude_deg'])} deg")
    ok = p["dead_zone_s"] < g["dead_zone_s"]
    return _row("Fig. 14", "0.005 deg/s: GA (whole) compensation still a large dead zone; GA-PSO (piecewise) suppresses "
                "creep and the dead zone", ours, "reproduced" if ok else "not reproduced",
                "Same mechanism as Fig. 10c: residual friction at 0.005 deg/s. Simulated, not hardware.", m, "fig14.png")


@_of("fig15")
def row_fig15(r, S):
    m = r["metrics"]
    ratio = m["GA-PSO piecewise"]["rms_error_deg"] / m["PID"]["rms_error_deg"]
    ours = (f"on a joint with +{(r['settings']['friction_drift'] - 1):.0%} friction drift: PID RMS {_f(m['PID']['rms_error_deg'])} deg, "
            f"compensated {_f(m['GA-PSO piecewise']['rms_error_deg'])} deg ({ratio:.2f}x)")
    return _row("Fig. 15", "experiment: compensation (GA-PSO piecewise) tracks the sine better than PID", ours,
                "reproduced" if ratio < 1 else "not reproduced",
                "No hardware: a drifted plant stands in for the experiment; the ranking survives a 10% model error.", m, "fig15.png")


@_of("beyond")
def row_beyond(r, S):
    m = r["metrics"]
    ours = "; ".join(f"{k}: dead zone {_f(v['dead_zone_s'])} s, |v error| <= 0.001 deg/s {v['band_fraction']:.0%} of the "
                     f"time, within +-10% {v.get('rel_band10_fraction', float('nan')):.0%}" for k, v in m.items())
    ok = [k for k, v in m.items() if "PID" not in k and abs(v["dead_zone_s"]) < 0.1 and v.get("rel_band10_fraction", 0) > 0.95]
    pid = next(v for k, v in m.items() if "PID" in k)
    why = ("The paper's +-0.001 deg/s band around 0.001 deg/s includes standing still, so it is met trivially (also by "
           "PID). The informative tests are the dead zone and a +-10% band: without compensation the PI must build the "
           f"whole friction torque through its lag (dead zone {_f(pid['dead_zone_s'])} s, tending to F/(ki v) ~ 11 s); with "
           "a well-identified model the residual is tiny. What limits it is the identified curve's error near 0 deg/s "
           "(static-fit loss), not the observer. The run is 120 s so that the joint leaves the pre-sliding range "
           "(0.12 deg > Fs/sigma0 = 0.058 deg).")
    verdict = (f"{len(ok)} of {len(m) - 1} compensations hold 0.001 deg/s (dead zone < 0.1 s, >95% of the time within "
               "+-10%)") if ok else "no compensation holds 0.001 deg/s within +-10%"
    return _row(f"Beyond: 0.001 deg/s for {r['settings'].get('duration_s', 30):g} s",
                "(not in the paper: its spec is met only at 0.005 deg/s)", ours, verdict, why, m, "beyond.png")


@_of("design")
def row_design(d, S):
    f = d["fit_on_best"]
    w = d["worst"]
    ours = (f"D-optimal torque sine: {d['best']['amplitude_nm']:g} N*m at {d['best']['frequency_hz']:g} Hz; fit there: "
            f"sigma0 = {_f(f['estimate'][0], 4)} +- {_f(f['se'][0], 2)}, sigma1 = {_f(f['estimate'][1], 3)} +- {_f(f['se'][1], 2)} "
            f"(truth {_f(d['truth'][0], 4)}, {_f(d['truth'][1], 4)}). Worst grid point ({w['amplitude_nm']:g} N*m, "
            f"{w['frequency_hz']:g} Hz): relative SE sigma0 {w['relative_se_sigma0']:.0%}, sigma1 {w['relative_se_sigma1']:.0%}"
            + (f". From a Fig. 9c-type recording (0.005 deg/s step under PI): relative SE sigma0 "
               f"{d['typical_recording']['relative_se_sigma0']:.1%}, sigma1 {d['typical_recording']['relative_se_sigma1']:.0%}"
               if "typical_recording" in d else ""))
    return _row("Dynamic identification (sec. 4.2.5, beyond)", "sigma1 'estimated approximately' by eq. 18; no uncertainty given",
                ours, "sigma0 and sigma1 identifiable with the designed excitation",
                "Slow or tiny excitations, and the paper's own kind of recording (a slow velocity step), leave sigma1 "
                "undetermined; a torque sine of ~0.5 N*m at a few Hz to 10 Hz (around the pre-sliding resonance "
                "sqrt(sigma0/J)/(2 pi) = 4.7 Hz) determines both to a few percent.", d, "excitation_design.png")


@_of("seeds")
def row_seeds(s, S):
    ours = "; ".join(f"{k}: dead zone over {len(v)} extra seeds = " + ", ".join(_f(x) for x in v) + " s" for k, v in s.items())
    good = {k: sum(abs(x) < 0.1 for x in v) for k, v in s.items()}
    why = ("; ".join(f"{k}: {good[k]} of {len(v)} seeds reach the GA-PSO-like optimum (dead zone < 0.1 s)" for k, v in s.items())
           + ". The paper's ranking of the algorithms rests on one run each; it is the final fit, not the algorithm, "
           "that sets the dead zone. The paper's binary GA has 20 x 20 evaluations on 10-bit genes (0.001 deg/s steps "
           "on vs).")
    return _row("Fig. 10c seeds (beyond)", "one identification per method", ours, "seed-dependent", why, s)


@_of("creep")
def row_creep(r, S):
    m, st = r["metrics"], r["settings"]
    worst = max(m["grid"], key=lambda g: g["max_velocity_over_command"])
    ours = (f"{m['n_stick_slip']} of {m['n']} velocity-PI gain pairs (kp {st['kp']}, ki {st['ki']}) stick-slip at "
            f"{st['v_deg_s']} deg/s over {st['duration_s']:g} s; the largest velocity reached is "
            f"{worst['max_velocity_over_command']:.2f} x the command (kp {worst['kp']:g}, ki {worst['ki']:g}); "
            f"creep amplitude up to {max(g['creep_amplitude_deg'] for g in m['grid']):.2e} deg")
    why = ("With Tables 1-2 the bristles' relaxation length Fs/sigma0 = "
           f"{st['presliding_range_deg']:.3f} deg takes {st['presliding_range_deg'] / st['v_deg_s']:.0f} s to traverse at "
           "0.005 deg/s. Our reading: the velocity weakening acts only below ~sigma0*v/g = 0.09 rad/s, where the "
           "loop's integral action dominates it, so the joint approaches the command from below without slipping. The paper's 'creep' is, in "
           "its own model, a slow elastic lag, not stick-slip. At higher commands the same model does "
           "stick-slip: with kp = 8 and ki <= ~100 the velocity swings several times the command between 0.01 and "
           "0.06 deg/s (experiments/fig13_creep, stick-slip map).")
    return _row("Creep search (beyond, Figs. 8, 9c, 13)", "PID at 0.005 deg/s shows creeping ('crawling and jumping')", ours,
                "no stick-slip in the paper's model" if m["n_stick_slip"] == 0 else "stick-slip found", why, m)


ROWS = [row_table1, row_table2, row_fig08, row_fig09ab, row_fig09c, row_fig10ab, row_fig10c, row_seeds, row_fig12, row_fig13,
        row_fig14, row_fig15, row_beyond, row_creep, row_design]


def build_rows(results: dict, setup) -> list[dict]:
    rows = []
    for fn in ROWS:
        r = fn(results, setup)
        if r is not None:
            rows.append(r)
    return rows


def write_report(out: Path, rows: list[dict], setup, timings: dict, quick: bool) -> None:
    out = Path(out)
    meta = dict(generated_utc=datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
                python=platform.python_version(), quick=quick, timings_s=timings)
    write_json(out / "report.json", dict(meta=meta, setup=setup.as_dict(), rows=rows))
    g = setup.as_dict()["gains"]
    lines = [
        "# Reproduction of Li et al., Electronics 2020, 9, 284 (Figs. 8-15, Table 2)",
        "",
        f"Generated {meta['generated_utc']}{' (--quick: reduced settings, numbers are indicative only)' if quick else ''}. "
        "Every number below is from a simulation; the paper's robot data are not public.",
        "",
        "**Set-up.** Real joint = the paper's own Tables 1-2 model (3 LuGre segments, J = 0.128 N*m*s^2/deg). "
        "Compensators use models *identified* from noisy steady-state data (`data/stribeck_paper_like.csv`) by the "
        "paper's optimisers, sigma0 from a simulated pre-sliding step read through a "
        f"{ENC:g}-deg encoder (eq. 17), sigma1 from eq. 18. Gains: kp = {_f(g['kp'])} N*m*s/deg (assumed ~10 Hz velocity "
        f"loop), ki = {_f(g['ki'], 4)} N*m/deg (grid-calibrated so the uncompensated dead zone at 0.005 deg/s is the paper's "
        f"2 s), kpp = {_f(g['kpp'])} 1/s (cascade rule (kp/J)/4), observer k = {_f(g['k_obs'])}, J_ff = {_f(g['J_ff'])}.",
        "",
        "**Metrics** (`lugre_jax.metrics`): dead zone = mean horizontal lag of the position curve behind the ideal ramp "
        "over the last 25% of a 30 s record [s]; creep amplitude = peak-to-peak of the detrended position error over the "
        "second half [deg]; cone = fraction of time the position lies between (v +- 0.001)*t (the paper's Fig. 13 "
        "boundary lines); band = fraction of samples with |omega - v| <= 0.001 deg/s.",
        "",
        "| Figure/Table | Paper's claim | Ours (measured) | Verdict | Why |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        fig = f" ([png]({r['figure']}))" if r.get("figure") else ""
        cells = [r["id"] + fig, r["paper_claim"], r["ours"], r["verdict"], r["why"]]
        # A literal | would end the cell; GitHub-flavoured Markdown reads \| as the character.
        lines.append("| " + " | ".join(c.replace("|", "\\|").replace("\n", " ") for c in cells) + " |")
    lines += ["", "Identified static models (RMS against the averaged data):", ""]
    for k, v in setup.static_params.items():
        segs = "; ".join(f"[{float(s['v_range'][0]):g}, {float(s['v_range'][1]):g}] Fc={_f(s['Fc'])} Fs={_f(s['Fs'])} vs={_f(s['vs'])} "
                         f"sigma2={_f(s['sigma2'])} sigma0={_f(s['sigma0'], 4)} sigma1={_f(s['sigma1'])}" for s in v["segments"])
        lines.append(f"- {k} (RMS {_f(v['rms_nm'])} N*m): {segs}")
    lines += ["", "Wall time per stage [s]: " + ", ".join(f"{k} {v:.1f}" for k, v in timings.items()), ""]
    with atomic_path(out / "REPORT.md") as tmp:
        tmp.write_text("\n".join(lines) + "\n")
