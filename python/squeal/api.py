"""The compute functions of each verb, with typed results."""

from __future__ import annotations

import os
import tempfile
import warnings
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np

from . import _args, _squeal
from ._squeal import Scene
from .results import (
    CacheUse,
    CeaReport,
    CeaSweep,
    CompareReport,
    HistoryColumn,
    LimitCycleReport,
    ModesReport,
    TransientSummary,
    Verdict,
)

ProgressCallback = Callable[[Dict[str, Any]], None]
PathLike = Union[str, "os.PathLike[str]"]


class _Workdir:
    """The folder gmsh writes its .geo/.msh into: the caller's, or a temporary one."""

    def __init__(self, workdir: Optional[PathLike]) -> None:
        self._tmp = None if workdir is not None else tempfile.TemporaryDirectory(prefix="squeal-")
        self.path = os.fspath(workdir) if workdir is not None else self._tmp.name

    def __enter__(self) -> str:
        return self.path

    def __exit__(self, *exc: object) -> None:
        if self._tmp is not None:
            self._tmp.cleanup()


def _fs(p: Optional[PathLike]) -> Optional[str]:
    return None if p is None else os.fspath(p)


def _warn(ws: List[str]) -> None:
    for w in ws:
        warnings.warn(f"squeal: {w}", stacklevel=3)


@dataclass
class ModesResult:
    """Modal analysis of one component (``squeal modes``)."""

    frequencies_hz: np.ndarray
    """Natural frequencies, Hz (n_modes)."""
    shapes: np.ndarray
    """Mass-normalised mode shapes at the nodes, (n_nodes, 3, n_modes); zeros at fixed DOFs."""
    nodes: np.ndarray
    """Node coordinates (n_nodes, 3)."""
    node_tags: np.ndarray
    """gmsh node tags (n_nodes)."""
    cells: List[Tuple[str, np.ndarray]]
    """Volume cells as meshio takes them: (meshio cell type, connectivity into ``nodes``)."""
    report: ModesReport
    """``modes.json``'s content (statistics of the assembly and the Lanczos solver)."""

    def to_meshio(self) -> Any:
        """A ``meshio.Mesh`` with one point array ``mode_NN`` per mode."""
        import meshio

        data = {f"mode_{j + 1:02d}": self.shapes[:, :, j] for j in range(self.shapes.shape[2])}
        return meshio.Mesh(self.nodes, self.cells, point_data=data)


@dataclass
class ReducedModel:
    """The reduced model (``squeal reduce``): row/column i of the matrices is ``dofs[i]``."""

    K: np.ndarray
    """Reduced stiffness (n × n, symmetric)."""
    M: np.ndarray
    """Reduced mass (n × n, symmetric)."""
    B: Optional[np.ndarray]
    """Element damping Σ (GE/W4) K_c (n × n), None without element damping."""
    p_brake: np.ndarray
    """Unit brake load (n)."""
    dofs: List[Dict[str, Any]]
    """DOF map records: ``component, kind ("grid"|"modal"), grid, comp, index, shared_with``."""
    gaps: List[Dict[str, Any]]
    """Gap records: ``pad_grid, rotor_grid, x, y, z, nx, ny, nz, area, p0, temperature`` and
    the sliding velocity ``vx_slide, vy_slide, vz_slide``; a gap tied to a rotor face
    (``pairing = "surface"`` or ``"mortar"``) also has ``face, xi, eta, face_grids, weights``
    (a mortar tie: ``mortar = True``, the grids of non-zero weight), and a mortar gap on a
    quadratic pad face's mid-side node ``pad_grids, pad_weights`` (its pad side)."""
    gap_pairs: List[int]
    """Gaps of each ``[[contact]]`` pair, in scene order."""
    friction_law: Any
    components: List[Dict[str, Any]]
    warnings: List[str]
    cache: Optional[CacheUse]
    """Cache use (``hit``, ``key``, ``note``) when a cache was given."""

    def to_scene(self, toml: Union[str, Dict[str, Any], None] = None, base_dir: PathLike = ".") -> Scene:
        """A scene over these arrays (``Scene.from_arrays``), no files needed."""
        return Scene.from_arrays(
            self.K, self.M, self.dofs, gaps=self.gaps, B=self.B, p_brake=self.p_brake,
            toml=toml, base_dir=base_dir,
        )


