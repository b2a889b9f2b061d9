//! squeal-contact: gap matching and friction laws, paper eqs. (1)–(7).
//!
//! This crate does not know meshes: it takes node ids, coordinates and area vectors
//! ([`ContactNode`]), builds the pad/rotor "gap" elements ([`match_gaps`], the PREBSQL step),
//! evaluates the friction law μ(p, |V_t|, T) ([`FrictionLaw`]) and the gap forces and their
//! exact tangents ([`GapSet::add_forces`], [`GapSet::add_tangents`]), and the contact
//! constraint matrix G ([`GapSet::constraint_matrix`]).
//!
//! Two pairings make the gaps: [`match_gaps`] pairs coincident pad and rotor nodes
//! (PREBSQL's rule); [`tie_gaps`] projects each pad node on the rotor's quad4/quad8 faces
//! ([`RotorFace`]) and ties it to the face point, whose nodes carry the shape-function
//! weights N_a(ξ*) ([`FaceTie`]): non-matching meshes. Every force, tangent and G routine
//! works on both ([`Gap::rotor_terms`]).
//!
//! # Sign conventions (read this once)
//!
//! * `n = S_p/|S_p|` is the outward pad normal, pointing from the pad toward the rotor.
//! * The constraint row of gap g is `G_g u = (u_rotor − u_pad)·n` [Paper eq. (9)], and the
//!   contact forces are `Q = −Gᵀ λ̇` [Paper eq. (12)]. With these two signs, a positive
//!   multiplier `λ̇_g` pushes the pad by `+n λ̇_g` (toward the rotor) and the rotor by `−n λ̇_g`:
//!   it is a *tensile* normal force. The compressive normal force of eq. (1) is therefore
//!   `F_z = −λ̇_g`, and `p_n = −λ̇_g/|S_p| + P_0` (a preload `P_0 > 0` is a compression).
//!   See [`forces`] for the equations.

pub mod error;
pub mod forces;
pub mod friction;
pub mod gaps;

/// The workspace's real scalar (its one definition is `squeal_meshes::Real`).
pub use squeal_meshes::Real;

pub use error::{ContactError, NodeReport};
pub use forces::GapOutput;
pub use friction::{FrictionEval, FrictionLaw};
pub use gaps::{
    bond_rows, bond_rows_joined, match_gaps, mortar_gaps, tie_gaps, BondRow, ContactNode, FaceKind,
    FaceTie, Gap, GapSet, MatchOptions, MortarOptions, MortarStats, PadSide, RotorFace, RotorRow,
    TieOptions, TieOutcome, TieStats, Unmatched, FACE_SNAP,
};
