"""Type stubs of the extension module ``squeal._squeal`` (built from ``python/src``)."""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np

from .results import (
    BasisCheck,
    CacheUse,
    CeaReport,
    CeaSweep,
    CompareReport,
    HistoryColumn,
    LimitCycleReport,
    ModesReport,
    PropensityEvaluated,
    PropensityReport,
    SweepPoint,
    TransientSummary,
    Verdict,
)

__version__: str

_Path = Union[str, "os.PathLike[str]"]
_Progress = Optional[Callable[[Dict[str, Any]], None]]
_Value = Any  # bool | int | float | str | list | dict (a TOML value)

class SquealError(Exception): ...
class SceneError(SquealError):
    field: Optional[str]
    """The scene key or option the error names (None: a scene file that does not parse)."""
    path: Optional[str]
    """The scene file that does not parse (None otherwise)."""

class InputError(SquealError):
    field: Optional[str]
    path: Optional[str]
    """The input file (None: an in-memory array)."""

class InputFileNotFound(InputError, FileNotFoundError):
    """A missing input file: ``errno`` 2, ``filename`` and ``path`` the file."""
class MeshError(SquealError): ...
class ModelError(SquealError): ...
class SolverError(SquealError): ...
class OutputError(SquealError): ...
class Cancelled(SquealError): ...

class Scene:
    """A squeal scene (the TOML file's tables, typed and validated)."""

    @staticmethod
    def from_file(path: _Path, set: Optional[Mapping[str, _Value]] = None) -> "Scene":
        """Reads a scene file; ``set`` overrides values as ``--set key=value`` does."""
    @staticmethod
    def from_toml(text: str, base_dir: _Path = ".", set: Optional[Mapping[str, _Value]] = None) -> "Scene":
        """A scene from TOML text; relative paths resolve against ``base_dir``."""
    @staticmethod
    def from_dict(data: Mapping[str, Any], base_dir: _Path = ".", set: Optional[Mapping[str, _Value]] = None) -> "Scene":
        """A scene from a dict with the TOML file's structure (None values left out)."""
    @staticmethod
    def from_arrays(
        K: Any,
        M: Any,
        dofs: Any,
        gaps: Any = None,
        B: Any = None,
        p_brake: Any = None,
        toml: Union[str, Mapping[str, Any], None] = None,
        base_dir: _Path = ".",
        set: Optional[Mapping[str, _Value]] = None,
    ) -> "Scene":
        """A scene over a stored reduced model given as arrays (no files): K, M (n × n), optional
        B and p_brake, the DOF map and gap table as records (lists of dicts or DataFrames)."""
    def set(self, key: str, value: _Value) -> "Scene":
        """A copy with ``key`` (dotted, as ``--set``) set to ``value``, validated again."""
    def set_many(self, values: Mapping[str, _Value]) -> "Scene":
        """A copy with several keys set together, validated once all are set."""
    def to_toml(self) -> str:
        """The scene as TOML, every default filled in."""
    def to_dict(self) -> Dict[str, Any]:
        """The scene as a dict, every default filled in."""
    @property
    def base_dir(self) -> str: ...
    @property
    def model_source(self) -> str:
        """``mesh``, ``op4``, ``punch`` or ``arrays``."""
    @property
    def components(self) -> List[str]: ...
    def __eq__(self, other: object) -> bool: ...

class ModesOut(TypedDict):
    frequencies_hz: np.ndarray
    shapes: np.ndarray
    nodes: np.ndarray
    node_tags: np.ndarray
    cells: List[Tuple[str, np.ndarray]]
    report: ModesReport

class ReduceOut(TypedDict):
    K: np.ndarray
    M: np.ndarray
    B: Optional[np.ndarray]
    p_brake: np.ndarray
    dofs: List[Dict[str, Any]]
    gaps: List[Dict[str, Any]]
    gap_pairs: List[int]
    friction_law: Dict[str, Any]
    components: List[Dict[str, Any]]
    warnings: List[str]
    cache: Optional[CacheUse]

