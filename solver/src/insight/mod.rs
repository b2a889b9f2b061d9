//! What to change: the energy balance of each complex mode, and the derivatives of its root
//! with respect to the parameters of the model.
//!
//! - [`eigen_triplet`]: right and left eigenvectors of one root of the constrained quadratic
//!   problem (one complex LU of the bordered matrix of [`crate::cea`]).
//! - [`mode_energy`]: the power each gap's friction feeds into the mode, the power each
//!   component's damping takes out, the kinetic and strain energy per component, and the
//!   closure of `2σ E = net power`.
//! - [`eigenvalue_derivative`]: `∂p/∂θ` from the left and right eigenvectors and the
//!   derivatives of the matrices ([`MatrixDerivative`]).
//!
//! Takes matrices only; the pipeline splits its model into [`EnergyParts`] and builds the
//! matrix derivatives of each design parameter.

mod energy;
mod sensitivity;
mod triplet;

pub use energy::{mode_energy, ComponentPart, EnergyParts, GapPart, ModeEnergy};
pub use sensitivity::{eigenvalue_derivative, MatrixDerivative, Sensitivity};
pub use triplet::{eigen_triplet, Triplet, TripletSolver};