@dataclass
class TransientResult:
    """The nonlinear BSQL transient (``squeal transient``)."""

    time: np.ndarray
    """Times of the recorded rows, s."""
    columns: List[str]
    """Names of the history's columns (``history_map.json``; column 0 is ``t``)."""
    column_info: List[HistoryColumn]
    """What each column is (kind, grid, component, gap, DOF)."""
    history: np.ndarray
    """The recorded rows (every NOUTPT-th step), as ``history.npy``."""
    energy: np.ndarray
    energy_columns: List[str]
    summary: TransientSummary
    """``summary.json``'s body: status, steps, CPU, squeal, growth rate, statistics, …"""
    verdict: Verdict
    """The squeal verdict (state, growth rate, dominant frequency, reasons)."""
    success: bool
    """The integration reached TFINAL (else ``summary["status"]`` says why it stopped)."""
    warnings: List[str]
    cache: Optional[CacheUse]

    def column(self, name: str) -> np.ndarray:
        """One column of the history by name."""
        return self.history[:, self.columns.index(name)]

    def to_dataframe(self) -> Any:
        """The history as a pandas DataFrame (one column per record)."""
        import pandas as pd

        return pd.DataFrame(self.history, columns=self.columns)


@dataclass
class CeaResult:
    """Complex eigenvalues about the steady sliding state (``squeal cea``)."""

    eigenvalues: np.ndarray
    """p = Re p + i ω per mode (complex), modes up to ``cea.max_frequency_hz`` sorted by
    frequency; the motion is Re(u e^{pt})."""
    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    """ζ = −2 Re p/|Im p| (NaN for a real root)."""
    unstable: np.ndarray
    """Boolean per mode."""
    shapes: np.ndarray
    """Complex mode shapes on the reduced DOFs (n × n_modes)."""
    dofs: List[Dict[str, Any]]
    report: CeaReport
    """``cea.json``'s content (state, contact, modes, roots outside the band, statistics)."""
    sweep: Optional[CeaSweep]
    """``cea.sweep.json``'s content with a friction sweep."""
    warnings: List[str]
    cache: Optional[CacheUse]

    @property
    def real_parts(self) -> np.ndarray:
        """Re p per mode, 1/s (> 0: growing)."""
        return self.eigenvalues.real

    @property
    def energy(self) -> Dict[str, Any]:
        """The energy balance of every root (``cea.json``'s ``energy``; docs/insight.md):
        ``roots[i]`` for mode i holds the friction feed-in per gap and per contact pair, the
        damping work per component, the kinetic and strain shares per component (names in
        ``components``, pairs in ``pairs``) per unit mode energy, and the identity's closure."""
        return self.report.get("energy", {})

    @property
    def sensitivity(self) -> Dict[str, Any]:
        """Sensitivities of the roots to the design parameters (``cea.json``'s
        ``sensitivity``; docs/insight.md): ``roots[j]`` (unstable roots first, then the least
        stable ones) has ``mode`` (index into the modes) and ``params`` ranked by
        ``|normalised|`` (scale × ∂Re p/∂θ), each with ``d_real_part``, ``d_frequency_hz``,
        ``delta_to_neutral`` (the first-order change bringing Re p to 0) and ``status``;
        ``parameters`` lists the parameters varied. Empty with ``[cea] sensitivity = false``."""
        return self.report.get("sensitivity") or {}


def modes(
    scene: Scene,
    component: Optional[str] = None,
    *,
    workdir: Optional[PathLike] = None,
    progress: Optional[ProgressCallback] = None,
) -> ModesResult:
    """Modal analysis of one component (``component``: its name; default the scene's only one).

    gmsh's ``.geo``/``.msh`` go into ``workdir`` (default: a temporary folder).
    """
    f = "squeal.modes"
    _args.scene(f, scene)
    _args.text(f, "component", component)
    workdir = _args.path(f, "workdir", workdir)
    _args.callback(f, "progress", progress)
    with _Workdir(workdir) as w:
        d = _squeal.modes(scene, w, component=component, progress=progress)
    return ModesResult(**d)


