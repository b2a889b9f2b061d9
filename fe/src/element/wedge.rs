//! Re-export of [`squeal_meshes::shapes::wedge`] (one implementation for the elements and the
//! mesh readers' det J checks).
pub use squeal_meshes::shapes::wedge::*;
