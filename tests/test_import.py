"""Importing the package changes nothing process-wide (no XLA_FLAGS, no x64) and does not start XLA's
backend; ``lugre_jax.configure()`` is the opt-in that the CLI, the benchmark and the tests call."""

import subprocess
import sys


def test_import_leaves_backend_unstarted():
    code = ("from jax._src import xla_bridge as xb\n"
            "import lugre_jax, lugre_jax.cli, lugre_jax.identify, lugre_jax.diagnose\n"
            "print(bool(xb._backends))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False", out.stdout + out.stderr


def test_cli_gets_one_host_device_per_core():
    import os

    code = ("import sys\nfrom lugre_jax import cli\ncli._configure_process(no_cache=True)\n"
            "import jax\nprint(len(jax.devices()))\n")
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert int(out.stdout.strip()) == (os.cpu_count() or 1), out.stdout + out.stderr


def _env_flags_after_import(flags):
    import os

    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    if flags is not None:
        env["XLA_FLAGS"] = flags
    code = "import os, lugre_jax\nlugre_jax.configure()\nprint(os.environ['XLA_FLAGS'])\n"
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          env=env).stdout.strip()


def test_configure_sets_xla_options_keeping_user_flags():
    opt = "xla_cpu_small_while_loop_byte_threshold"
    wide = "--xla_cpu_prefer_vector_width=512"
    assert _env_flags_after_import(None) == f"--xla_backend_extra_options={opt}=100000000 {wide}"
    # other backend options are merged into the same flag, not replaced by a second copy of it
    got = _env_flags_after_import("--xla_cpu_enable_fast_math=false --xla_backend_extra_options=a=1")
    assert got == f"--xla_cpu_enable_fast_math=false --xla_backend_extra_options=a=1,{opt}=100000000 {wide}"
    # values the user chose are kept
    mine = f"--xla_backend_extra_options={opt}=4096 --xla_cpu_prefer_vector_width=256"
    assert _env_flags_after_import(mine) == mine


def test_time_loop_compiles_to_one_kernel():
    # With the threshold raised at import, XLA:CPU outlines the solver's while loop into a single
    # kernel (a call tagged xla_cpu_small_call); without it, the loop is dispatched op by op.
    import os

    code = ("import lugre_jax as lj, jax, diffrax\nlj.configure()\n"
            "s = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),\n"
            "              controller=lj.VelocityPID(kp=8.0, ki=60.0), reference=lj.VelocitySteps([0.02]))\n"
            "f = jax.jit(lambda s: lj.simulate(s, 2.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02)).theta)\n"
            "print('xla_cpu_small_call' in f.lower(s).compile().as_text())\n")
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.strip() == "True", out.stdout + out.stderr
    env["XLA_FLAGS"] = "--xla_backend_extra_options=xla_cpu_small_while_loop_byte_threshold=1024"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.strip() == "False", out.stdout + out.stderr  # premise: the option decides it


def test_import_has_no_process_wide_side_effects():
    import os

    code = ("import os, jax\nbefore = os.environ.get('XLA_FLAGS')\n"
            "import lugre_jax, lugre_jax.cli, lugre_jax.identify, lugre_jax.diagnose\n"
            "print(os.environ.get('XLA_FLAGS') == before, jax.config.jax_enable_x64)\n")
    for flags in (None, "--xla_cpu_enable_fast_math=false"):
        env = {k: v for k, v in os.environ.items() if k not in ("XLA_FLAGS", "JAX_ENABLE_X64")}
        if flags:
            env["XLA_FLAGS"] = flags
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
        assert out.stdout.split() == ["True", "False"], out.stdout + out.stderr


def test_configure_after_backend_start_says_so():
    import os

    code = ("import jax, jax.numpy as jnp, lugre_jax\njnp.ones(2).block_until_ready()\n"
            "lugre_jax.configure(one_kernel_loops=False, vector_width=None)\n"  # x64 only: allowed
            "print(jax.config.jax_enable_x64)\n"
            "try:\n    lugre_jax.configure()\nexcept RuntimeError as e:\n    print('refused', 'before any JAX work' in str(e))\n")
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.split() == ["True", "refused", "True"], out.stdout + out.stderr


def test_simulate_without_x64_names_the_fix():
    import os

    code = ("import lugre_jax as lj\n"
            "s = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),\n"
            "              controller=lj.VelocityPID(kp=8.0, ki=60.0), reference=lj.VelocitySteps([0.02]))\n"
            "try:\n    lj.simulate(s, 1.0, 100.0)\nexcept RuntimeError as e:\n    print('configure()' in str(e))\n")
    env = {k: v for k, v in os.environ.items() if k not in ("XLA_FLAGS", "JAX_ENABLE_X64")}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert out.stdout.strip() == "True", out.stdout + out.stderr
