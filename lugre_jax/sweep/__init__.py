"""Batched sensitivity sweeps: SALib-compatible sampling and Sobol' analysis in JAX, and a chunked,
resumable runner over local devices and ``jax.distributed`` processes (``lugre-jax sweep``).

Pure analysis (no simulator): :func:`saltelli_sample`, :func:`sobol_analyze`, :func:`latin_hypercube`,
:func:`grid_sample`. Sweeps of the simulator: :func:`load_spec` / :func:`spec_from_dict` check a SPEC
(see ``docs/sweeps.md``), :func:`run_sweep` runs it into a folder.
"""

from ._metrics import (
    AbstractMetric as AbstractMetric,
    BandFraction as BandFraction,
    CreepAmplitude as CreepAmplitude,
    DeadZone as DeadZone,
    StickSlip as StickSlip,
    TrackingError as TrackingError,
)
from ._paths import batch_system as batch_system
from ._problem import check_problem as check_problem
from ._runner import (
    STATUS_FAILED as STATUS_FAILED,
    STATUS_FAST as STATUS_FAST,
    STATUS_STIFF as STATUS_STIFF,
    SweepResult as SweepResult,
    run_chunk as run_chunk,
    run_sweep as run_sweep,
)
from ._sample import (
    AbstractSampler as AbstractSampler,
    Grid as Grid,
    LatinHypercube as LatinHypercube,
    Saltelli as Saltelli,
    grid_sample as grid_sample,
    latin_hypercube as latin_hypercube,
    saltelli_sample as saltelli_sample,
)
from ._sobol import SobolIndices as SobolIndices, sobol_analyze as sobol_analyze
from ._spec import (
    SweepSpec as SweepSpec,
    load_spec as load_spec,
    spec_from_dict as spec_from_dict,
)
from ._plots import tornado_plot as tornado_plot
