"""The paper's parameter sets: Table 1 (static), Table 2 (dynamic) and the inertia J from eq. (18).

Table 1 lists three segments, split at 0.05 deg/s (minimum torque) and 1.2 deg/s (critical Stribeck
velocity). Segment 3 is the high-velocity form eq. (11): Fs and vs are "/" in the paper; we encode it
as ``Fs = Fc`` (the exponential term then vanishes) with ``vs = 1``.

Eq. (18), ``sigma1 + sigma2 = 1.4*sqrt(J*sigma0)``, lets us recover the J the authors used. Segments
1 and 3 give J = 0.1280 N*m*s^2/deg, segment 2 gives J = 0.1923: the paper's Table 2 is not
self-consistent. We use J = 0.128 (two of three segments agree) and report the inconsistency rather
than hide it: :func:`paper_inertia_per_segment` returns all three.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..friction import LuGre, Segmented

TABLE1 = {
    # segment: (Fc [N*m], Fs [N*m], vs [deg/s], sigma2 [N*m*s/deg])
    1: (0.9150, 6.4808, 0.0315, 2.9804),
    2: (0.8600, 2.3570, 0.0480, 3.0502),
    3: (4.5203, None, None, 0.0012),
}
TABLE2 = {
    # segment: (sigma0 [N*m/deg], sigma1 [N*m*s/deg])
    1: (111.3160, 2.3042),
    2: (29.9400, 0.3095),
    3: (90.4060, 4.7613),
}
SEGMENT_EDGES = (0.05, 1.2)  # deg/s
PAPER_J = 0.128  # N*m*s^2/deg, from eq. (18) on segments 1 and 3


def paper_inertia_per_segment() -> dict[int, float]:
    """J [N*m*s^2/deg] implied by eq. (18) for each segment of Tables 1-2."""
    out = {}
    for k in (1, 2, 3):
        s0, s1 = TABLE2[k]
        s2 = TABLE1[k][3]
        out[k] = float(((s1 + s2) / 1.4) ** 2 / s0)
    return out


def paper_segment(k: int) -> LuGre:
    """LuGre model of segment ``k`` (1, 2 or 3) of Tables 1-2.

    Segment 1 is not passive (:class:`~lugre_jax.friction.LuGre`: ``sigma2 = 2.98`` where passivity
    needs ``sigma1*(Fs - Fc)/Fc = 14.0``); it is the paper's published model and is built as
    published (``require_passive=False``, whatever the default).
    """
    if k not in TABLE1:
        raise ValueError(f"segment must be 1, 2 or 3, got {k!r}")
    Fc, Fs, vs, s2 = TABLE1[k]
    if Fs is None:
        Fs, vs = Fc, 1.0
    s0, s1 = TABLE2[k]
    return LuGre(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2, sigma0=s0, sigma1=s1, require_passive=False)


def paper_friction() -> Segmented:
    """The paper's piecewise LuGre model: three segments of Tables 1-2 split at 0.05 and 1.2 deg/s."""
    return Segmented(tuple(paper_segment(k) for k in (1, 2, 3)), jnp.asarray(SEGMENT_EDGES))


def paper_table1_array() -> np.ndarray:
    """Table 1 as a (3, 4) array (Fc, Fs, vs, sigma2); NaN where the paper prints '/'."""
    return np.array([[np.nan if x is None else x for x in TABLE1[k]] for k in (1, 2, 3)])
