//! squeal-meshes: parametric gmsh geometry, the gmsh CLI, `.msh` reading, VTU writing.
//!
//! - [`geo`]: `.geo` templates (rotor / annular plate, block) written from Rust;
//! - [`gmsh`]: runs the gmsh program on a `.geo` text;
//! - [`msh`]: reads `.msh` 2.2 / 4.1 files into a [`Mesh`];
//! - [`vtu`]: writes a [`Mesh`] and point/cell arrays as a VTK `.vtu` file.
pub mod collapse;
mod error;
mod face_set;
pub mod geo;
pub mod geo_file;
pub mod gmsh;
pub mod interrupt;
pub mod jacobian;
pub mod mesh;
pub mod msh;
mod query;
pub mod shapes;
pub mod split;
pub mod structured;
pub mod topology;
pub mod vtu;

pub use error::MeshError;
pub use gmsh::{mesh_geo, mesh_geo_file, GmshOptions, GmshRun};
pub use interrupt::Interrupt;
pub use mesh::{CellBlock, CellKind, Face, FaceSet, Mesh, Real};
pub use msh::{parse_msh, read_msh};
pub use query::hex_centroid_jacobian;
pub use topology::LocalFace;
pub use vtu::{write_vtu, CellArray, PointArray};
