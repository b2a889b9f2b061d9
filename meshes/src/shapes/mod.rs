//! Shape functions of the tetrahedra, wedges, pyramids and triangles (hexahedra: see
//! [`crate::jacobian`] here and `squeal_fe::element::shape`). They live in this crate so that
//! the mesh readers' det J checks and the elements share one implementation; `squeal-fe`
//! re-exports them.

pub mod pyramid;
pub mod simplex;
pub mod wedge;
