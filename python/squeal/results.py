"""The dicts the compute functions return, as ``TypedDict``\\ s: one per Rust result struct
(``python/src`` converts the struct itself, field for field, so a key here is the Rust field's
name and ``python/tests/test_result_types.py`` fails when one is renamed).

Conventions of the conversion (``python/src/values.rs``), the same as the CLI's JSON files:
``Option<T>`` is ``Optional[T]`` (None), a field skipped when empty is an optional key, a
tuple or fixed array is a list, an enum with a tag (``status``, ``kind``, ``state``, ``reason``,
``effect``) is a dict with the tag key and the variant's fields (optional keys here), and a
float that is not finite (NaN, ±inf: e.g. a bound of an empty set) is None. Nested results
not typed field by field are ``Dict[str, Any]``; their files' documentation lists them.
"""

from typing import Any, Dict, List, Optional, TypedDict, Union

class CacheUse(TypedDict):
    """How the reduced model came through the model cache: ``hit``, ``key`` and ``note`` of
    ``model::CacheUse``."""

    hit: bool
    key: str
    note: Optional[str]


# ---- the transient (`squeal transient`'s summary.json, squeal_pipeline::stages::transient)


class _TransientStatusBase(TypedDict):
    status: str
    """``reached``, ``step_size_too_small``, ``error_test_failures``, ``convergence_failures``,
    ``max_steps``, ``interrupted`` or ``step_collapse``."""
    t: float


class TransientStatus(_TransientStatusBase, total=False):
    """How the integration ended (``squeal_solver::bdf::Status``): the variant's fields."""

    h: float
    order: int
    residual_norm: Optional[float]
    error_norm: float
    steps: int
    h_collapse: float


class VerdictRoot(TypedDict):
    """A root of the response (``verdict::roots::Root``)."""

    growth_rate_per_s: float
    frequency_hz: float
    amplitude: float
    amplitude_end: float
    significant: bool
    consistent: bool
    growth_rate_range_per_s: List[float]


class PencilFit(TypedDict):
    """The matrix-pencil fit of the response (``verdict::roots::PencilFit``)."""

    roots: List[VerdictRoot]
    window: List[float]
    channels: int
    samples: int
    dt: float
    pencil: int
    order: int
    singular_values: List[float]
    relative_residual: float


class Envelope(TypedDict):
    """The envelope estimate (``verdict::envelope::Envelope``)."""

    growth_rate_per_s: Optional[float]
    dominant_frequency_hz: Optional[float]
    growth_factor: Optional[float]
    n_peaks: int
    window: List[float]
    h_max_window: Optional[float]


class Resolution(TypedDict):
    """How well the steps resolve a frequency (``verdict::guard::Resolution``)."""

    source: str
    frequency_hz: float
    samples_per_period: float
    h_times_f: float
    numerical_decay_per_s: float
    resolved: bool


class _UnresolvedBase(TypedDict):
    reason: str
    """``steps_too_coarse``, ``window_too_short``, ``contact_tensile``, ``stopped``,
    ``no_response``, ``poor_fit`` or ``limit_cycle_without_growth``."""


class Unresolved(_UnresolvedBase, total=False):
    """Why a verdict is ``unresolved`` (``verdict::guard::Unresolved``): the variant's fields."""

    source: str
    frequency_hz: float
    samples_per_period: float
    h_times_f: float
    numerical_decay_per_s: float
    resolved: bool
    window_s: float
    detectable_growth_per_s: float
    min_growth_rate_per_s: float
    t: float
    gap: int
    pressure: float
    h: Optional[float]
    status: TransientStatus
    relative_residual: float
    max_relative_residual: float
    peak_normal_velocity: float
    amplitude_growth: Optional[float]
    min_growth_factor: float


class _VerdictBase(TypedDict):
    growth_rate_per_s: Optional[float]
    dominant_frequency_hz: Optional[float]
    growth_factor: Optional[float]
    growth_rate_min_per_s: Optional[float]
    roots: List[VerdictRoot]
    estimator: Optional[PencilFit]
    envelope: Envelope
    window: List[float]
    state: str
    """``squeal``, ``no_squeal`` or ``unresolved`` (with ``reasons``)."""
    resolution: List[Resolution]
    detectable_growth_per_s: Optional[float]
    h_max_window: Optional[float]
    valid_until: Optional[float]
    saturation: Optional[Dict[str, Any]]
    evidence: Optional[Dict[str, Any]]