def reduce(
    scene: Scene,
    *,
    cache: Optional[PathLike] = None,
    workdir: Optional[PathLike] = None,
    progress: Optional[ProgressCallback] = None,
) -> ReducedModel:
    """The reduced model of the scene: mesh → FE → Craig–Bampton → superelement → gaps → loads
    (or the stored model it names). ``cache``: a model-cache folder (as ``--cache``)."""
    f = "squeal.reduce"
    _args.scene(f, scene)
    cache = _args.path(f, "cache", cache)
    workdir = _args.path(f, "workdir", workdir)
    _args.callback(f, "progress", progress)
    with _Workdir(workdir) as w:
        d = _squeal.reduce(scene, w, cache=_fs(cache), progress=progress)
    _warn(d["warnings"])
    return ReducedModel(**d)


def transient(
    scene: Scene,
    *,
    cache: Optional[PathLike] = None,
    workdir: Optional[PathLike] = None,
    progress: Optional[ProgressCallback] = None,
) -> TransientResult:
    """The nonlinear transient of the scene, in memory (no file is written but gmsh's).

    An integration that stops before TFINAL returns with ``success = False`` and the status in
    ``summary``; errors raise.
    """
    f = "squeal.transient"
    _args.scene(f, scene)
    cache = _args.path(f, "cache", cache)
    workdir = _args.path(f, "workdir", workdir)
    _args.callback(f, "progress", progress)
    with _Workdir(workdir) as w:
        d = _squeal.transient(scene, w, cache=_fs(cache), progress=progress)
    _warn(d["warnings"])
    return TransientResult(**d)


def cea(
    scene: Scene,
    mu: Optional[Tuple[float, float, int]] = None,
    *,
    cache: Optional[PathLike] = None,
    workdir: Optional[PathLike] = None,
    progress: Optional[ProgressCallback] = None,
) -> CeaResult:
    """Complex eigenvalue analysis about the steady sliding state (or the restart state the
    scene's ``[cea]`` names). ``mu=(first, last, count)``: also a friction sweep with mode
    tracking, as ``squeal cea --mu first:last:count`` (in ``CeaResult.sweep``)."""
    f = "squeal.cea"
    _args.scene(f, scene)
    mu = _args.mu_range(f, mu)
    cache = _args.path(f, "cache", cache)
    workdir = _args.path(f, "workdir", workdir)
    _args.callback(f, "progress", progress)
    with _Workdir(workdir) as w:
        d = _squeal.cea(scene, w, mu=mu, cache=_fs(cache), progress=progress)
    _warn(d["warnings"])
    return CeaResult(**d)


@dataclass
class LimitCycleResult:
    """Limit cycles of the band-limited model by harmonic balance (``squeal limit-cycle``),
    one per unstable root in the band, most unstable first."""

    frequencies_hz: np.ndarray
    """The cycle's frequency per mode (at the operating point when reached)."""
    peak_normal_velocity: np.ndarray
    """Peak over the gaps and the period of the rotor's normal velocity on the friction face."""
    rms_normal_velocity: np.ndarray
    """Its RMS over the gaps and the period."""
    reached: np.ndarray
    """Boolean per mode: the branch reached the operating point with its harmonics converged."""
    report: LimitCycleReport
    """``limit_cycle.json``'s content (``band_model``: kept/removed roots and the error
    estimate; ``modes``: root, Hopf point, branch, harmonics, Floquet stability)."""
    warnings: List[str]


