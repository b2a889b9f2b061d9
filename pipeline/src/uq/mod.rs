//! Uncertainty quantification for the squeal propensity study: input distributions with a
//! Gaussian copula, a randomised quasi-Monte Carlo (scrambled Sobol) design in Saltelli's
//! form, and the estimators (probabilities with intervals, quantiles, Sobol indices).
//!
//! Pure: it knows nothing of scenes or models; the propensity stage evaluates the design's
//! rows (a CEA each) and hands the outcomes back.

pub mod design;
pub mod dist;
pub mod estimate;

pub use design::{Design, DesignRow, RowKind};
pub use dist::{Copula, Distribution};
pub use estimate::{
    band_of, probability, quantile, sobol_indices, third_octave_bands, Band, Outcome, Probability,
    SobolIndices,
};

#[cfg(test)]
mod tests;
