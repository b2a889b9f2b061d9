//! The BSQL brake-squeal system, paper eqs. (8)–(18), as a [`DaeSystem`].
//!
//! Unknowns y = {v, λ, u} (lengths n, ng, n): velocities, contact *impulses* and
//! displacements, so that λ' is the contact force of [Paper eq. (12)] (see DESIGN.md: with
//! this reading ∂F/∂y' is nonsingular when G has full row rank and the iteration matrix is
//! exactly eq. (18)). Constant matrices M, B, K (n × n) and G (ng × n) are given dense (reduced
//! models); the products of every Newton iteration and every step's energy terms use their
//! non-zero entries only (compressed rows built once in [`BsqlSystem::new`]: M, B, K on their
//! union pattern, K alone, G and Gᵀ), the iteration matrix is assembled from the dense copies.
//! When M, B, K have a diagonal block that no constraint touches (a Craig–Bampton model's
//! modal coordinates, found by pattern in [`BsqlSystem::new`]), it is eliminated before the
//! LU: the factorisation and its solves are of the kept DOFs and the multipliers only
//! ([`jacobian`], `linalg::diag_block`). When the components (pads, rotor) are coupled only by
//! the constraint rows, each component's block is factorised apart and the multipliers through
//! their Schur complement (`blocks`, `linalg::bordered`).
//! Friction enters through the [`FrictionForces`] callback.
//!
//! - [`residual`]: F(t, y, y'), eq. (16), and the load history P(t).
//! - [`jacobian`]: the iteration matrix, eq. (18), with the u-row eliminated.
//! - [`steady`]: the static sliding equilibrium.
//! - [`energy`]: energy bookkeeping per accepted step.
//! - [`unilateral`]: separation and re-contact of constraints (events, plastic impact).
//! - [`compliance`]: optional normal contact compliance (a penalty spring per row).
//! - [`smooth`]: a smooth unilateral law for compliant rows (separation with no event).

mod blocks;
pub mod compliance;
pub mod energy;
pub mod jacobian;

pub mod residual;
pub mod smooth;
pub mod steady;
pub mod unilateral;

use faer::Mat;
use serde::{Deserialize, Serialize};

pub use compliance::compliant_cea;
pub use energy::{EnergyBalance, EnergyRestart, PowerTerms};
pub use residual::LoadHistory;
pub use steady::{steady_state, steady_state_of, Statics, SteadyOptions, SteadyState};
pub use unilateral::{
    EventRestart, Unilateral, UnilateralOptions, UnilateralState, UnilateralStats,
};

use crate::bdf::{DaeSystem, TolerancePartition, Tolerances};
use crate::linalg::bordered::BorderedBlocks;
use crate::linalg::diag_block::DiagBlock;
use crate::linalg::lu::DenseLu;
use crate::linalg::sparse::RunRows;
use crate::linalg::symmetric::Products;
use crate::{Real, SolverError};

