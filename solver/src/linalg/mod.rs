//! Linear-algebra kernels shared by the integrators: dense LU on preallocated storage, the
//! elimination of a diagonal block (Craig–Bampton modal coordinates) before it, the
//! factorisation of a bordered block-diagonal matrix block by block (components coupled by
//! contact rows), and sparse
//! products with the constant matrices of a time step (by their upper triangles when they are
//! symmetric).

pub(crate) mod bordered;
pub(crate) mod diag_block;
pub(crate) mod lu;
pub(crate) mod sparse;
pub(crate) mod symmetric;
