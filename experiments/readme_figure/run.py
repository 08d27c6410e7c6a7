"""The README's figure: the paper's joint (Tables 1-2, J = 0.128) under velocity PI (kp = 8, ki = 60)
at three commanded velocities, simulated with the library's default (error-controlled) stepping in
one batched call. Writes docs/img/creep.png.

    python experiments/readme_figure/run.py [--out docs/img/creep.png]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import lugre_jax as lj  # noqa: E402
from lugre_jax.io import save_figure  # noqa: E402

VELOCITIES = (0.1, 0.02, 0.005)  # deg/s


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[2] / "docs" / "img" / "creep.png"))
    a = ap.parse_args(argv)
    lj.configure()
    systems = [lj.System(friction=lj.paper_friction(), joint=lj.Joint(J=lj.PAPER_J),
                         controller=lj.VelocityPID(kp=8.0, ki=60.0), reference=lj.VelocitySteps([v]))
               for v in VELOCITIES]
    sol = lj.simulate(lj.stack_systems(systems), 40.0, 20.0, batched=True)
    assert np.all(np.asarray(sol.result) == lj.RESULT_OK)
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.4))
    for i, v in enumerate(VELOCITIES):
        ax[0].plot(sol.ts, np.asarray(sol.omega[i]) / v, label=f"{v:g} deg/s")
        ax[1].plot(sol.ts, np.asarray(sol.theta[i] - sol.theta_ref[i]), label=f"{v:g} deg/s")
    ax[0].set(xlabel="time [s]", ylabel="velocity / command [-]", title="stick-slip and creep")
    ax[1].set(xlabel="time [s]", ylabel="position error [deg]", title="tracking error")
    ax[0].legend(title="command")
    for x in ax:
        x.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, a.out)
    print(a.out)


if __name__ == "__main__":
    main()
