//! The problem layer, below the verbs: the BSQL system a reduced model and a scene's
//! operating point ([`operating`]) make ([`system`]), where a run starts ([`start`]), the scene's `[transient]` table as solver
//! options ([`options`]), the restart file ([`restart`]), the linearisation about a state
//! ([`tangents`]) and its roots ([`linear`]), and the band-limited model ([`band`],
//! [`recover`]).
//!
//! `modes`, `cea` and `transient` sit above it; none of them imports another verb
//! (`pipeline/tests/layers.rs`).

pub mod band;
pub mod linear;
pub mod operating;
pub mod options;
pub mod recover;
pub mod restart;
pub mod start;
pub mod system;
pub mod tangents;

pub use operating::OperatingPoint;
pub use system::Problem;