/// Friction forces F_f(λ', v) of [Paper eq. (8)] and their tangents, supplied by the caller
/// (the contact crate's gap elements, eqs. (1)–(7), or a test model).
pub trait FrictionForces {
    /// Add the friction forces F_f(λ', v) (length n) to `f`.
    fn add_forces(
        &mut self,
        t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError>;
    /// ∂F_f/∂λ' (n × ng) and, if `d_dv` is Some, ∂F_f/∂v (n × n), added into dense matrices.
    fn add_tangents(
        &mut self,
        t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError>;
    /// True when some contact is near sticking (its slip speed within a few regularisation
    /// speeds of zero): the iteration matrix then needs the friction damping C_f = ∂F_f/∂v,
    /// whose entries grow like μN/VTOL there (default: never).
    fn near_stick(&mut self, _t: Real, _v: &[Real], _lambda_dot: &[Real]) -> bool {
        false
    }
}

/// No friction (F_f = 0): a linear constrained structure.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoFriction;

impl FrictionForces for NoFriction {
    fn add_forces(
        &mut self,
        _: Real,
        _: &[Real],
        _: &[Real],
        _: &mut [Real],
    ) -> Result<(), SolverError> {
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _: Real,
        _: &[Real],
        _: &[Real],
        _: &mut Mat<Real>,
        _: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        Ok(())
    }
}

/// Options of the BSQL system.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BsqlOptions {
    /// Include the friction damping C_f = ∂F_f/∂v in the transient iteration matrix
    /// (default: false, as the paper: "included only for the complex eigenvalue solution";
    /// Newton then converges linearly in the v-dependence of friction).
    pub include_friction_damping: bool,
    /// Include C_f automatically in the factorisations at which the friction model reports
    /// a contact near sticking ([`FrictionForces::near_stick`]), and in every factorisation
    /// after the first Newton convergence failure with a fresh matrix without it (default:
    /// true). Off, a stick–slip run takes many Newton failures at each stick (the
    /// v-dependence of friction is then steep and left out of Newton's matrix), and so does a
    /// growing squeal vibration (the tangential vibration velocity turns the sliding direction,
    /// ∂F_f/∂v ~ μN/|V_t|): 2 049 failures and 6 731 set-ups for 5 562 steps on the study
    /// brake at RTOL1 1e-4 (README, "Cost of a transient step").
    pub friction_damping_near_stick: bool,
}

#[allow(clippy::derivable_impls)] // Default impl is where defaults are documented.
impl Default for BsqlOptions {
    fn default() -> Self {
        Self {
            include_friction_damping: false,
            friction_damping_near_stick: true,
        }
    }
}

impl BsqlOptions {
    /// Nothing to check yet; kept for the Options/validate convention.
    pub fn validate(&self) -> Result<(), SolverError> {
        Ok(())
    }
}

/// Counters and monitors of the BSQL system (written to `summary.json`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct BsqlStats {
    /// Residual evaluations.
    pub residual_evals: u64,
    /// Friction tangent evaluations (one per factorisation).
    pub tangent_evals: u64,
    /// Factorisations of the (n + ng) saddle system.
    pub factorisations: u64,
    /// Constraint drift ‖G v‖∞ over the closed rigid rows at the last observed step (an open
    /// row's G v is its separation speed, a compliant row's its spring's rate: neither counts).
    pub constraint_drift: Real,
    /// Largest ‖G v‖∞ over observed steps.
    pub max_constraint_drift: Real,
    /// Factorisations that included C_f because a contact was near sticking.
    pub near_stick_factorisations: u64,
    /// Factorisations that included C_f because Newton had failed with a fresh matrix
    /// without it (see [`BsqlOptions::friction_damping_near_stick`]).
    #[serde(default)]
    pub friction_damping_after_failure: u64,
    /// DOFs of the diagonal (modal) block eliminated before the LU (0: the whole system is
    /// factorised).
    #[serde(default)]
    pub eliminated_dofs: u64,
    /// Times the block was found again because the friction tangents touched an eliminated
    /// DOF (those DOFs are kept from then on).
    #[serde(default)]
    pub modal_redetections: u64,
    /// Component blocks the saddle matrix is factorised by (0: one LU of the whole; see
    /// [`BsqlSystem::set_component_blocks`]).
    #[serde(default)]
    pub component_blocks: u64,
    /// Factorisations of the whole matrix because it did not fit the component blocks (a
    /// friction damping C_f coupling pad and rotor) or a block was singular.
    #[serde(default)]
    pub block_fallbacks: u64,
}

/// What the last factorisation holds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Factored {
    None,
    /// J of eq. (18) at this cj, with the scaling s of the multiplier block.
    Iteration {
        cj: Real,
        s: Real,
    },
    /// ∂F/∂y' alone (initial conditions), scaling s.
    Derivative {
        s: Real,
    },
}