class Verdict(_VerdictBase, total=False):
    """The squeal verdict (``verdict::Verdict``)."""

    reasons: List[Unresolved]
    ramp_saturation: Dict[str, Any]
    """A growth held by the contact's opening before the load ramp ended (evidence
    ``growth_during_ramp``): ``first_opening``, ``cycles``, ``envelope_trend_per_s``,
    ``max_peak``, ``last_peak``, ``cycles_with_open_gaps``."""


class GapEvent(TypedDict):
    t: float
    gap: int
    pressure: float


class ContactValidity(TypedDict):
    """What the contact did (``verdict::validity::ContactValidity``)."""

    n_gaps: int
    tensile_at_start: int
    tensile_gap_steps: int
    first_separation: Optional[GapEvent]
    judged_from: float
    first_tensile_after_ramp: Optional[GapEvent]
    min_pressure: Optional[GapEvent]
    steps: int


class BdfStats(TypedDict):
    """BDF counters (``squeal_solver::bdf::BdfStats``)."""

    steps: int
    newton_iterations: int
    residual_evals: int
    jacobian_setups: int
    error_test_failures: int
    convergence_failures: int
    order_histogram: List[int]
    last_h: float
    last_order: int
    cpu_s: float
    setups_cj_ratio: int
    setups_forced: int
    setups_stale_retry: int
    setups_branch: int
    convergence_failures_rate: int
    convergence_failures_max_iters: int


class BsqlStats(TypedDict):
    """BSQL counters (``squeal_solver::bsql::BsqlStats``)."""

    residual_evals: int
    tangent_evals: int
    factorisations: int
    constraint_drift: float
    max_constraint_drift: float
    near_stick_factorisations: int
    friction_damping_after_failure: int
    eliminated_dofs: int
    modal_redetections: int
    component_blocks: int
    block_fallbacks: int


class EnergyBalance(TypedDict):
    """The energy balance (``squeal_solver::bsql::EnergyBalance``)."""

    t0: float
    t: float
    initial_energy: float
    kinetic: float
    strain: float
    damping_dissipated: float
    friction_work: float
    external_work: float
    constraint_work: float
    impact_dissipated: float
    quadrature_error: float
    records: int


class StepBound(TypedDict):
    h_max: Optional[float]
    scene_h_max: Optional[float]
    band_hz: Optional[float]
    band_h_max: Optional[float]
    band_samples_per_period: float


class SteadySummary(TypedDict):
    iterations: int
    residual_norm: float


class IcStats(TypedDict):
    iterations: int
    residual_evals: int
    jacobian_setups: int
    residual_norm: float
    cj: float


class StepsByOrder(TypedDict):
    counts: List[int]
    t0: float
    t1: float


class VerdictCea(TypedDict):
    """The CEA the verdict ran at the steady state (``transient::VerdictCeaResult``)."""

    unstable_in_band: List[List[float]]
    """(frequency Hz, Re p 1/s) per root."""
    unstable_outside_band: int
    error: Optional[str]


class RootPair(TypedDict):
    """A response root beside the nearest CEA root (``verdict::roots::RootPair``)."""

    transient_growth_rate_per_s: float
    transient_frequency_hz: float
    transient_amplitude_end: float
    transient_growth_rate_range_per_s: List[float]
    transient_consistent: bool
    cea_real_part: float
    cea_frequency_hz: float
    rel_diff_growth: float
    rel_diff_frequency: float


class InputWarning(TypedDict):
    """An input accepted with a measured value to know about (``squeal_pipeline::Warning``)."""

    input: str
    message: str
    value: float
    tolerance: float


class _EffectBase(TypedDict):
    effect: str


class Effect(_EffectBase, total=False):
    """An effect the run computed (``transient::effects::Effect``): the variant's fields."""

    gaps: int
    law: Dict[str, Any]
    t_load: float
    integrator: str
    max_order: Optional[int]
    rho_inf: Optional[float]
    fixed_step: Optional[float]
    noutpt: int


