//! squeal-meshes: parametric gmsh geometry, the gmsh CLI, `.msh` reading, VTU writing.
pub mod mesh;
pub use mesh::{CellBlock, CellKind, Mesh, Real};
