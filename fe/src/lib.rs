//! squeal-fe: solid elements, materials, sparse assembly, loads, modal solve.
//!
//! - [`element`]: hex8 with incompatible modes (default), plain hex8, hex20;
//! - [`assemble`]: parallel sparse assembly of K and consistent M over the free DOFs of a
//!   [`DofMap`];
//! - [`pressure_load`], [`nodal_force`], [`face_areas`]: load vectors and contact areas;
//! - [`modal::solve_modes`]: shift-invert block Lanczos;
//! - [`ordering::nested_dissection`]: fill-reducing ordering for the modal factorisation.

pub mod assembly;
pub mod cholesky;
pub mod dofs;
pub mod elasticity;
pub mod element;
pub mod error;
pub mod loads;
pub mod material;
pub mod modal;
pub mod ordering;

pub use assembly::{assemble, Assembled, AssemblyOptions, AssemblyStats, Hex8Formulation};
pub use dofs::DofMap;
pub use elasticity::{Elasticity, MaterialAxes, Orthotropic, SolidMaterial, TransverselyIsotropic};
pub use element::kinds::element_matrices;
pub use error::FeError;
pub use loads::{face_areas, nodal_force, pressure_load};
pub use material::Material;
pub use modal::{
    shifted, solve_modes, solve_modes_with, FactorKind, ModalOptions, ModalStats, ModalStatus,
    Modes,
};
pub use ordering::{dof_coordinates, nested_dissection, FillOrdering, NestedDissectionOptions};
pub use squeal_meshes::{Interrupt, Mesh, Real};