class _TransientSummaryBase(TypedDict):
    status: TransientStatus
    steps: int
    cpu_s: float
    bookkeeping_s: float
    squeal: bool
    growth_rate_per_s: Optional[float]
    dominant_frequency_hz: Optional[float]
    response: str
    verdict: Verdict
    constraint_drift: float
    max_constraint_drift: float
    integrator: str
    bdf_stats: BdfStats
    bsql_stats: BsqlStats
    steady_state: Optional[SteadySummary]
    initial_conditions: Optional[IcStats]
    energy: EnergyBalance
    energy_residual: float
    t_start: float
    t_end: float
    n_dofs: int
    n_gaps: int
    history_rows: int
    active_effects: List[Effect]
    ignored: List[Dict[str, Any]]
    model_hash: str
    restarted_from: Optional[str]
    step_bound: StepBound
    steps_by_order_after_ramp: Optional[StepsByOrder]
    contact: ContactValidity
    verdict_cea: Optional[VerdictCea]
    transient_vs_cea: Optional[List[RootPair]]
    warnings: List[InputWarning]


class TransientSummary(_TransientSummaryBase, total=False):
    """``summary.json``'s body without ``verb``, ``version``, ``wall_s``
    (``transient::TransientResult``); the keys below only when they apply."""

    galpha_stats: Dict[str, Any]
    band_limited: Dict[str, Any]
    separation: Dict[str, Any]
    limit_cycle: Dict[str, Any]


class _HistoryColumnBase(TypedDict):
    column: int
    name: str
    kind: str


class HistoryColumn(_HistoryColumnBase, total=False):
    """A column of the history (``history::Column``, ``history_map.json``)."""

    grid: int
    component: str
    gap: int
    dof: int


# ---- the complex eigenvalue analysis (`squeal cea`'s cea.json, stages::cea)


class CeaMode(TypedDict):
    """A root in the band (``cea::ModeOut``)."""

    index: int
    frequency_hz: float
    real_part: float
    damping_ratio: Optional[float]
    unstable: bool


class CeaRoot(TypedDict):
    frequency_hz: float
    real_part: float
    damping_ratio: Optional[float]


class CeaOutsideBand(TypedDict):
    """Roots above the validity band (``cea::OutsideBand``)."""

    band_hz: Optional[float]
    count: int
    n_unstable: int
    computed_up_to_hz: Optional[float]
    max_frequency_hz: Optional[float]
    max_unstable_frequency_hz: Optional[float]
    unstable: List[CeaRoot]


class CeaStats(TypedDict):
    """``squeal_solver::cea::CeaStats``."""

    n: int
    n_constraints: int
    n_reduced: int
    method: str
    n_basis: int
    basis_max_frequency_hz: Optional[float]
    n_modes: int
    n_real_roots: int
    n_unstable: int
    max_real_part: float
    spectral_radius: float
    constraint_rank_ratio: float
    time_reduce_s: float
    time_basis_s: float
    time_eigen_s: float
    refine: Optional[Dict[str, Any]]


class _CeaStateSourceBase(TypedDict):
    kind: str
    """``steady_state`` or ``restart``."""
    t: float


class CeaStateSource(_CeaStateSourceBase, total=False):
    """Where the linearisation's state came from (``cea::tangents::StateSource``)."""

    load_factor: float
    newton_iterations: int
    residual_norm: float
    path: str


class PairContact(TypedDict):
    """The contact at the state of one ``[[contact]]`` pair's gaps
    (``problem::tangents::PairContact``)."""

    n_gaps: int
    n_tensile: int
    min_pressure: float
    max_pressure: float
    normal_force: float


class _CeaContactBase(TypedDict):
    n_gaps: int
    max_pressure: float
    min_pressure: float
    total_normal_force: float
    max_slip_speed: float
    min_slip_speed: float
    mu_min: float
    mu_max: float
    n_tensile: int


