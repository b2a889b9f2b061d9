//! Linear-algebra kernels shared by the integrators: dense LU on preallocated storage, and
//! sparse products with the constant matrices of a time step.

pub(crate) mod lu;
pub(crate) mod sparse;