class TransientOut(TypedDict):
    time: np.ndarray
    columns: List[str]
    column_info: List[HistoryColumn]
    history: np.ndarray
    energy: np.ndarray
    energy_columns: List[str]
    summary: TransientSummary
    verdict: Verdict
    success: bool
    warnings: List[str]
    cache: Optional[CacheUse]

class CeaOut(TypedDict):
    eigenvalues: np.ndarray
    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    unstable: np.ndarray
    shapes: np.ndarray
    dofs: List[Dict[str, Any]]
    report: CeaReport
    sweep: Optional[CeaSweep]
    warnings: List[str]
    cache: Optional[CacheUse]

class LimitCycleOut(TypedDict):
    frequencies_hz: np.ndarray
    peak_normal_velocity: np.ndarray
    rms_normal_velocity: np.ndarray
    reached: np.ndarray
    report: LimitCycleReport
    warnings: List[str]

def scene_from_state(text: str, base_dir: _Path, arrays: Optional[Dict[str, Any]]) -> Scene: ...
def modes(scene: Scene, workdir: _Path, component: Optional[str] = None, progress: _Progress = None) -> ModesOut: ...
def reduce(scene: Scene, workdir: _Path, cache: Optional[_Path] = None, progress: _Progress = None) -> ReduceOut: ...
def transient(scene: Scene, workdir: _Path, cache: Optional[_Path] = None, progress: _Progress = None) -> TransientOut: ...
def cea(
    scene: Scene,
    workdir: _Path,
    mu: Optional[Tuple[float, float, int]] = None,
    cache: Optional[_Path] = None,
    progress: _Progress = None,
) -> CeaOut: ...
def limit_cycle(
    scene: Scene,
    workdir: _Path,
    cache: Optional[_Path] = None,
    progress: _Progress = None,
) -> LimitCycleOut: ...
def compare(
    a: str,
    b: str,
    workdir: _Path,
    tol_freq: Optional[float] = None,
    tol_mac: Optional[float] = None,
    tol_matrix: Optional[float] = None,
    tol_root: Optional[float] = None,
    tol_summary: Optional[float] = None,
    modes: Optional[int] = None,
    pair_mac: Optional[float] = None,
    scene: Optional[str] = None,
    cea: bool = True,
    cache: Optional[_Path] = None,
    progress: _Progress = None,
) -> CompareReport: ...
def sweep_value(
    scene: Scene,
    assignments: Sequence[Tuple[str, _Value]],
    label: str,
    index: int,
    analysis: str,
    cache_dir: _Path,
    run_dir: _Path,
    progress: _Progress = None,
    cancel: Optional[Callable[[], bool]] = None,
) -> SweepPoint: ...
def model_key(scene: Scene) -> Optional[str]: ...
def propensity_plan(
    scene: Scene,
    dists: Sequence[Tuple[str, str]],
    corr: Sequence[Tuple[str, str, float]],
    samples: int,
    replicates: Optional[int] = None,
    seed: int = 1,
    rereduce: bool = False,
) -> Dict[str, Any]:
    """The plan (``propensity::Plan``: inputs, correlation, design); a dict that pickles."""
def propensity_evaluate(
    scene: Scene,
    plan: Dict[str, Any],
    rows: Sequence[int],
    workdir: _Path,
    cache_dir: Optional[_Path] = None,
    progress: _Progress = None,
    cancel: Optional[Callable[[], bool]] = None,
) -> PropensityEvaluated: ...
def propensity_finish(
    scene: Scene,
    plan: Dict[str, Any],
    samples: Sequence[Dict[str, Any]],
    out: _Path,
    n_dofs: int = 0,
    n_gaps: int = 0,
    build_s: float = 0.0,
    evaluate_s: float = 0.0,
    wall_s: float = 0.0,
    threads: int = 1,
    basis_checks: Optional[Sequence[BasisCheck]] = None,
) -> PropensityReport: ...
def propensity_check_basis(
    scene: Scene,
    plan: Dict[str, Any],
    workdir: _Path,
    tolerance: float = 0.05,
    cache_dir: Optional[_Path] = None,
) -> List[BasisCheck]: ...