class CeaContact(_CeaContactBase, total=False):
    """The contact at the state (``problem::tangents::ContactSummary``; the bounds are None
    without gaps), and per pair in the scene's order (absent when the gaps are not grouped by
    pair, e.g. a gap table)."""

    per_pair: List[PairContact]


class CeaSteadyState(TypedDict):
    source: CeaStateSource
    contact: CeaContact
    max_abs_displacement: float
    max_abs_velocity: float


class InterfaceDegreeRow(TypedDict):
    """One degree an interface reduction tried (``model::degree::DegreeRow``)."""

    degree: int
    n_coords: int
    difference: Optional[float]
    root_change: Optional[float]
    growth_change: Optional[float]
    estimate: Optional[float]
    n_in_band: int
    n_unstable: int
    constraint_solves: int


class InterfaceReduction(TypedDict):
    """An interface-reduced component's degree and error estimate (``cea::InterfaceOut``)."""

    component: str
    degree: int
    n_coords: int
    n_interface_dofs: int
    tolerance: Optional[float]
    estimate: Optional[float]
    growth_scale: Optional[float]
    exact: bool
    history: List[InterfaceDegreeRow]
    note: str


class CeaReport(TypedDict):
    """``cea.json`` (``cea::CeaOut``)."""

    verb: str
    version: str
    friction_law: Dict[str, Any]
    friction_damping: bool
    max_frequency_hz: Optional[float]
    steady_state: CeaSteadyState
    modes: List[CeaMode]
    unstable: List[int]
    outside_band: CeaOutsideBand
    stats: CeaStats
    energy: Dict[str, Any]
    sensitivity: Optional[Dict[str, Any]]
    interface_reduction: List[InterfaceReduction]


class CeaCoupling(TypedDict):
    """A mode pair coupling at a critical μ (``cea::sweep::CouplingOut``)."""

    track: int
    mu_critical: float
    frequency_hz: float
    partner: Optional[int]
    pair_frequencies_before_hz: List[Optional[float]]
    pair_frequencies_after_hz: List[Optional[float]]


class CeaSweep(TypedDict):
    """``cea.sweep.json`` (``cea::sweep::SweepReport``)."""

    vary: str
    base_law: Dict[str, Any]
    mu: List[float]
    max_frequency_hz: Optional[float]
    couplings: List[CeaCoupling]
    lowest_critical_mu: Optional[float]
    band_hz: Optional[float]
    lowest_critical_mu_in_band: Optional[float]
    lowest_critical_mu_in_band_status: Optional[str]
    tracks: List[Dict[str, Any]]
    events: List[Dict[str, Any]]
    events_above_band: int
    stats: Dict[str, Any]
    steady_states: Optional[Dict[str, Any]]


# ---- modes (`squeal modes`'s modes.json, stages::modes)


class FeAssemblyStats(TypedDict):
    """``squeal_fe::assembly::AssemblyStats``."""

    n_elements: int
    n_free: int
    nnz_k: int
    nnz_m: int
    pattern_s: float
    elements_s: float
    build_s: float
    total_s: float


class _MeshReportBase(TypedDict):
    component: str
    n_nodes: int
    n_cells: int
    msh_path: str
    gmsh_s: Optional[float]


class MeshReport(_MeshReportBase, total=False):
    """``stages::mesh::MeshReport`` (``reader``: a Nastran/Abaqus file's reader report)."""

    reader: Dict[str, Any]


class ModesReport(TypedDict):
    """``modes.json`` (``stages::modes::ModesReport``)."""

    component: str
    n_nodes: int
    n_dofs: int
    frequencies_hz: List[float]
    status: Union[str, Dict[str, Dict[str, int]]]
    """``"converged"``, or ``{"max_iterations": {"converged": n}}``."""
    modal_stats: Dict[str, Any]
    assembly_stats: FeAssemblyStats
    mesh: MeshReport
    total_s: float


# ---- limit cycles (`squeal limit-cycle`'s limit_cycle.json, stages::limit_cycle)


class LimitCycleMode(TypedDict):
    """The cycle of one unstable root (``limit_cycle::ModeCycle``)."""

    root_frequency_hz: float
    root_real_part: float
    reached: bool
    frequency_hz: float
    peak_normal_velocity: float
    rms_normal_velocity: float
    stable: Optional[bool]
    detail: Dict[str, Any]


