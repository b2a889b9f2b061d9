//! One module per verb; each takes a typed scene and a run folder.

pub mod mesh;
pub mod modes;
