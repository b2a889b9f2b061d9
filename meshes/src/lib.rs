//! squeal-meshes: parametric gmsh geometry, the gmsh CLI, `.msh` reading, VTU writing.
//!
//! - [`geo`]: `.geo` templates (rotor / annular plate, block) written from Rust;
//! - [`gmsh`]: runs the gmsh program on a `.geo` text;
//! - [`msh`]: reads `.msh` 2.2 / 4.1 files into a [`Mesh`];
//! - [`bdf`], [`inp`]: read Nastran bulk data and Abaqus input into a [`Mesh`] (with the
//!   file's materials, material axes and constraints), listing what they do not read;
//! - [`vtu`]: writes a [`Mesh`] and point/cell arrays as a VTK `.vtu` file.
pub mod bdf;
pub mod collapse;
mod deck;
mod error;
mod face_set;
pub mod geo;
pub mod geo_file;
pub mod gmsh;
mod import;
pub mod inp;
pub mod interrupt;
pub mod jacobian;
pub mod mesh;
pub mod msh;
mod query;
pub mod section;
pub mod shapes;
pub mod split;
pub mod structured;
pub mod topology;
pub mod vtu;

pub use bdf::{parse_bdf, read_bdf, BdfOptions};
pub use error::MeshError;
pub use gmsh::{mesh_geo, mesh_geo_file, GmshOptions, GmshRun};
pub use import::{ReadReport, Unsupported};
pub use inp::{parse_inp, read_inp, InpOptions};
pub use interrupt::Interrupt;
pub use mesh::{CellBlock, CellKind, Face, FaceSet, Mesh, Real};
pub use msh::{parse_msh, read_msh};
pub use query::hex_centroid_jacobian;
pub use section::{AxesKind, Elastic, MaterialAxes, MaterialData, Section};
pub use topology::LocalFace;
pub use vtu::{write_vtu, CellArray, PointArray};