class LimitCycleReport(TypedDict):
    """``limit_cycle.json`` without ``verb``, ``version``, ``wall_s``
    (``limit_cycle::LimitCycleComputed``)."""

    band_model: Dict[str, Any]
    modes: List[LimitCycleMode]
    options: Dict[str, Any]
    time_band_s: float
    time_cycles_s: float


# ---- propensity (`squeal propensity`'s propensity.json, stages::propensity)


class _ComponentInputBase(TypedDict):
    component: str
    property: str
    """``young_scale``, ``density_scale`` or ``loss_factor``."""
    base: float


class ComponentInput(_ComponentInputBase, total=False):
    """A component property varied on the one reduced model (``propensity::ComponentInput``;
    ``volume`` for one volume's material)."""

    volume: str


class _PropensityInputBase(TypedDict):
    key: str
    text: str
    distribution: Dict[str, Any]
    mean: float
    reuses_model: bool


class PropensityInput(_PropensityInputBase, total=False):
    """An uncertain input (``propensity::Input``; ``component`` for a component property)."""

    component: ComponentInput


class FrequencyBand(TypedDict):
    center_hz: float
    lower_hz: float
    upper_hz: float


class BasisCheck(TypedDict):
    """One input's error of a basis the rows hold fixed (``propensity::BasisCheck``):
    ``craig_bampton`` (a volume's material against re-reduction) or ``projection`` (the CEA's
    projection basis of the design's centre against the row's own)."""

    kind: str
    key: str
    value: float
    derivative: List[float]
    """Largest Re λ (1/s) and its frequency (Hz) as the rows run."""
    rereduced: List[float]
    """The same afresh (re-reduced, or with the row's own projection basis)."""
    real_part_change: float
    frequency_change: float
    allowed: float
    passed: bool


class _PropensityModelBase(TypedDict):
    model: str
    n_dofs: int
    n_gaps: int
    band_hz: Optional[float]
    bands: List[FrequencyBand]


class ProjectionBasis(TypedDict):
    """``propensity::ProjectionBasis``: the CEA's projection basis every row reuses."""

    n_modes: int
    max_frequency_hz: float
    time_s: float


class PropensityModel(_PropensityModelBase, total=False):
    """``propensity::EvalInfo`` (``basis_checks`` when a basis held fixed was checked,
    ``projection_basis`` when the rows share one)."""

    basis_checks: List[BasisCheck]
    projection_basis: ProjectionBasis


class Probability(TypedDict):
    """``uq::Probability``: the estimate, its 95 % interval, the replicates' estimates."""

    p: float
    interval: List[float]
    replicates: List[float]


class BandProbability(TypedDict):
    center_hz: float
    lower_hz: float
    upper_hz: float
    p: float
    interval: List[float]


class MaxRealPart(TypedDict):
    mean: float
    quantiles: List[List[float]]
    min: float
    max: float
    histogram_edges: List[float]
    histogram_counts: List[int]


class SobolIndices(TypedDict):
    """``propensity::SobolOut``."""

    keys: List[str]
    first_order: List[float]
    first_order_interval: List[List[float]]
    total: List[float]
    total_interval: List[List[float]]
    variance: float


class _PropensityStatsBase(TypedDict):
    evaluations: int
    failed: int
    build_s: float
    evaluate_s: float
    wall_s: float
    threads: int


class PropensityPhases(TypedDict):
    """``propensity::evaluate::Phases``: seconds summed over the rows."""

    rows: int
    state_s: float
    eigen_s: float
    refine_s: float


class PropensityStats(_PropensityStatsBase, total=False):
    """``propensity::report::PropensityStats`` (``phases`` from the CLI's run)."""

    phases: PropensityPhases


class PropensityReport(TypedDict):
    """``propensity.json`` (``propensity::PropensityOut``)."""

    verb: str
    version: str
    inputs: List[PropensityInput]
    correlation: Optional[List[List[float]]]
    method: str
    n_base: int
    replicates: int
    seed: int
    budget: int
    model: PropensityModel
    p_unstable: Probability
    interval_note: str
    bands: List[BandProbability]
    max_real_part: Optional[MaxRealPart]
    sobol_max_real_part: Optional[SobolIndices]
    sobol_unstable: Optional[SobolIndices]
    sobol_note: str
    errors: List[str]
    stats: PropensityStats
    files: List[str]


