//! Fuzzing on stable Rust with proptest (issue 14): structure-aware mutations of real files
//! ([`mutate`]) driven by [`runner::fuzz`] — no panic, no hang, every error naming its input.
//! The targets are in `tests/tests/fuzz.rs`; the README's "Fuzzing" section has the commands.

pub mod api;
pub mod mutate;
pub mod runner;

pub use mutate::{inputs, Input, Mutation};
pub use runner::{fuzz, Outcome, Report};
