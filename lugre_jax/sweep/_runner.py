"""The sweep runner: chunked, resumable, split over local devices and over processes.

Folder layout (``out``)::

    sweep_state.json       SPEC hash, point and chunk counts (written once; a different SPEC is refused)
    spec.json              the SPEC, scenario inlined
    samples.npy            (n_points, D) parameter values, in the sampler's order
    chunks/chunk_NNNNNN.npz  per chunk: Y (points, outputs) and status (points,) int8
    outputs.npz, outputs.csv   all points: X, Y, status (CSV up to 262,144 points)
    indices.json           sobol: SALib's keys per output, with the dropped-group count
    summary.json           status counts, per-output statistics, timing
    *.png                  tornado plots (sobol) or heatmaps (grid)

A chunk file appears by rename only when complete, so a run killed at any instant (SIGKILL too)
leaves whole chunks and temporaries; a new run with the same SPEC removes the temporaries and
computes only the missing chunks. Each chunk is computed from its points alone with the same
compiled program (the last chunk is padded to full size), so the result does not depend on where
a run was interrupted. Process ``rank`` of ``world`` computes chunks ``i = rank (mod world)``;
rank 0 waits for the others' chunk files (a shared folder) and writes the analysis.

accuracy.json          the fast stepping against a tight solve on points spread over the box
                       (SPEC key ``accuracy``; also in summary.json and indices.json)

Status per point: 0 solved by the fast stepping, 1 failed it and solved by the stiff adaptive
Kvaerno5, 2 failed both (its outputs are NaN in the files and it is left out of every analysis).
"""

from __future__ import annotations

import dataclasses
import json
import time
import warnings
from pathlib import Path
from typing import Any

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._simulation import RESULT_OK, Adaptive, Lanes, SaveAt, simulate
from ..io import atomic_path, write_csv, write_json, write_manifest
from ._paths import batch_system
from ._sample import Grid, Saltelli
from ._sobol import sobol_analyze
from ._spec import SweepSpec

STATUS_FAST, STATUS_STIFF, STATUS_FAILED = 0, 1, 2
_CSV_MAX = 262_144
# the runner's resume state (SPEC hash and counts); MANIFEST.json, every command's completion record,
# is written last over the whole folder
_MANIFEST = "sweep_state.json"
_ACCURACY = "accuracy.json"
# The accuracy check's reference: implicit, so it holds on stiff lanes, and far tighter than any
# metric's tolerance.
TIGHT = Adaptive(diffrax.Kvaerno5(), rtol=1e-9, atol=1e-11, max_steps=200_000)


class _Reduce(eqx.Module):
    """Per-lane reduction: the metrics and the result code (hashable, so compilations are reused)."""

    outputs: tuple

    def __call__(self, sol):
        return jnp.stack([m(sol) for m in self.outputs]), sol.result


def _simulate_lanes(system, spec: SweepSpec, stepping, shard):
    """THE simulator call of the sweep: per-lane metrics ``(lanes, outputs)`` and result codes
    ``(lanes,)``, reduced inside the batched call (nothing of the trajectories is kept)."""
    vals, code = simulate(system, spec.duration_s, spec.sample_hz, batched=True, stepping=stepping,
                          saveat=SaveAt(reduce=_Reduce(spec.outputs)), lanes=Lanes(shard=shard))
    return np.asarray(vals), np.asarray(code)


def _take(tree, idx):
    return jax.tree.map(lambda x: x[idx] if eqx.is_array(x) else x, tree)