/// The BSQL system with its workspace (allocated once in [`BsqlSystem::new`]).
#[allow(non_snake_case)]
pub struct BsqlSystem<F: FrictionForces> {
    pub(crate) M: Mat<Real>,
    pub(crate) B: Mat<Real>,
    pub(crate) K: Mat<Real>,
    pub(crate) G: Mat<Real>,
    pub(crate) load: LoadHistory,
    pub(crate) friction: F,
    pub(crate) opts: BsqlOptions,
    pub(crate) n: usize,
    pub(crate) ng: usize,
    /// Largest |G_ij| (for scaling the multiplier block).
    pub(crate) g_scale: Real,
    pub(crate) stats: BsqlStats,
    // Workspace.
    pub(crate) f_n: Vec<Real>,
    pub(crate) d_dlam: Mat<Real>,
    pub(crate) d_dv: Mat<Real>,
    pub(crate) rhs: Vec<Real>,
    /// The factorised saddle matrix: (n + ng) square, or (kept + ng) with the diagonal block
    /// eliminated.
    pub(crate) lu: DenseLu,
    /// The eliminated diagonal block (None: the whole system is factorised).
    pub(crate) modal: Option<DiagBlock>,
    /// The saddle matrix's component blocks (None: one LU of the whole).
    pub(crate) blocks: Option<BorderedBlocks>,
    /// The last factorisation is the blocks' (else `lu`'s).
    pub(crate) blocks_factored: bool,
    /// Component blocks allowed ([`BsqlSystem::set_component_blocks`]).
    component_blocks: bool,
    /// The structure is used at all (the last [`BsqlSystem::set_modal_elimination`]).
    structured: bool,
    /// Right-hand side of the reduced saddle system (kept + ng; empty without `modal`).
    pub(crate) red_rhs: Vec<Real>,
    /// DOFs never eliminated: those the friction tangents were seen to touch.
    pub(crate) touched: Vec<bool>,
    /// C_f goes into every iteration matrix: Newton failed with a fresh matrix without it.
    pub(crate) cf_after_failure: bool,
    /// (t, cj) of the last iteration-matrix set-up, its y and y' in `last_y`, `last_yp`.
    last_setup: Option<(Real, Real)>,
    last_y: Vec<Real>,
    last_yp: Vec<Real>,
    /// M, B, K on their union pattern (the residual's M v' + B v + K u, the energy forms), by
    /// the upper triangle when the three are symmetric.
    pub(crate) mbk: Products,
    /// K alone (the Newton solve's K r_u / cj).
    pub(crate) k_rows: Products,
    /// G and Gᵀ in compressed rows.
    pub(crate) g_rows: RunRows,
    pub(crate) gt_rows: RunRows,
    /// G v (length ng).
    pub(crate) gv: Vec<Real>,
    factored: Factored,
    /// Open (separated) constraints: their row is λ' = `lambda_dot_open` instead of G v' = 0.
    pub(crate) open: Vec<bool>,
    /// The contact force an open constraint carries (its preload's share; see
    /// [`unilateral`]).
    pub(crate) lambda_dot_open: Vec<Real>,
    /// Compliance c_k = 1/(k_n A_k) per row (empty: all rows rigid); see [`compliance`].
    pub(crate) compliance: Vec<Real>,
    /// Width ε_k of the smooth unilateral law per row (empty: none); see [`smooth`].
    pub(crate) smooth_width: Vec<Real>,
    /// S_k' at the last iteration-matrix set-up (empty without the smooth law).
    pub(crate) smooth_slope: Vec<Real>,
}

#[allow(non_snake_case)]
impl<F: FrictionForces> BsqlSystem<F> {
    /// Build the system from M, B, K (n × n), G (ng × n), the loads and the friction model.
    pub fn new(
        M: Mat<Real>,
        B: Mat<Real>,
        K: Mat<Real>,
        G: Mat<Real>,
        load: LoadHistory,
        friction: F,
        opts: BsqlOptions,
    ) -> Result<Self, SolverError> {
        opts.validate()?;
        let (n, ng, g_scale) = check_matrices(&M, &B, &K, &G, &load)?;
        let d_dv = if opts.include_friction_damping || opts.friction_damping_near_stick {
            Mat::zeros(n, n)
        } else {
            Mat::zeros(0, 0)
        };
        let mbk = Products::new(&[&M, &B, &K], "M, B, K union pattern")?;
        let k_rows = Products::new(&[&K], "K")?;
        let g_rows = RunRows::from_dense(&[&G], "G")?;
        let gt_rows = RunRows::transpose_of_dense(&G, "G")?;
        let mut sys = Self {
            M,
            B,
            K,
            G,
            load,
            friction,
            opts,
            n,
            ng,
            g_scale: if g_scale > 0.0 { g_scale } else { 1.0 },
            stats: BsqlStats::default(),
            f_n: vec![0.0; n],
            d_dlam: Mat::zeros(n, ng),
            d_dv,
            rhs: vec![0.0; n + ng],
            lu: DenseLu::new(0),
            modal: None,
            blocks: None,
            blocks_factored: false,
            component_blocks: true,
            structured: true,
            red_rhs: Vec::new(),
            touched: vec![false; n],
            cf_after_failure: false,
            last_setup: None,
            last_y: vec![0.0; 2 * n + ng],
            last_yp: vec![0.0; 2 * n + ng],
            mbk,
            k_rows,
            g_rows,
            gt_rows,
            gv: vec![0.0; ng],
            factored: Factored::None,
            open: vec![false; ng],
            lambda_dot_open: vec![0.0; ng],
            compliance: Vec::new(),
            smooth_width: Vec::new(),
            smooth_slope: Vec::new(),
        };
        sys.set_modal_elimination(true);
        Ok(sys)
    }