class PropensityEvaluated(TypedDict):
    """What ``_squeal.propensity_evaluate`` returns for a chunk of design rows."""

    samples: List[Dict[str, Any]]
    build_s: float
    n_dofs: int
    n_gaps: int
    evaluate_s: float


# ---- one design-sweep value (a `sweep.json` point, stages::sweep)


class _VerdictStateBase(TypedDict):
    state: str


class VerdictState(_VerdictStateBase, total=False):
    """``squeal``, ``no_squeal``, or ``unresolved`` with its ``reasons``."""

    reasons: List[Unresolved]


class _SweepCeaBase(TypedDict):
    max_frequency_hz: Optional[float]
    n_unstable: int
    max_real_part: Optional[float]
    max_real_part_frequency_hz: Optional[float]
    min_damping_ratio: Optional[float]
    unstable_modes: List[CeaMode]


class SweepCea(_SweepCeaBase, total=False):
    """A value's CEA indicators (``sweep::CeaIndicators``)."""

    lowest_critical_mu: float


class SweepTransient(TypedDict):
    """A value's transient indicators (``sweep::TransientIndicators``)."""

    status: TransientStatus
    squeal: bool
    verdict: VerdictState
    growth_rate_per_s: Optional[float]
    dominant_frequency_hz: Optional[float]
    steps: int
    cpu_s: float
    t_end: float


class _SweepPointBase(TypedDict):
    index: int
    value: Any
    label: str
    run_dir: str
    cache_hit: Optional[bool]
    cache_key: Optional[str]
    build_s: float
    analysis_s: float
    cea: Optional[SweepCea]
    transient: Optional[SweepTransient]
    error: Optional[str]
    failed: bool
    """An error, or a transient stopped before TFINAL (``SweepPoint::failed``)."""


class SweepPoint(_SweepPointBase, total=False):
    """What ``_squeal.sweep_value`` returns: a ``sweep.json`` point (``sweep::SweepPoint``)."""

    cache_note: str
    warnings: List[InputWarning]


# ---- compare (`squeal compare`'s compare.json, stages::compare)


class _CompareInputBase(TypedDict):
    kind: str
    """``scene``, ``stored`` or ``run``."""


class CompareInput(_CompareInputBase, total=False):
    path: str
    matrices: str
    dofmap: str
    gaps: Optional[str]


class MatrixDiff(TypedDict):
    name: str
    norm_a: float
    norm_b: float
    norm_difference: float
    relative: float
    max_abs_difference: float
    at: Optional[List[int]]


class ModePair(TypedDict):
    mode_a: int
    frequency_a_hz: float
    mode_b: Optional[int]
    frequency_b_hz: Optional[float]
    relative_frequency_difference: Optional[float]
    mac: float


class CompareRootPair(TypedDict):
    frequency_a_hz: float
    real_part_a: float
    frequency_b_hz: Optional[float]
    real_part_b: Optional[float]
    relative_frequency_difference: Optional[float]
    real_part_difference: Optional[float]
    relative_real_part_difference: Optional[float]


class SummaryRow(TypedDict):
    key: str
    a: Any
    b: Any
    relative: Optional[float]
    timing: bool


class CompareCheck(TypedDict):
    tolerance_name: str
    tolerance: float
    worst: Optional[float]
    """None when infinite (an unpaired root or a non-numeric summary difference)."""
    at: str
    passed: bool


class CompareReport(TypedDict):
    """``compare.json`` (``compare::CompareReport``)."""

    verb: str
    version: str
    a: CompareInput
    b: CompareInput
    n_dofs: Optional[List[int]]
    matrices: List[MatrixDiff]
    modes: List[ModePair]
    unpaired_modes_b: List[int]
    roots: Optional[List[CompareRootPair]]
    cea_note: Optional[str]
    summaries: List[SummaryRow]
    checks: List[CompareCheck]
    passed: bool
