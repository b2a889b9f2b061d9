"""squeal: a disc-brake squeal simulator (the BSQL method) from Python.

The same engine as the ``squeal`` command, in memory::

    import squeal
    scene = squeal.Scene.from_file("examples/sample-brake/base.toml").set("friction.law.mu0", 0.5)
    c = squeal.cea(scene)                 # complex eigenvalues at the steady sliding state
    r = squeal.reduce(scene)              # K, M, B as numpy; DOF map and gaps as records
    t = squeal.transient(scene)           # time history, summary, verdict
    df = squeal.sweep(scene, "friction.law.mu0", [0.3, 0.5, 0.7])   # a pandas DataFrame
    p = squeal.propensity(scene, {"friction.law.mu0": "uniform(0.4, 0.6)"}, 256)  # P(squeal)

Every computation releases the GIL; ``progress=`` takes a callable receiving one event dict
per step (``squeal.TqdmProgress()`` draws tqdm bars) and Ctrl-C cancels a run
(``KeyboardInterrupt``). Errors are ``squeal.SquealError`` subclasses carrying the command
line's message.
"""

from __future__ import annotations

from ._squeal import (
    Cancelled,
    InputError,
    InputFileNotFound,
    MeshError,
    ModelError,
    OutputError,
    Scene,
    SceneError,
    SolverError,
    SquealError,
    __version__,
)
from .api import (
    CeaResult,
    CompareResult,
    LimitCycleResult,
    ModesResult,
    ReducedModel,
    TransientResult,
    cea,
    compare,
    limit_cycle,
    modes,
    reduce,
    transient,
)
from .progress import TqdmProgress
from .propensity import PropensityResult, propensity
from .sweep import sweep

__all__ = [
    "Cancelled",
    "CeaResult",
    "CompareResult",
    "InputError",
    "InputFileNotFound",
    "LimitCycleResult",
    "MeshError",
    "ModelError",
    "ModesResult",
    "OutputError",
    "PropensityResult",
    "ReducedModel",
    "Scene",
    "SceneError",
    "SolverError",
    "SquealError",
    "TqdmProgress",
    "TransientResult",
    "__version__",
    "compare",
    "cea",
    "limit_cycle",
    "modes",
    "propensity",
    "reduce",
    "sweep",
    "transient",
]
