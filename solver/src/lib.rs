//! squeal-solver: DAE integrator (BDF) and complex eigenvalue analysis. Takes matrices and callbacks only.
//!
//! - [`bdf`]: a DASSL/IDA-style variable-step, variable-order BDF integrator for implicit
//!   systems F(t, y, y') = 0 in residual form, with consistent initial conditions and
//!   a serialisable state for restarts.
//! - [`bsql`]: the BSQL brake-squeal system, paper eqs. (8)–(18), as a [`bdf::DaeSystem`],
//!   with the steady sliding state and energy bookkeeping.
//! - [`cea`]: complex eigenvalue analysis, paper eqs. (19)–(24).
//! - [`condense`]: the band-limited model (in-band contact-linearised roots plus the static
//!   correction) and its transient.
//! - [`hb`]: limit cycles of the band-limited model by harmonic balance (AFT, continuation from
//!   the Hopf point, Floquet stability).

pub mod bdf;
pub mod bsql;
pub mod cea;
pub mod condense;
pub mod error;
pub mod galpha;
pub mod hb;
pub mod insight;
pub mod interrupt;
mod linalg;

pub use error::SolverError;
pub use interrupt::Interrupt;

/// The workspace's real scalar (defined once, in `squeal-meshes`, the crate graph's root).
pub use squeal_meshes::Real;
