//! Gap elements: pad/rotor node pairs with normal, area and sliding velocity (PREBSQL).

mod bond;
mod face;
mod grid;
mod matching;
mod mortar;
mod set;
mod shape;
mod tie;
mod vec3;

use crate::{ContactError, Real};
use serde::{Deserialize, Serialize};

pub use bond::{bond_rows, bond_rows_joined, BondRow};
pub use face::{FaceKind, RotorFace, SNAP as FACE_SNAP};
pub use matching::match_gaps;
pub use mortar::{mortar_gaps, MortarOptions, MortarStats};
pub use set::GapSet;
pub use tie::{tie_gaps, TieOptions, TieOutcome, TieStats, Unmatched};

/// A contact-surface node as the caller knows it (no mesh needed).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactNode {
    /// Node id (reported in errors and stored in the gap).
    pub id: u64,
    /// Coordinates.
    pub coords: [Real; 3],
    /// Outward area vector S_p of a pad node (its length is the tributary area); ignored for
    /// rotor nodes.
    pub area: [Real; 3],
}

/// Options of the gap matching (PREBSQL).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MatchOptions {
    /// Distance within which a pad node and a rotor node coincide (default: 1e-6, model units).
    pub tolerance: Real,
    /// A point on the rotor axis (default: [0, 0, 0]).
    pub rotor_axis_origin: [Real; 3],
    /// Unit vector of the rotor axis; the rotor turns positively (right hand) about it
    /// (default: [0, 0, 1]).
    pub rotor_axis: [Real; 3],
    /// Rotor speed in revolutions per minute (default: 0; the paper's sample brake: 143.239).
    pub rpm: Real,
    /// Preload pressure P_0 given to every gap (default: 0). [Paper eq. (1)]
    pub p0: Real,
    /// Temperature given to every gap (default: 0; only read by temperature-dependent laws).
    pub temperature: Real,
}

impl Default for MatchOptions {
    fn default() -> Self {
        MatchOptions {
            tolerance: 1e-6,
            rotor_axis_origin: [0.0; 3],
            rotor_axis: [0.0, 0.0, 1.0],
            rpm: 0.0,
            p0: 0.0,
            temperature: 0.0,
        }
    }
}

impl MatchOptions {
    /// Checks the options; the error names the field and the value.
    pub fn validate(&self) -> Result<(), ContactError> {
        let bad = |field: &str, value: String, reason: &str| ContactError::InvalidOption {
            field: format!("match.{field}"),
            value,
            reason: reason.to_string(),
        };
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(bad(
                "tolerance",
                format!("{}", self.tolerance),
                "must be finite and > 0",
            ));
        }
        let a = self.rotor_axis;
        let norm = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if !norm.is_finite() || (norm - 1.0).abs() > 1e-6 {
            return Err(bad(
                "rotor_axis",
                format!("{a:?} (norm {norm})"),
                "must be a unit vector",
            ));
        }
        if self.rotor_axis_origin.iter().any(|x| !x.is_finite()) {
            return Err(bad(
                "rotor_axis_origin",
                format!("{:?}", self.rotor_axis_origin),
                "must be finite",
            ));
        }
        for (name, v) in [
            ("rpm", self.rpm),
            ("p0", self.p0),
            ("temperature", self.temperature),
        ] {
            if !v.is_finite() {
                return Err(bad(name, format!("{v}"), "must be finite"));
            }
        }
        Ok(())
    }

    /// Rotor angular velocity vector ω = (2π·rpm/60)·axis, in rad per unit time.
    pub fn omega(&self) -> [Real; 3] {
        let w = self.rpm * 2.0 * std::f64::consts::PI / 60.0;
        [
            w * self.rotor_axis[0],
            w * self.rotor_axis[1],
            w * self.rotor_axis[2],
        ]
    }
}

