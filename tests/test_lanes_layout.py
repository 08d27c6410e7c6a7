"""The lane layout: default chunks chosen from a device description (testable on a CPU with a
stated description of an accelerator), and results that do not depend on the chunking."""

import diffrax
import numpy as np
import pytest

import lugre_jax as lj
from lugre_jax._simulation._lanes import DEFAULT_CHUNK, DeviceInfo, default_chunk, device_info

H100 = DeviceInfo("gpu", free_bytes=79 * 2**30, kind="NVIDIA H100 80GB HBM3")


def test_default_chunk_per_device():
    lane_bytes = 8 * 2001 * 16 + 8 * 64 * 8  # simulate's estimate at 2,001 samples
    assert default_chunk(DeviceInfo("cpu"), 1_000_000, lane_bytes) == DEFAULT_CHUNK
    # an accelerator takes every lane in one call when half its free memory holds them ...
    assert default_chunk(H100, 100_000, lane_bytes) == 100_000
    # ... and as many as it holds when not
    n = default_chunk(H100, 10_000_000, lane_bytes)
    assert n == int(0.5 * H100.free_bytes) // lane_bytes and n * lane_bytes <= 0.5 * H100.free_bytes
    assert default_chunk(DeviceInfo("gpu", free_bytes=None), 10_000, lane_bytes) == DEFAULT_CHUNK
    assert device_info().platform == "cpu"


def _batch(b):
    rng = np.random.default_rng(5)
    return lj.stack_systems([
        lj.System(friction=lj.LuGre(Fc=0.9, Fs=float(fs), vs=0.03, sigma0=float(s0), sigma1=2.0, sigma2=8.0),
                  joint=lj.Joint(J=0.128), controller=lj.VelocityPID(kp=8.0, ki=60.0),
                  reference=lj.VelocitySteps([0.02, 0.1, -0.05], dwell_s=0.7))
        for fs, s0 in zip(rng.uniform(1.0, 1.5, b), rng.uniform(50, 200, b))])


@pytest.mark.parametrize("stepping", [lj.FixedStep(diffrax.Bosh3(), dt=0.005), lj.LaneAdaptive()],
                         ids=["fixed", "lane_adaptive"])
def test_results_do_not_depend_on_chunking(stepping):
    batch = _batch(13)
    ref = lj.simulate(batch, 2.0, 100.0, batched=True, stepping=stepping, lanes=lj.Lanes(chunk_size=13))
    for chunk in (1, 4, 8):
        sol = lj.simulate(batch, 2.0, 100.0, batched=True, stepping=stepping, lanes=lj.Lanes(chunk_size=chunk))
        np.testing.assert_array_equal(np.asarray(sol.result), np.asarray(ref.result))
        if isinstance(stepping, lj.FixedStep):
            np.testing.assert_allclose(np.asarray(sol.ys), np.asarray(ref.ys), rtol=1e-12, atol=1e-300)
        else:
            # each lane's accept/reject decisions can differ in the last bit between vector widths:
            # equal to far below the stepping's own tolerance
            np.testing.assert_allclose(np.asarray(sol.theta), np.asarray(ref.theta), rtol=0, atol=1e-9)