    /// Eliminate the diagonal block of M, B, K before the LU when there is one (default: on,
    /// set by [`BsqlSystem::new`]); off, the whole (n + ng) saddle system is factorised. The
    /// two differ by round-off only. A DOF is eliminated when no constraint row and no
    /// friction tangent seen so far touches it,
    /// M_ii > 0, B_ii ≥ 0, K_ii ≥ 0 (so cj M_ii + B_ii + K_ii/cj > 0 for every cj > 0), and
    /// no other eliminated DOF couples with it in M, B or K; at least n/10 (and 2) such DOFs
    /// are needed (fewer would not pay for the Schur complement's bookkeeping).
    ///
    /// On, the component blocks ([`BsqlSystem::set_component_blocks`]) are used as well when
    /// allowed; a DOF that bridges two components (a caliper mode coupling the pads) is then
    /// not eliminated.
    pub fn set_modal_elimination(&mut self, on: bool) {
        let (n, ng) = (self.n, self.ng);
        self.factored = Factored::None;
        self.structured = on;
        let with_blocks = on && self.component_blocks;
        let bridging = if with_blocks {
            blocks::bridging_dofs(&self.M, &self.B, &self.K, &self.G)
        } else {
            vec![false; n]
        };
        self.modal = if on {
            let (M, B, K, G) = (&self.M, &self.B, &self.K, &self.G);
            let touched = &self.touched;
            let allowed = |i: usize| {
                !touched[i]
                    && !bridging[i]
                    && (0..ng).all(|k| G[(k, i)] == 0.0)
                    && M[(i, i)] > 0.0
                    && B[(i, i)] >= 0.0
                    && K[(i, i)] >= 0.0
                    && M[(i, i)].is_finite()
                    && B[(i, i)].is_finite()
                    && K[(i, i)].is_finite()
            };
            DiagBlock::detect(&[M, B, K], allowed, n.div_ceil(10).max(2))
        } else {
            None
        };
        let nv = self.modal.as_ref().map_or(n, |b| b.kept.len());
        self.stats.eliminated_dofs = (n - nv) as u64;
        self.blocks = if with_blocks {
            blocks::partition(
                &self.M,
                &self.B,
                &self.K,
                &self.G,
                self.modal.as_ref(),
                &bridging,
            )
        } else {
            None
        };
        self.blocks_factored = false;
        self.stats.component_blocks = self.blocks.as_ref().map_or(0, |b| b.sizes().0.len()) as u64;
        if self.lu.a.nrows() != nv + ng {
            self.lu = DenseLu::new(nv + ng);
        }
        self.red_rhs = if self.modal.is_some() {
            vec![0.0; nv + ng]
        } else {
            Vec::new()
        };
    }

    /// Factorise the saddle matrix by component blocks when the structure has them (default:
    /// on; see `blocks`): each block's LU apart (in parallel), then the Schur complement on
    /// the multipliers and bridging DOFs. Off, or when the matrix of a set-up couples two
    /// blocks (C_f between pad and rotor), one LU of the whole (kept + ng) matrix. The two
    /// differ by round-off only. Takes effect with the structure of the last
    /// [`BsqlSystem::set_modal_elimination`] (none when that was off).
    pub fn set_component_blocks(&mut self, on: bool) {
        self.component_blocks = on;
        self.set_modal_elimination(self.structured);
    }

    /// Sizes of the component blocks and of their border (multipliers and bridging DOFs);
    /// None when the saddle matrix is factorised whole.
    pub fn component_block_sizes(&self) -> Option<(Vec<usize>, usize)> {
        self.blocks.as_ref().map(BorderedBlocks::sizes)
    }

