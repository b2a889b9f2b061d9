//! Sparse Cholesky factorisations built on faer's supernodal LLᵀ.
//!
//! [`SplitCholesky`] factorises an SPD matrix split at the top separator S of a nested
//! dissection into two subdomains D₁, D₂: the bordered matrices [A_kk, A_kS; A_Sk, A_SS] are
//! factorised in parallel (one rayon task each, faer's sequential supernodal kernels), the
//! separator's Schur complement is assembled from their trailing blocks and factorised densely,
//! and every solve runs the two subdomains' substitutions in parallel. Same factor entries
//! (to round-off) as one factorisation in the nested-dissection order, with both cores busy in
//! the factorisation and in each block solve, and half of the factor read per core.

mod bordered;
mod split;

pub use bordered::BorderedCholesky;
pub use split::{SplitCholesky, SplitStats};