def limit_cycle(
    scene: Scene,
    *,
    cache: Optional[PathLike] = None,
    workdir: Optional[PathLike] = None,
    progress: Optional[ProgressCallback] = None,
) -> LimitCycleResult:
    """Limit cycles of the scene's band-limited model (``[transient] band_cutoff``) by harmonic
    balance with AFT, continued in μ from each unstable in-band root's Hopf point, as
    ``squeal limit-cycle`` (docs/limit-cycle.md)."""
    f = "squeal.limit_cycle"
    _args.scene(f, scene)
    cache = _args.path(f, "cache", cache)
    workdir = _args.path(f, "workdir", workdir)
    _args.callback(f, "progress", progress)
    with _Workdir(workdir) as w:
        d = _squeal.limit_cycle(scene, w, cache=_fs(cache), progress=progress)
    _warn(d["warnings"])
    return LimitCycleResult(**d)


EXIT_BEYOND_TOLERANCE = 4
"""``squeal compare``'s exit status when a check fails (``CompareResult.exit_code``)."""


@dataclass
class CompareResult:
    """Regression of two reduced models or two run folders (``squeal compare A B``)."""

    passed: bool
    """Every check within its tolerance (a tolerance left ``None`` is reported, not checked)."""
    report: CompareReport
    """``compare.json``'s content: ``matrices`` (‖A−B‖_F/‖A‖_F per matrix), ``modes`` (MAC
    pairing, Δf/f), ``roots`` (CEA roots paired, Δf, ΔRe p), ``summaries`` (run folders),
    ``checks``."""

    @property
    def exit_code(self) -> int:
        """What ``squeal compare`` exits with: 0 passed, 4 beyond a tolerance."""
        return 0 if self.passed else EXIT_BEYOND_TOLERANCE

    def matrices(self) -> Dict[str, float]:
        """Relative Frobenius difference per matrix name (KR, MR, BR, PBRAKE)."""
        return {m["name"]: m["relative"] for m in self.report["matrices"]}


def compare(
    a: PathLike,
    b: PathLike,
    *,
    tol_freq: Optional[float] = None,
    tol_mac: Optional[float] = None,
    tol_matrix: Optional[float] = None,
    tol_root: Optional[float] = None,
    tol_summary: Optional[float] = None,
    modes: Optional[int] = None,
    pair_mac: Optional[float] = None,
    scene: Optional[PathLike] = None,
    cea: bool = True,
    cache: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    progress: Optional[ProgressCallback] = None,
) -> CompareResult:
    """Compares two reduced models (scenes, ``.op4``/``.pch`` with ``dofmap.json`` beside them,
    ``squeal reduce`` folders) or two run folders, as ``squeal compare A B``: undamped
    frequencies paired by MAC, matrix difference norms, CEA roots paired (Δf, ΔRe p),
    ``summary.json`` values side by side. ``out``: also write ``compare.json``/``compare.md``
    there. ``scene``: friction, rotor and loads for the CEA of stored matrices. ``pair_mac``:
    the MAC below which two modes are not paired, in [0, 1] and at most ``tol_mac`` (default:
    0.5, or ``tol_mac`` when that is lower). The tolerances are validated as ``squeal compare``
    validates them (``SceneError`` naming the option)."""
    f = "squeal.compare"
    for name, v in (("a", a), ("b", b)):
        if v is None:
            raise _args.type_error(f, name, "a path (str or os.PathLike)", v)
        _args.path(f, name, v)
    for name, v in (("tol_freq", tol_freq), ("tol_mac", tol_mac), ("tol_matrix", tol_matrix),
                    ("tol_root", tol_root), ("tol_summary", tol_summary), ("pair_mac", pair_mac)):
        _args.real(f, name, v)
    modes = _args.integer(f, "modes", modes, 0)
    _args.path(f, "scene", scene)
    _args.boolean(f, "cea", cea)
    _args.path(f, "cache", cache)
    out = _args.path(f, "out", out)
    _args.callback(f, "progress", progress)
    with _Workdir(out) as w:
        d = _squeal.compare(
            _fs(a),
            _fs(b),
            w,
            tol_freq=tol_freq,
            tol_mac=tol_mac,
            tol_matrix=tol_matrix,
            tol_root=tol_root,
            tol_summary=tol_summary,
            modes=modes,
            pair_mac=pair_mac,
            scene=_fs(scene),
            cea=cea,
            cache=_fs(cache),
            progress=progress,
        )
    return CompareResult(passed=bool(d["passed"]), report=d)
