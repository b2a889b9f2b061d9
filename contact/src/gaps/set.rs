//! [`GapSet`]: the gaps of all contact surfaces with their friction law and VTOL.

use super::Gap;
use crate::{ContactError, FrictionLaw, Real};
use serde::{Deserialize, Serialize};

/// All gap elements of a model, with the friction law and the regularisation speed VTOL
/// they share. Forces and tangents: [`GapSet::add_forces`], [`GapSet::add_tangents`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GapSet {
    /// The gaps; gap g owns multiplier λ̇_g and constraint row g.
    pub gaps: Vec<Gap>,
    /// Friction law μ(p, |V_t|, T). [Paper eq. (4)]
    pub law: FrictionLaw,
    /// Regularisation speed VTOL > 0 (the paper's sample brake: 0.001). [Paper eq. (5)]
    pub vtol: Real,
}

impl GapSet {
    /// Default VTOL (the paper's sample-brake input), used by [`crate::match_gaps`].
    pub const DEFAULT_VTOL: Real = 1e-3;

    /// A gap set with the given law and VTOL; validates both (and the gaps' own laws).
    pub fn new(gaps: Vec<Gap>, law: FrictionLaw, vtol: Real) -> Result<Self, ContactError> {
        GapSet {
            gaps,
            law: FrictionLaw::default(),
            vtol: Self::DEFAULT_VTOL,
        }
        .with_friction(law, vtol)
    }

    /// The friction law of gap `g`: its own ([`Gap::friction`]) or the set's.
    pub fn law_of<'a>(&'a self, g: &'a Gap) -> &'a FrictionLaw {
        g.friction.as_ref().unwrap_or(&self.law)
    }

    /// Every law in use: the set's and the gaps' own (each once, in order of appearance).
    pub fn laws(&self) -> Vec<&FrictionLaw> {
        let mut out = vec![&self.law];
        for g in &self.gaps {
            if let Some(l) = &g.friction {
                if !out.contains(&l) {
                    out.push(l);
                }
            }
        }
        out
    }

    /// Sets the set's friction law and VTOL (validated, with the gaps' own laws).
    pub fn with_friction(mut self, law: FrictionLaw, vtol: Real) -> Result<Self, ContactError> {
        law.validate()?;
        for (ig, g) in self.gaps.iter().enumerate() {
            if let Some(l) = &g.friction {
                l.validate().map_err(|e| ContactError::Tie {
                    gap: ig,
                    pad_node: g.pad_node,
                    message: format!("its own friction law: {e}"),
                })?;
            }
        }
        if !(vtol.is_finite() && vtol > 0.0) {
            return Err(ContactError::InvalidOption {
                field: "friction.vtol".into(),
                value: format!("{vtol}"),
                reason: "must be finite and > 0".into(),
            });
        }
        self.law = law;
        self.vtol = vtol;
        Ok(self)
    }

    /// Appends the gaps of another surface (its law and VTOL are dropped: this set's apply).
    pub fn append(&mut self, other: GapSet) {
        self.gaps.extend(other.gaps);
    }

    /// Number of gaps (= number of contact multipliers ng).
    pub fn len(&self) -> usize {
        self.gaps.len()
    }

    /// Whether there is no gap.
    pub fn is_empty(&self) -> bool {
        self.gaps.is_empty()
    }

    /// Sets every gap's pad and rotor DOF indices from a node-id → [x, y, z] DOF map
    /// (None for a fixed DOF).
    pub fn assign_dofs(&mut self, mut dofs_of: impl FnMut(u64) -> [Option<usize>; 3]) {
        for g in &mut self.gaps {
            g.pad_dofs = dofs_of(g.pad_node);
            g.rotor_dofs = dofs_of(g.rotor_node);
            if let Some(t) = &mut g.tie {
                t.dofs = t.nodes.iter().map(|&n| dofs_of(n)).collect();
            }
            if let Some(p) = &mut g.pad_side {
                p.dofs = p.nodes.iter().map(|&n| dofs_of(n)).collect();
            }
        }
    }

    /// Checks that every DOF index is < `n`.
    pub fn check_dofs(&self, n: usize) -> Result<(), ContactError> {
        for ig in 0..self.gaps.len() {
            self.check_gap_dofs(ig, n)?;
        }
        Ok(())
    }

    /// [`GapSet::check_dofs`] for gap `ig` alone.
    pub(crate) fn check_gap_dofs(&self, ig: usize, n: usize) -> Result<(), ContactError> {
        let g = &self.gaps[ig];
        if let Some(t) = &g.tie {
            if t.dofs.len() != t.nodes.len() || t.weights.len() != t.nodes.len() {
                return Err(ContactError::Tie {
                    gap: ig,
                    pad_node: g.pad_node,
                    message: format!(
                        "{} face nodes, {} weights, {} DOF triples (DOFs not assigned?)",
                        t.nodes.len(),
                        t.weights.len(),
                        t.dofs.len()
                    ),
                });
            }
        }
        if let Some(p) = &g.pad_side {
            if p.dofs.len() != p.nodes.len() || p.weights.len() != p.nodes.len() {
                return Err(ContactError::Tie {
                    gap: ig,
                    pad_node: g.pad_node,
                    message: format!(
                        "pad side: {} nodes, {} weights, {} DOF triples (DOFs not assigned?)",
                        p.nodes.len(),
                        p.weights.len(),
                        p.dofs.len()
                    ),
                });
            }
        }
        let tied = g.tie.iter().flat_map(|t| t.dofs.iter()).flatten();
        let pad_side = g.pad_side.iter().flat_map(|p| p.dofs.iter()).flatten();
        let rows = g.rotor_rows.iter().map(|r| &r.dof);
        for d in g
            .pad_dofs
            .iter()
            .chain(g.rotor_dofs.iter())
            .flatten()
            .chain(tied.flatten())
            .chain(pad_side.flatten())
            .chain(rows)
        {
            if *d >= n {
                return Err(ContactError::DofOutOfRange {
                    gap: ig,
                    pad_node: g.pad_node,
                    rotor_node: g.rotor_node,
                    dof: *d,
                    n,
                });
            }
        }
        Ok(())
    }
}