/// One gap element: a pad point in contact with a rotor point. [Paper eqs. (1)–(7)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gap {
    /// Pad node id.
    pub pad_node: u64,
    /// Rotor node id.
    pub rotor_node: u64,
    /// Position of the pad node.
    pub coords: [Real; 3],
    /// Indices of the pad node's x, y, z DOFs in the reduced vector (None = fixed DOF).
    pub pad_dofs: [Option<usize>; 3],
    /// Indices of the rotor node's x, y, z DOFs in the reduced vector (None = fixed DOF).
    pub rotor_dofs: [Option<usize>; 3],
    /// Unit normal n = S_p/|S_p|, out of the pad, toward the rotor.
    pub normal: [Real; 3],
    /// Contact area A = |S_p|.
    pub area: Real,
    /// Steady sliding velocity of the rotor material at the point, ω × r (the paper's
    /// {0, V_y, 0} in a local frame). [Paper eq. (2)]
    pub v_slide: [Real; 3],
    /// Preload pressure P_0. [Paper eq. (1)]
    pub p0: Real,
    /// Temperature of the gap (read only by temperature-dependent friction laws).
    pub temperature: Real,
    /// Surface pairing ([`crate::tie_gaps`]): the rotor face the pad node projects on, with
    /// the weights of its nodes. None: the coincident pair `rotor_node` (weight 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tie: Option<FaceTie>,
    /// The rotor point's displacement as rows over the reduced vector, when the rotor's
    /// contact DOFs are not reduced DOFs themselves (an interface-reduced rotor): u_k =
    /// Σ_rows weights[k] · x[dof]. When non-empty it replaces `rotor_dofs` and the tie's DOFs
    /// in [`Gap::rotor_terms`] (the node ids and weights still say where the point is).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rotor_rows: Vec<RotorRow>,
    /// The pad side as a combination of pad nodes, û = Σ_k w_k u_k, instead of the node
    /// `pad_node` alone: a mortar gap on a mid-side node of a quadratic pad face, whose dual
    /// multiplier pairs with the transformed basis ([`crate::mortar_gaps`]). None: the node
    /// `pad_node` with weight 1 (`pad_dofs`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pad_side: Option<PadSide>,
    /// This gap's own friction law (a contact pair with its own `friction`), used instead of
    /// the set's [`GapSet::law`]. None: the set's law.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<crate::FrictionLaw>,
}

/// The pad side of a gap over several pad nodes: the point û = Σ_k w_k u_k (weights sum to 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PadSide {
    /// Pad node ids (the gap's `pad_node` among them).
    pub nodes: Vec<u64>,
    /// Their weights (sum 1).
    pub weights: Vec<Real>,
    /// x, y, z DOF indices of each node (None = fixed). Set by [`GapSet::assign_dofs`].
    #[serde(default)]
    pub dofs: Vec<[Option<usize>; 3]>,
}

/// One term of a recovered rotor point: reduced DOF `dof` moves the point by `weights`
/// (x, y, z) per unit value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RotorRow {
    pub dof: usize,
    pub weights: [Real; 3],
}

/// The rotor side of a gap tied to a rotor face: the point x(ξ*) = Σ_a N_a(ξ*) x_a.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FaceTie {
    /// Face id given by the caller.
    pub face: u64,
    /// quad4 or quad8.
    pub kind: FaceKind,
    /// Face coordinates (ξ*, η*) of the projection.
    pub xi: [Real; 2],
    /// The face's node ids (in the face's order).
    pub nodes: Vec<u64>,
    /// Weights N_a(ξ*) of the nodes (they sum to 1; 0 for nodes the point does not see).
    pub weights: Vec<Real>,
    /// Distance from the pad node to the projected point (0 when read from a gap table).
    #[serde(default)]
    pub distance: Real,
    /// x, y, z DOF indices of each node (None = fixed or not in the model; only nodes of
    /// non-zero weight need DOFs). Set by [`GapSet::assign_dofs`].
    #[serde(default)]
    pub dofs: Vec<[Option<usize>; 3]>,
    /// Mortar pairing ([`crate::mortar_gaps`]): `nodes` are the rotor nodes of non-zero
    /// mortar weight W_ja (on one or more faces; they sum to 1 and may be negative), not the
    /// face's nodes; `face`, `xi` and `distance` are the pad node's projection on its main
    /// face, for reports (default: false, the node-to-surface tie).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub mortar: bool,
    /// Coordinates of `nodes`, same order (default: empty = not known, e.g. a gap table
    /// without them), so that a stored model can place every tied rotor node (VTU outputs).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub coords: Vec<[Real; 3]>,
}

impl ContactNode {
    /// |S_p| of a pad node, or why its area vector cannot make a gap (zero or non-finite).
    pub(crate) fn pad_area(&self) -> Result<Real, String> {
        let s = self.area;
        let a = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
        if a.is_finite() && a > 0.0 {
            Ok(a)
        } else {
            Err(format!(
                "pad node has area vector {s:?} (|S_p| = {a}); it must be non-zero and finite"
            ))
        }
    }
}

