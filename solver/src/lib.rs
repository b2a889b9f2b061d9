//! squeal-solver: DAE integrator (BDF) and complex eigenvalue analysis. Takes matrices and callbacks only.
