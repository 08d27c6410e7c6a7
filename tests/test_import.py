"""Importing the package must not start XLA's backend: the CLI sets the host device count (one per
core, so the batched simulator can shard) after import, and XLA reads it only once, at start."""

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

    code = ("import sys\nfrom lugre_jax import cli\ncli._maybe_enable_host_devices([])\n"
            "import jax\nprint(len(jax.devices()))\n")
    env = {k: v for k, v in os.environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert int(out.stdout.strip()) == (os.cpu_count() or 1), out.stdout + out.stderr
