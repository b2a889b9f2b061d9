//! Growth rates and frequencies of the response's roots: a multi-channel matrix pencil.
//!
//! The response after the load ramp of a linearly (un)stable brake is a sum of damped
//! exponentials, x_c(t) = Σ_k a_{c,k} e^{(σ_k + iω_k) t} on every output DOF c. A single envelope
//! cannot separate two roots close in frequency (a self-excited root and its stable partner, or
//! two growing roots): their beating biases it. The matrix pencil (Hua & Sarkar 1990) fits
//! every root at once:
//!
//! 1. resample each channel on a uniform grid t_n = t_0 + nΔt (cubic Hermite from the
//!    integrator's accepted steps, with the derivative y' it also returns: the BDF's steps are
//!    not uniform);
//! 2. stack the Hankel matrices Y_c[i, j] = x_c[i + j] (j = 0..L) of every channel on top of
//!    each other and take the thin SVD Y = U Σ Vᵀ;
//! 3. the model order M: the last gap of at least `gap_ratio` between consecutive singular
//!    values above `sv_floor`·s₁ (the signal/noise split), else every singular value above
//!    the floor, at most `max_order`;
//! 4. with V₁, V₂ the first and last L rows of V's first M columns, the roots are the
//!    eigenvalues z_k of V₁⁺V₂, and s_k = ln(z_k)/Δt = σ_k + iω_k;
//! 5. the amplitudes a_{c,k}: least squares on the Vandermonde matrix [z_k^n] per channel;
//! 6. consistency (a stabilisation check, as in operational modal analysis): the fit is
//!    repeated on the later parts of the window, [t0 + kT/6, t1] for k = 1, 2. A physical root
//!    is found again in each refit, within `refit_frequency_tol` in frequency or a quarter of
//!    the refit window's resolution 1/T_r, whichever is larger (close roots pull each other by
//!    a fraction of 1/T_r, more in the shorter refits: the study brake's coupled 2043 Hz root
//!    moves by 34 Hz = 0.12/T_r between the fit and a refit, next to its partner); a root the
//!    fit made out of the misfit (the response part that is not a sum of the fitted
//!    exponentials: a modulated or non-stationary response) moves or vanishes. Each root
//!    reports the range of σ over the fits. Only a root found in every refit may decide the
//!    verdict, and a clear growth needs it to grow in every fit
//!    ([`super::Verdict::is_squeal`]). The range is the fit's sensitivity to the
//!    window, not a confidence interval: the refits' shorter windows resolve close roots
//!    less well.
//!
//! # Reference
//! Y. Hua and T. K. Sarkar, "Matrix pencil method for estimating parameters of exponentially
//! damped/undamped sinusoids in noise", IEEE Trans. ASSP 38(5), 814–824, 1990 (the SVD-based
//! "total least squares" pencil); the multi-channel form stacks the channels' Hankel blocks,
//! which share the right singular subspace (the roots are common, the amplitudes are not).

pub mod options;
pub mod pairing;
pub mod pencil;
pub mod resample;

pub use options::PencilOptions;
pub use pairing::{pair_with_cea, RootPair};
pub use pencil::{estimate, mark_consistency, matrix_pencil, model_order, PencilFit, Root};
pub use resample::{resample_hermite, sample_spacing};

#[cfg(test)]
mod tests;
