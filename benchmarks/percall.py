"""Per-call time of lugre-jax bench's throughput configuration (Bosh3, dt 0.02, 20 s at 100 Hz,
per-lane tracking errors), batched with `batch` lanes: `calls` calls timed together, `reps` times.
Works on the pre-refactor tree (lugre_jax._bench) and on the current one (lugre_jax._cli._bench)."""
import os, sys, time
import lugre_jax
if hasattr(lugre_jax, "configure"):
    lugre_jax.configure()
import jax, numpy as np
try:
    from lugre_jax._cli._bench import bench_system, lane_factors, _tracking_errors, simulate, DURATION, HZ
except ImportError:
    from lugre_jax._bench import bench_system, lane_factors, _tracking_errors, simulate, DURATION, HZ
batch, calls, reps = (int(a) for a in (sys.argv[1:] + ["1", "2000", "5"][len(sys.argv) - 1:]))
system = bench_system(lane_factors(batch, seed=3))
run = lambda: simulate(system, DURATION, HZ, batched=True, shard=None, reduce=_tracking_errors, solver="bosh3", dt=0.02)
jax.block_until_ready(run())
wall, cpu = [], []
for _ in range(reps):
    t, c = time.perf_counter(), time.process_time()
    for _ in range(calls):
        jax.block_until_ready(run())
    wall.append((time.perf_counter() - t) / calls * 1e3)
    cpu.append((time.process_time() - c) / calls * 1e3)
print(f"{os.environ.get('TAG', '?'):5s} batch={batch} wall min {min(wall):.3f} med {np.median(wall):.3f}  "
      f"cpu min {min(cpu):.3f} med {np.median(cpu):.3f} ms/call  load {os.getloadavg()[0]:.1f}", flush=True)
