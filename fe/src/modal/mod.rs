//! Modal analysis: lowest eigenpairs of K φ = ω² M φ by shift-invert block Lanczos.
//!
//! The operator (K − σM)⁻¹M with σ < 0 is self-adjoint in the M-inner product; its largest
//! eigenvalues θ = 1/(ω² − σ) are the lowest ω². K − σM is positive definite for σ < 0 even
//! for free-free models, so it is factorised once by sparse Cholesky (symbolic once, numeric
//! once; LDLᵀ on the same symbolic structure, then LU, as fall-backs reported in the stats).
//! The fill-reducing ordering is AMD or, given DOF coordinates ([`solve_modes_with`]),
//! geometric nested dissection ([`crate::ordering`]); block solves are sequential, products
//! with M and the tall-skinny orthogonalisation products are parallel over rows.

mod dense;
mod factor;
mod lanczos;
mod options;
mod solve;
mod spmm;
mod tall;

pub use factor::shifted;
pub use options::{FactorKind, ModalOptions, ModalStats, ModalStatus, Modes};
pub use solve::{solve_modes, solve_modes_with};
