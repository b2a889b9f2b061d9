//! Gap forces and tangents, paper eqs. (1)–(7), and the constraint matrix G, eqs. (9)/(11).
//!
//! Per gap (pad node p, rotor node r, unit normal n, area A = |S_p|):
//!
//! ```text
//! p_n  = −λ̇/A + P_0                       (1)  compressive normal force F_z = −λ̇, see below
//! Δv   = v_r − v_p + v_slide              (2)
//! V_t  = Δv − (Δv·n) n                    (3)
//! F_t  = μ(p_n, |V_t|, T) · A · p_n        (4)
//! F_t ← F_t · r(|V_t|)                    (5)  regularisation, see [`regularisation`]
//! f_p += F_t V_t/|V_t|,  f_r −= F_t V_t/|V_t|   (6), (7)
//! ```
//!
//! # Sign of the multiplier
//! The constraint row is `G_g u = (u_r − u_p)·n` (eq. 9) and the contact forces enter as
//! `Q = −Gᵀλ̇` (eq. 12), i.e. `+Gᵀλ̇` in the residual (eq. 16). The normal force on the pad
//! is then `+n λ̇` (toward the rotor): a positive λ̇ is *tension*. The paper's "incremental
//! normal force" F_z of eq. (1) is a compression (it adds to the preload P_0), so
//! `F_z = −λ̇`. With that reading a pad pressed harder into the rotor has a larger p_n and a
//! larger friction force, which the Hoffmann test (`tests/hoffmann.rs`) checks end to end.
//!
//! # Direction
//! V_t is the velocity of the rotor surface relative to the pad. The pad is dragged along
//! +V_t (eq. 6) and the rotor held back along −V_t (eq. 7). The power of the pair of forces
//! on the absolute velocities is `f_p·v_p + f_r·(v_r + v_slide) = −F_t r(|V_t|) |V_t| ≤ 0`
//! for p_n, μ ≥ 0: friction dissipates.

mod constraint;
mod kernel;
mod regularise;
mod tangents;

pub use kernel::GapOutput;
pub use regularise::regularisation;
pub use tangents::GapBlock;
