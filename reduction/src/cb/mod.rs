//! Craig–Bampton reduction of one component: constraint modes, fixed-interface modes,
//! reduced matrices, data recovery and checks (rigid-body mass, frequencies).
//!
//! - [`reduce`] / [`reduce_damped`]: (K, M[, B]) sparse over the free DOFs + boundary free-DOF
//!   indices → [`CbModel`] with dense reduced matrices ordered [boundary DOFs, modal coordinates].
//!   One sparse Cholesky of K_ii serves both the constraint modes Ψ = −K_ii⁻¹K_ib (solved in
//!   parallel column blocks) and, above [`CbOptions::dense_max`] interior DOFs, the shift-invert
//!   block Lanczos for the fixed-interface modes (σ = 0: K_ii is positive definite whenever the
//!   boundary restrains the rigid-body motions).
//! - [`reduce_interface`]: the same with part of the boundary moving in an interface basis
//!   u_f = L p ([`InterfaceBasis`], e.g. [`polynomial_basis`] of a contact patch): constraint
//!   modes and products scale with the interface coordinates instead of the boundary DOFs.
//! - [`InterfaceLadder`]: the same at increasing polynomial degrees on one K_ii factor and one
//!   set of fixed-interface modes, solving only the new columns' constraint modes per degree.
//! - [`CbModel::recover`]: full free-DOF vector from a reduced one.
//! - [`check`]: pyyeti-`cbcheck`-like report ([`CbCheck`], Serialize + Display).

mod check;
mod eigen;
mod factor;
mod interface;
mod ladder;
mod model;
mod multilevel;
mod options;
mod partition;
mod reduce;
mod rigid;
mod verify;

pub use check::{check, CbCheck, CheckOptions, FrequencyRow, FullMethod, RigidCheck};
pub use eigen::dense_generalized_eigen;
pub use factor::KiiOrdering;
pub use interface::{
    polynomial_basis, polynomial_basis_graded, BasisColumn, InterfaceBasis, InterfaceDof,
};
pub use ladder::InterfaceLadder;
pub use model::{peak_rss_kib, CbModel, CbStats, EigenMethod, PhaseMemory};
pub use multilevel::{MultilevelStats, SeparatorStats, SubstructureOptions, SubstructureStats};
pub use options::CbOptions;
pub use partition::Sparse;
pub use reduce::{reduce, reduce_damped, reduce_interface, reduce_ordered};
pub use rigid::{dof_points, rigid_body_mass, DofPoint, RigidBodyMass};
pub use verify::Verification;
