//! One module per verb; each takes a typed scene and a run folder.

pub mod accuracy;
pub mod cea;
pub mod compare;
pub mod limit_cycle;
pub mod mesh;
pub mod model;
pub mod modes;
pub mod plotit;
pub mod propensity;
pub mod reduce;
pub mod reproduce;
pub mod sweep;
pub mod transient;
