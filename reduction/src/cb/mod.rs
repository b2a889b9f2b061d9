//! Craig–Bampton reduction of one component: constraint modes, fixed-interface modes,
//! reduced matrices, data recovery and checks (rigid-body mass, frequencies).

mod check;
mod eigen;
mod model;
mod options;
mod partition;
mod reduce;
mod rigid;

pub use check::{check, CbCheck, CheckOptions, FrequencyRow, RigidCheck};
pub use eigen::dense_generalized_eigen;
pub use model::{peak_rss_kib, CbModel, CbStats, EigenMethod, PhaseMemory};
pub use options::CbOptions;
pub use partition::Sparse;
pub use reduce::{reduce, reduce_damped};
pub use rigid::{dof_points, rigid_body_mass, DofPoint, RigidBodyMass};
