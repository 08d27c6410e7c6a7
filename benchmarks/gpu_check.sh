#!/usr/bin/env bash
# Issue #34's table on whatever accelerator this runs on, one line per figure, at most ~6 minutes
# (each row has its own time limit; a row that runs out prints "timeout"). Run from the repository:
#     bash benchmarks/gpu_check.sh [results_dir]
# Needs jax (with CUDA for a GPU), diffrax, equinox, numpy, scipy, tqdm. A smaller run to try it on a
# CPU: GPU_CHECK_SWEEP_N=64 GPU_CHECK_LANES=1000 bash benchmarks/gpu_check.sh /tmp/gpu_check
set -u
cd "$(dirname "$0")/.."
OUT=${1:-benchmarks/results/gpu_check}
mkdir -p "$OUT"
PY=${PYTHON:-python}

row() {  # row LIMIT_S NAME COMMAND...
  local limit=$1 name=$2; shift 2
  local t0=$SECONDS
  if timeout "$limit" "$@" > "$OUT/$name.log" 2>&1; then
    printf '%-44s %s\n' "$name" "$(tail -n 1 "$OUT/$name.log")"
  else
    printf '%-44s %s (%d s; see %s)\n' "$name" "timeout or error" "$((SECONDS - t0))" "$OUT/$name.log"
  fi
}

$PY - <<'PY' | tee "$OUT/device.txt"
import jax
d = jax.devices()[0]
print(f"device: {d.platform} {getattr(d, 'device_kind', '')} x{len(jax.devices())}, jax {jax.__version__}")
PY

# 1-2: the 2^20-simulation sweep (Bosh3 at 20 ms, 20 s), default chunks and 262,144-point chunks
$PY - "$OUT" <<'PY'
import json, os, sys
spec = json.load(open("experiments/scenarios/sweep_bench.json"))
spec["scenario"] = os.path.abspath("experiments/scenarios/stick_slip_pi.json")
spec["n"] = int(os.environ.get("GPU_CHECK_SWEEP_N", spec["n"]))
spec["chunk_size"] = min(spec["chunk_size"], spec["n"] * 8)
spec["accuracy"] = None  # timed alone; its check is a separate row of the sweep's summary
json.dump(spec, open(f"{sys.argv[1]}/sweep_bench.json", "w"))
spec["chunk_size"] = min(262144, spec["n"] * 8)
json.dump(spec, open(f"{sys.argv[1]}/sweep_bench_262k.json", "w"))
PY
for s in sweep_bench sweep_bench_262k; do
  rm -rf "$OUT/$s.out"
  row 150 "$s (sweep seconds)" $PY -c "
import json, subprocess, sys
r = subprocess.run([sys.executable, '-m', 'lugre_jax.cli', 'sweep', '$OUT/$s.json', '--out', '$OUT/$s.out',
                    '--no-progress', '--no-figures'], capture_output=True, text=True)
if r.returncode: sys.exit(r.stderr[-2000:])
s = json.loads(r.stdout.strip().splitlines()[-1])
print(f\"{s['n_points']:,} simulations in {s['seconds']:.2f} s inside the sweep\")"
done

# 3-4: lj.simulate, 100,000 lanes of the paper's joint, FixedStep(Bosh3, dt=0.005), 20 s at 100 Hz
for chunk in default 100000; do
  row 90 "simulate 1e5 lanes Bosh3 5 ms ($chunk chunk)" $PY -c "
import time, numpy as np, jax, diffrax, lugre_jax as lj
lj.configure()
one = lj.System(friction=lj.paper_friction(), joint=lj.Joint(J=lj.PAPER_J), controller=lj.VelocityPID(kp=8.0, ki=60.0),
                reference=lj.VelocitySteps([0.02, 0.1, -0.05, 0.5], dwell_s=5.0))
import os
b = int(os.environ.get('GPU_CHECK_LANES', 100_000))
s = lj.broadcast_system(one, b)
lanes = lj.Lanes() if '$chunk' == 'default' else lj.Lanes(chunk_size=min(b, $chunk))
st = lj.FixedStep(diffrax.Bosh3(), dt=0.005)
f = lambda: jax.block_until_ready(lj.simulate(s, 20.0, 100.0, batched=True, stepping=st, lanes=lanes,
                                              saveat=lj.SaveAt(mean=lambda x: x.theta ** 2)).value)
t = time.perf_counter(); f(); first = time.perf_counter() - t
t = time.perf_counter(); f(); el = time.perf_counter() - t
print(f'{b / el:,.0f} simulations/s ({el:.2f} s per call, first call {first:.1f} s)')"
done