def run_chunk(spec: SweepSpec, X: np.ndarray, *, shard: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Outputs ``(len(X), n_outputs)`` and status ``(len(X),)`` for the points ``X``, padded to
    ``spec.chunk_size`` lanes (so every chunk runs the same compiled program)."""
    n = X.shape[0]
    pad = max(spec.chunk_size, n)
    Xp = np.concatenate([X, np.repeat(X[:1], pad - n, 0)]) if pad > n else X
    system = batch_system(spec.system, list(spec.paths), Xp)
    Y, code = _simulate_lanes(system, spec, spec.fast, shard)
    Y, code = Y[:n].copy(), code[:n]
    ok = (code == RESULT_OK) & np.all(np.isfinite(Y), axis=1)
    status = np.where(ok, STATUS_FAST, STATUS_FAILED).astype(np.int8)
    bad = np.flatnonzero(~ok)
    if bad.size and spec.stiff is not None:
        # Re-solve only the failed lanes, padded to a power of two (>= 8) so a sweep compiles the
        # stiff solve for a handful of sizes, not one per failure count.
        m = max(8, 1 << int(bad.size - 1).bit_length())
        idx = np.concatenate([bad, np.repeat(bad[:1], m - bad.size)])
        Y2, code2 = _simulate_lanes(_take(system, jnp.asarray(idx)), spec, spec.stiff, shard)
        Y2, code2 = Y2[:bad.size], code2[:bad.size]
        ok2 = (code2 == RESULT_OK) & np.all(np.isfinite(Y2), axis=1)
        Y[bad] = Y2
        status[bad] = np.where(ok2, STATUS_STIFF, STATUS_FAILED)
    Y[status == STATUS_FAILED] = np.nan
    return Y, status


def check_accuracy(spec: SweepSpec, *, shard: bool | None = None) -> dict:
    """The fast stepping (with its fallback, as the sweep runs it) against a tight stiff solve on
    ``spec.accuracy.lanes`` points spread over the box (scrambled Sobol', ``spec.seed``): per output
    the largest absolute deviation, the output's largest magnitude on those points (its scale), and
    whether the deviation is within ``rtol`` times that scale. Lanes where the tight solve or both
    fast solves fail are left out and counted."""
    from scipy.stats import qmc

    acc = spec.accuracy
    lo, hi = spec.bounds[:, 0], spec.bounds[:, 1]
    with warnings.catch_warnings():  # any count of points: the balance of 2^m points is not needed here
        warnings.simplefilter("ignore", UserWarning)
        U = qmc.Sobol(len(spec.names), scramble=True, seed=spec.seed).random(acc.lanes)
    X = lo + U * (hi - lo)
    Y, status = run_chunk(dataclasses.replace(spec, chunk_size=acc.lanes), X, shard=shard)
    system = batch_system(spec.system, list(spec.paths), X)
    Yt, code = _simulate_lanes(system, spec, TIGHT, shard)
    ok = (status != STATUS_FAILED) & (code == RESULT_OK) & np.all(np.isfinite(Yt), axis=1)
    outputs, within = {}, True
    for k, name in enumerate(spec.output_names):
        dev = float(np.max(np.abs(Y[ok, k] - Yt[ok, k]))) if ok.any() else float("nan")
        scale = float(np.max(np.abs(Yt[ok, k]))) if ok.any() else float("nan")
        good = bool(ok.any() and dev <= acc.rtol * scale)
        within &= good
        outputs[name] = {"max_abs_deviation": dev, "scale": scale, "relative": dev / scale if scale else
                         (0.0 if dev == 0 else float("inf")), "within": good}
    return {"stepping": spec.fast.describe(), "reference": TIGHT.describe(), "lanes": acc.lanes,
            "lanes_compared": int(ok.sum()), "rtol": acc.rtol, "enforce": acc.enforce, "within": within,
            "outputs": outputs}


def _refusal(spec: SweepSpec, acc: dict) -> str:
    name, o = max(((n, o) for n, o in acc["outputs"].items() if not o["within"]),
                  key=lambda item: item[1]["relative"] if np.isfinite(item[1]["relative"]) else np.inf)
    return (f"SPEC.accuracy.rtol: the fast stepping {acc['stepping']} is {o['max_abs_deviation']:.3g} from a tight "
            f"solve in output '{name}' ({o['relative']:.2%} of its scale {o['scale']:.3g}) on "
            f"{acc['lanes_compared']} of {acc['lanes']} points spread over the box, more than accuracy.rtol "
            f"{acc['rtol']:g}; choose a finer \"stepping\" (or raise accuracy.rtol), or set "
            f"\"accuracy\": {{\"enforce\": false}} to run it anyway")


def _accuracy(spec: SweepSpec, out: Path, shard) -> dict | None:
    """The accuracy check of ``spec`` (read back from ``out`` when this SPEC's folder has it);
    ``ValueError`` when it is beyond tolerance and enforced. Runs before anything is written."""
    if spec.accuracy is None:
        return None
    path = out / _ACCURACY
    if path.exists() and (out / _MANIFEST).exists():
        try:
            if json.loads((out / _MANIFEST).read_text()).get("spec_sha256") == spec.digest():
                return json.loads(path.read_text())
        except (OSError, json.JSONDecodeError, AttributeError):
            pass
    acc = check_accuracy(spec, shard=shard)
    if spec.accuracy.enforce and not acc["within"]:
        raise ValueError(_refusal(spec, acc))
    return acc


@dataclasses.dataclass(frozen=True)
class SweepResult:
    """What :func:`run_sweep` did. ``complete`` is False when this process stopped early
    (``max_chunks``) or, for rank > 0, always (rank 0 writes the analysis)."""

    out: str
    n_points: int
    n_chunks: int
    chunks_computed: int
    complete: bool
    status_counts: dict | None = None
    indices: dict | None = None
    seconds: float = 0.0
    accuracy: dict | None = None

    def to_json(self) -> dict[str, Any]:
        d = {k: v for k, v in dataclasses.asdict(self).items() if k != "indices"}
        if self.indices is not None:
            d["indices"] = {k: v.to_json() for k, v in self.indices.items()}
        return d


def _chunk_path(out: Path, i: int) -> Path:
    return out / "chunks" / f"chunk_{i:06d}.npz"


def _prepare(spec: SweepSpec, out: Path, X: np.ndarray, n_chunks: int, rank: int, wait_s: float) -> None:
    """Create the folder (rank 0), or check that it holds this SPEC's sweep."""
    digest = spec.digest()
    man = out / _MANIFEST
    if rank != 0:  # rank 0 creates the folder; the others wait for its manifest
        deadline = time.monotonic() + wait_s
        while not man.exists():
            if time.monotonic() > deadline:
                raise OSError(f"{out}: no {_MANIFEST} from process 0 after {wait_s:g} s")
            time.sleep(0.1)
    if man.exists():
        try:
            old = json.loads(man.read_text()).get("spec_sha256")
        except (OSError, json.JSONDecodeError, AttributeError):
            old = None
        if old != digest:
            raise ValueError(f"{out}: holds a sweep of a different SPEC ({_MANIFEST} spec_sha256 {str(old)[:12]}... "
                             f"!= {digest[:12]}...; a SPEC without 'stepping' counts its default stepping); use a new --out "
                             f"folder or delete this one")
        return
    if out.exists() and any(out.iterdir()):
        raise ValueError(f"{out}: exists, is not empty and has no {_MANIFEST}; use a new --out folder")
    (out / "chunks").mkdir(parents=True, exist_ok=True)
    write_json(out / "spec.json", spec.raw)
    with atomic_path(out / "samples.npy") as tmp:
        np.save(tmp, X)
    # Written last: a folder with a manifest has its samples.
    write_json(man, dict(spec_sha256=digest, n_points=int(X.shape[0]), chunk_size=spec.chunk_size,
                         n_chunks=n_chunks, names=list(spec.names), outputs=list(spec.output_names)))


def _remove_stale(out: Path, rank: int, world: int) -> None:
    """Temporaries of chunks this process owns, left by a killed run (another process's are live)."""
    for p in (out / "chunks").glob(".chunk_*"):
        try:
            i = int(p.name.split("_")[1].split(".")[0])
        except (IndexError, ValueError):
            continue
        if i % world == rank:
            p.unlink(missing_ok=True)


def run_sweep(spec: SweepSpec, out, *, progress: bool = True, shard: bool | None = None, rank: int | None = None,
              world: int | None = None, max_chunks: int | None = None, wait_s: float = 3600.0,
              figures: bool = True) -> SweepResult:
    """Run (or resume) the sweep ``spec`` into folder ``out``; see the module doc for the files.

    ``shard``: split each chunk over local devices (None: when it pays, as ``simulate``). ``rank``/
    ``world``: this process's share, by default ``jax.process_index()``/``jax.process_count()``
    (after ``jax.distributed.initialize``). ``max_chunks``: stop after computing that many chunks
    (a time-limited job; run again to continue). ``wait_s``: how long rank 0 waits for the other
    processes' chunks.
    """
    t_start, started = time.perf_counter(), time.time()
    out = Path(out)
    rank = jax.process_index() if rank is None else int(rank)
    world = jax.process_count() if world is None else int(world)
    if world > 1:
        # jax.devices() lists every process's devices, and the simulator's split uses jax.devices():
        # under jax.distributed each process runs on its own (first) device.
        shard = False
    X = spec.sampler.sample(spec.problem, spec.n, spec.seed)
    n_points = X.shape[0]
    n_chunks = -(-n_points // spec.chunk_size)
    accuracy = _accuracy(spec, out, shard)  # may refuse the sweep: before anything is written
    _prepare(spec, out, X, n_chunks, rank, wait_s)
    if accuracy is not None and rank == 0 and not (out / _ACCURACY).exists():
        write_json(out / _ACCURACY, accuracy)
    _remove_stale(out, rank, world)
    mine = [i for i in range(rank, n_chunks, world) if not _chunk_path(out, i).exists()]
    if max_chunks is not None:
        mine = mine[:max_chunks]
    bar = None
    if progress and mine:
        from tqdm.auto import tqdm

        total = sum(min(spec.chunk_size, n_points - i * spec.chunk_size) for i in mine)
        bar = tqdm(total=total, unit="sim", desc=f"sweep[{rank}/{world}]" if world > 1 else "sweep",
                   smoothing=0.1, dynamic_ncols=True)
    failed_mark = out / f".process_{rank}.failed"
    failed_mark.unlink(missing_ok=True)
    try:
        for i in mine:
            lo, hi = i * spec.chunk_size, min(n_points, (i + 1) * spec.chunk_size)
            Y, status = run_chunk(spec, X[lo:hi], shard=shard)
            with atomic_path(_chunk_path(out, i)) as tmp:
                np.savez(tmp, Y=Y, status=status)
            if bar is not None:
                bar.update(hi - lo)
                bar.set_postfix(stiff=int((status == STATUS_STIFF).sum()), failed=int((status == STATUS_FAILED).sum()))
    except BaseException as e:
        if world > 1:  # tell rank 0 not to wait for chunks that will not come
            failed_mark.write_text(f"{type(e).__name__}: {e}\n")
        raise
    finally:
        if bar is not None:
            bar.close()
    missing = [i for i in range(n_chunks) if not _chunk_path(out, i).exists()]
    if missing and (rank != 0 or world == 1 or max_chunks is not None):
        return SweepResult(str(out), n_points, n_chunks, len(mine), False, seconds=time.perf_counter() - t_start)
    if rank != 0:
        return SweepResult(str(out), n_points, n_chunks, len(mine), False, seconds=time.perf_counter() - t_start)
    deadline = time.monotonic() + wait_s
    while missing:
        if time.monotonic() > deadline:
            raise OSError(f"{out}: {len(missing)} chunks (first {missing[0]}) still missing after {wait_s:g} s; "
                          "are the other processes running? Run again to resume")
        # Markers older than this run are from an earlier attempt of a process that has restarted.
        dead = sorted(p for p in out.glob(".process_*.failed") if p.stat().st_mtime >= started)
        if dead:
            raise OSError(f"{out}: {dead[0].name[1:-7]} stopped ({dead[0].read_text().strip()}); "
                          f"{len(missing)} chunks missing; run again to resume")
        time.sleep(0.2)
        missing = [i for i in missing if not _chunk_path(out, i).exists()]
    return _finish(spec, out, X, n_chunks, len(mine), t_start, figures, accuracy)


def _load_all(out: Path, n_chunks: int) -> tuple[np.ndarray, np.ndarray]:
    Ys, Ss = [], []
    for i in range(n_chunks):
        with np.load(_chunk_path(out, i)) as z:
            Ys.append(z["Y"])
            Ss.append(z["status"])
    return np.concatenate(Ys), np.concatenate(Ss)


def _finish(spec: SweepSpec, out: Path, X, n_chunks, computed, t_start, figures, accuracy=None) -> SweepResult:
    Y, status = _load_all(out, n_chunks)
    names, onames = list(spec.names), list(spec.output_names)
    with atomic_path(out / "outputs.npz") as tmp:
        np.savez(tmp, X=X, Y=Y, status=status, names=np.array(names), outputs=np.array(onames))
    if X.shape[0] <= _CSV_MAX:
        cols = {n: X[:, j] for j, n in enumerate(names)}
        cols.update({n: Y[:, k] for k, n in enumerate(onames)})
        cols["status"] = status
        write_csv(out / "outputs.csv", cols)
    counts = {"fast_ok": int((status == STATUS_FAST).sum()), "stiff_ok": int((status == STATUS_STIFF).sum()),
              "failed": int((status == STATUS_FAILED).sum())}
    indices = None
    if isinstance(spec.sampler, Saltelli):
        so = spec.sampler.calc_second_order
        indices = {}
        for k, name in enumerate(onames):
            try:
                indices[name] = sobol_analyze(spec.problem, Y[:, k], seed=spec.seed, calc_second_order=so,
                                              num_resamples=spec.num_resamples, conf_level=spec.conf_level,
                                              ok=status != STATUS_FAILED)
            except ValueError as e:  # too few usable groups: say so in the file, not a crash at the end
                indices[name] = None
                print(f"sweep: {name}: no indices ({e})")
        write_json(out / "indices.json", {
            "problem": spec.problem,
            "outputs": {k: (v.to_json() if v is not None else None) for k, v in indices.items()},
            "estimators": "S1 Saltelli 2010, ST Jansen, S2 Saltelli 2002; bootstrap over base points (SALib's draw)",
            "accuracy": accuracy,
        })
        indices = {k: v for k, v in indices.items() if v is not None}
    stats = {}
    for k, name in enumerate(onames):
        y = Y[status != STATUS_FAILED, k]
        stats[name] = ({"mean": float(y.mean()), "std": float(y.std()), "min": float(y.min()),
                        "p50": float(np.median(y)), "max": float(y.max())} if y.size else None)
    seconds = time.perf_counter() - t_start
    write_json(out / "summary.json", dict(n_points=int(X.shape[0]), n_chunks=n_chunks, chunks_computed_this_run=computed,
                                          status=counts, outputs=stats, accuracy=accuracy, seconds_this_run=seconds,
                                          status_codes={"0": "fast stepping ok", "1": "stiff Kvaerno5 re-solve ok",
                                                        "2": "failed both; NaN outputs, left out of analyses"}))
    if figures:
        from ._plots import grid_heatmaps, tornado_plots

        if indices:
            tornado_plots(indices, out)
        if isinstance(spec.sampler, Grid):
            grid_heatmaps(spec, X, Y, status, out)
    write_manifest(out, {"command": "sweep", "spec_sha256": spec.digest()})
    return SweepResult(str(out), int(X.shape[0]), n_chunks, computed, True, counts, indices, seconds, accuracy)