    /// Factorise the assembled saddle matrix (`lu.a`): by blocks when it fits them, else whole.
    /// A block (or the border's Schur complement) that is singular where the whole matrix
    /// may not be (a block with a zero pivot that the multipliers' rows would fix) also falls
    /// back to the whole LU, which then decides.
    fn factor_saddle(&mut self, what: &'static str, t: Real) -> Result<(), SolverError> {
        self.blocks_factored = false;
        if let Some(b) = &mut self.blocks {
            match b.factor(&self.lu.a, what, t) {
                Ok(true) => {
                    self.blocks_factored = true;
                    return Ok(());
                }
                Ok(false)
                | Err(SolverError::SingularMatrix { .. } | SolverError::NonFinite { .. }) => {}
                Err(e) => return Err(e),
            }
            self.stats.block_fallbacks += 1;
        }
        self.lu.factor(what, t)
    }

    /// Number of DOFs eliminated before the LU (the diagonal block), the number of coupling
    /// patterns (groups) they fall in, and the multiply–adds of one Schur-complement update
    /// (all 0 without elimination).
    pub fn modal_elimination(&self) -> (usize, usize, usize) {
        self.modal
            .as_ref()
            .map_or((0, 0, 0), |b| (b.d.len(), b.n_groups(), b.schur_flops()))
    }

    /// Number of structural DOFs n.
    pub fn n_dof(&self) -> usize {
        self.n
    }

    /// Number of constraints ng.
    pub fn n_constraints(&self) -> usize {
        self.ng
    }

    /// Non-zero entries of the sparse products: (M, B, K union pattern, K, G).
    pub fn product_nnz(&self) -> (usize, usize, usize) {
        (self.mbk.nnz(), self.k_rows.nnz(), self.g_rows.nnz())
    }

    /// Whether the products with M, B, K use their upper triangles (all three symmetric to
    /// round-off; `linalg::symmetric`), and the same for K alone.
    pub fn symmetric_products(&self) -> (bool, bool) {
        (self.mbk.is_symmetric(), self.k_rows.is_symmetric())
    }

    /// Counters and the constraint-drift monitor.
    pub fn stats(&self) -> &BsqlStats {
        &self.stats
    }

    /// Sets the counters and the drift monitor (a restarted run continues those of the run it
    /// resumes).
    ///
    /// A run that had switched C_f on after a Newton failure
    /// (`friction_damping_after_failure` > 0) continues with it: the last iteration matrix is
    /// formed again with C_f at its point before the counters are set.
    pub fn restore_stats(&mut self, stats: BsqlStats) {
        if stats.friction_damping_after_failure > 0 && !self.cf_after_failure {
            self.cf_after_failure = true;
            if let (Some((t, cj)), Factored::Iteration { .. }) = (self.last_setup, self.factored) {
                let (y, yp) = (self.last_y.clone(), self.last_yp.clone());
                // The matrix the run had is the one it formed there; a failure now is the
                // restart's to report (at the next step's set-up).
                if self.setup_jacobian(t, &y, &yp, cj).is_err() {
                    self.factored = Factored::None;
                }
            }
        }
        let (eliminated, blocks) = (self.stats.eliminated_dofs, self.stats.component_blocks);
        self.stats = stats;
        // This system's structure, not the file's.
        self.stats.eliminated_dofs = eliminated;
        self.stats.component_blocks = blocks;
    }

    /// The friction model.
    pub fn friction_mut(&mut self) -> &mut F {
        &mut self.friction
    }

    /// The load history.
    pub fn load(&self) -> &LoadHistory {
        &self.load
    }

    /// BSQL's tolerance partitions: (RTOL1, ATOL1) on v and u, (RTOL2, ATOL2) on λ
    /// (ATOL2 = 1e20 excludes the multipliers, as the paper ran).
    pub fn tolerances(&self, rtol1: Real, atol1: Real, rtol2: Real, atol2: Real) -> Tolerances {
        let p = |len, rtol, atol| TolerancePartition { len, rtol, atol };
        Tolerances::Partitions {
            parts: vec![
                p(self.n, rtol1, atol1),
                p(self.ng, rtol2, atol2),
                p(self.n, rtol1, atol1),
            ],
        }
    }

