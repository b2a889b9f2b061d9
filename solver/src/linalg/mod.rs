//! Dense linear-algebra kernels shared by the integrators.

pub(crate) mod lu;
