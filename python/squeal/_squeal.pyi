"""Type stubs of the extension module ``squeal._squeal`` (built from ``python/src``)."""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

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

def scene_from_state(text: str, base_dir: _Path, arrays: Optional[Dict[str, Any]]) -> Scene: ...
def modes(scene: Scene, workdir: _Path, component: Optional[str] = None, progress: _Progress = None) -> Dict[str, Any]: ...
def reduce(scene: Scene, workdir: _Path, cache: Optional[_Path] = None, progress: _Progress = None) -> Dict[str, Any]: ...
def transient(scene: Scene, workdir: _Path, cache: Optional[_Path] = None, progress: _Progress = None) -> Dict[str, Any]: ...
def cea(
    scene: Scene,
    workdir: _Path,
    mu: Optional[Tuple[float, float, int]] = None,
    cache: Optional[_Path] = None,
    progress: _Progress = None,
) -> Dict[str, Any]: ...
def limit_cycle(
    scene: Scene,
    workdir: _Path,
    cache: Optional[_Path] = None,
    progress: _Progress = None,
) -> Dict[str, Any]: ...
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
) -> Dict[str, Any]: ...
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
) -> str: ...
def model_key(scene: Scene) -> Optional[str]: ...
def propensity_plan(
    scene: Scene,
    dists: Sequence[Tuple[str, str]],
    corr: Sequence[Tuple[str, str, float]],
    samples: int,
    replicates: Optional[int] = None,
    seed: int = 1,
    rereduce: bool = False,
) -> str: ...
def propensity_evaluate(
    scene: Scene,
    plan: str,
    rows: Sequence[int],
    workdir: _Path,
    cache_dir: Optional[_Path] = None,
    progress: _Progress = None,
    cancel: Optional[Callable[[], bool]] = None,
) -> str: ...
def propensity_finish(
    scene: Scene,
    plan: str,
    samples: str,
    out: _Path,
    n_dofs: int = 0,
    n_gaps: int = 0,
    build_s: float = 0.0,
    evaluate_s: float = 0.0,
    wall_s: float = 0.0,
    threads: int = 1,
) -> str: ...