    /// Split y (or y') into its partitions (v, λ, u).
    pub fn split<'a>(&self, y: &'a [Real]) -> (&'a [Real], &'a [Real], &'a [Real]) {
        let (v, rest) = y.split_at(self.n);
        let (l, u) = rest.split_at(self.ng);
        (v, l, u)
    }

    /// Assemble y = {v, λ, u}.
    pub fn join(&self, v: &[Real], lambda: &[Real], u: &[Real]) -> Vec<Real> {
        let mut y = Vec::with_capacity(2 * self.n + self.ng);
        y.extend_from_slice(v);
        y.extend_from_slice(lambda);
        y.extend_from_slice(u);
        y
    }
}

impl<F: FrictionForces> DaeSystem for BsqlSystem<F> {
    fn len(&self) -> usize {
        2 * self.n + self.ng
    }
    fn residual(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        res: &mut [Real],
    ) -> Result<(), SolverError> {
        self.eval_residual(t, y, yp, res)
    }
    fn setup_jacobian(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
        cj: Real,
    ) -> Result<(), SolverError> {
        self.factored = Factored::None;
        self.last_setup = Some((t, cj));
        self.last_y.copy_from_slice(y);
        self.last_yp.copy_from_slice(yp);
        let s = self.assemble_iteration_matrix(t, y, yp, Some(cj))?;
        self.factor_saddle("BSQL iteration (eq. 18)", t)?;
        self.stats.factorisations += 1;
        self.factored = Factored::Iteration { cj, s };
        Ok(())
    }
    fn newton_failed_with_fresh_matrix(&mut self) {
        if self.opts.friction_damping_near_stick && !self.opts.include_friction_damping {
            self.cf_after_failure = true;
        }
    }
    fn solve_jacobian(&mut self, b: &mut [Real]) -> Result<(), SolverError> {
        match self.factored {
            Factored::Iteration { cj, s } => self.solve_iteration(b, Some(cj), s),
            Factored::Derivative { s } => self.solve_iteration(b, None, s),
            Factored::None => Err(SolverError::Callback {
                t: Real::NAN,
                message: "BSQL solve requested before a successful factorisation".into(),
            }),
        }
    }
    fn setup_derivative_jacobian(
        &mut self,
        t: Real,
        y: &[Real],
        yp: &[Real],
    ) -> Result<bool, SolverError> {
        self.factored = Factored::None;
        let s = self.assemble_iteration_matrix(t, y, yp, None)?;
        self.factor_saddle("BSQL ∂F/∂y'", t)?;
        self.stats.factorisations += 1;
        self.factored = Factored::Derivative { s };
        Ok(true)
    }
}

/// Checks the shapes of M, B, K (n × n), G (ng × n) and the loads (length n); returns
/// (n, ng, max |G_ij|), the scale the saddle systems use to balance their blocks.
#[allow(non_snake_case)]
pub(crate) fn check_matrices(
    M: &Mat<Real>,
    B: &Mat<Real>,
    K: &Mat<Real>,
    G: &Mat<Real>,
    load: &LoadHistory,
) -> Result<(usize, usize, Real), SolverError> {
    let n = M.nrows();
    for (what, m) in [("M", M), ("B", B)] {
        if m.nrows() != n || m.ncols() != n {
            return Err(SolverError::DimensionMismatch {
                what,
                expected: n,
                got: if m.nrows() != n { m.nrows() } else { m.ncols() },
            });
        }
    }
    check_statics(n, K, G, load)
}

/// The checks of [`check_matrices`] on K (n × n), G (n columns) and the loads alone (what the
/// steady state reads): (n, ng, the largest |G_ij|).
#[allow(non_snake_case)]
pub(crate) fn check_statics(
    n: usize,
    K: &Mat<Real>,
    G: &Mat<Real>,
    load: &LoadHistory,
) -> Result<(usize, usize, Real), SolverError> {
    if K.nrows() != n || K.ncols() != n {
        return Err(SolverError::DimensionMismatch {
            what: "K",
            expected: n,
            got: if K.nrows() != n { K.nrows() } else { K.ncols() },
        });
    }
    if G.ncols() != n {
        return Err(SolverError::DimensionMismatch {
            what: "G (columns)",
            expected: n,
            got: G.ncols(),
        });
    }
    load.validate(n)?;
    let ng = G.nrows();
    let mut g_scale: Real = 0.0;
    for j in 0..n {
        for i in 0..ng {
            g_scale = g_scale.max(G[(i, j)].abs());
        }
    }
    Ok((n, ng, g_scale))
}