impl Gap {
    /// The gap of pad node `pn` (area `a` = |S_p|) on `rotor_node`, as both pairings make it:
    /// normal n = S_p/a, sliding velocity ω × (x − origin) [Paper eq. (2)], P0 and temperature
    /// from the options, DOF indices unassigned.
    pub(crate) fn at_pad_node(
        pn: &ContactNode,
        a: Real,
        rotor_node: u64,
        opts: &MatchOptions,
        tie: Option<FaceTie>,
    ) -> Gap {
        let (s, x, o, w) = (pn.area, pn.coords, opts.rotor_axis_origin, opts.omega());
        let r = [x[0] - o[0], x[1] - o[1], x[2] - o[2]];
        Gap {
            pad_node: pn.id,
            rotor_node,
            coords: x,
            pad_dofs: [None; 3],
            rotor_dofs: [None; 3],
            normal: [s[0] / a, s[1] / a, s[2] / a],
            area: a,
            v_slide: [
                w[1] * r[2] - w[2] * r[1],
                w[2] * r[0] - w[0] * r[2],
                w[0] * r[1] - w[1] * r[0],
            ],
            p0: opts.p0,
            temperature: opts.temperature,
            tie,
            rotor_rows: Vec::new(),
            pad_side: None,
            friction: None,
        }
    }

    /// The pad side of the gap as (x/y/z weights, x/y/z DOFs) terms: the node `pad_node`
    /// with weight 1, or the nodes of [`Gap::pad_side`] with their weights. The pad point's
    /// velocity component k is Σ w_k v[dofs_k], and a force f on it is w_k f_k on DOF dofs_k.
    pub fn pad_terms(&self) -> impl Iterator<Item = ([Real; 3], [Option<usize>; 3])> + '_ {
        let single = self.pad_side.is_none().then_some(([1.0; 3], self.pad_dofs));
        let combined = self.pad_side.iter().flat_map(|p| {
            p.weights
                .iter()
                .copied()
                .zip(p.dofs.iter())
                .filter(|(w, _)| *w != 0.0)
                .map(|(w, d)| ([w; 3], *d))
        });
        single.into_iter().chain(combined)
    }

    /// The pad node ids the gap acts on (`pad_node`, or the nodes of its pad side).
    pub fn pad_nodes(&self) -> Vec<u64> {
        match &self.pad_side {
            None => vec![self.pad_node],
            Some(p) => p
                .nodes
                .iter()
                .zip(&p.weights)
                .filter(|(_, &w)| w != 0.0)
                .map(|(&n, _)| n)
                .collect(),
        }
    }

    /// The rotor side of the gap as (x/y/z weights, x/y/z DOFs) terms: the one coincident
    /// node with weight 1, or the tied face's nodes of non-zero weight (the same weight in
    /// every direction), or the recovery rows (`rotor_rows`: one reduced DOF per term, its
    /// weight per direction). The rotor point's velocity component k is Σ w_k v[dofs_k], and
    /// a force f on it is w_k f_k on DOF dofs_k.
    pub fn rotor_terms(&self) -> impl Iterator<Item = ([Real; 3], [Option<usize>; 3])> + '_ {
        let rows = !self.rotor_rows.is_empty();
        let single = (self.tie.is_none() && !rows).then_some(([1.0; 3], self.rotor_dofs));
        let tied = self.tie.iter().filter(move |_| !rows).flat_map(|t| {
            t.weights
                .iter()
                .copied()
                .zip(t.dofs.iter())
                .filter(|(w, _)| *w != 0.0)
                .map(|(w, d)| ([w; 3], *d))
        });
        single.into_iter().chain(tied).chain(
            self.rotor_rows
                .iter()
                .map(|r| (r.weights, [Some(r.dof); 3])),
        )
    }

    /// The rotor node ids the gap acts on (the coincident node, or the tied face's nodes of
    /// non-zero weight).
    pub fn rotor_nodes(&self) -> Vec<u64> {
        match &self.tie {
            None => vec![self.rotor_node],
            Some(t) => t
                .nodes
                .iter()
                .zip(&t.weights)
                .filter(|(_, &w)| w != 0.0)
                .map(|(&n, _)| n)
                .collect(),
        }
    }
}
