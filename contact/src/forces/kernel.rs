//! Per-gap evaluation of eqs. (1)–(7) and [`GapSet::add_forces`].

use super::regularise::regularisation;
use crate::{ContactError, FrictionEval, Gap, GapSet, Real};
use serde::Serialize;

pub(crate) type V3 = [Real; 3];

pub(crate) fn dot(a: V3, b: V3) -> Real {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn gather(v: &[Real], dofs: &[Option<usize>; 3]) -> V3 {
    let mut out = [0.0; 3];
    for k in 0..3 {
        if let Some(d) = dofs[k] {
            out[k] = v[d];
        }
    }
    out
}

/// Everything eqs. (1)–(7) compute for one gap (also the data behind the tangents).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GapOutput {
    /// Normal pressure p_n = −λ̇/A + P_0. [Paper eq. (1)]
    pub pressure: Real,
    /// Tangential slip velocity V_t (rotor surface relative to the pad). [Paper eq. (3)]
    pub slip_velocity: V3,
    /// |V_t|.
    pub slip_speed: Real,
    /// μ and its derivatives at (p_n, |V_t|, T). [Paper eq. (4)]
    pub friction: FrictionEval,
    /// Friction force magnitude after regularisation, F_t·r(|V_t|). [Paper eqs. (4)–(5)]
    pub friction_force: Real,
    /// Force vector on the pad, F_t r V_t/|V_t| (the rotor gets its opposite). [Paper eq. (6)]
    pub force_on_pad: V3,
    /// φ(|V_t|) = r(|V_t|)/|V_t| (see [`super::regularisation`]).
    pub(crate) phi: Real,
    /// φ'(|V_t|)/|V_t|.
    pub(crate) psi: Real,
}

/// Eqs. (1)–(7) for one gap. `v` is the full velocity vector, `lambda` this gap's λ̇.
pub(crate) fn evaluate_gap(set: &GapSet, gap: &Gap, v: &[Real], lambda: Real) -> GapOutput {
    let n = gap.normal;
    let pressure = -lambda / gap.area + gap.p0; // [Paper eq. (1)], F_z = −λ̇
                                                // The pad point's velocity (the node, or Σ_k w_k v_k on a combined pad side).
    let mut vp = [0.0; 3];
    for (w, dofs) in gap.pad_terms() {
        let va = gather(v, &dofs);
        for k in 0..3 {
            vp[k] += w[k] * va[k];
        }
    }
    // The rotor point's velocity Σ_a N_a v_a (one node with weight 1 when coincident).
    let mut vr = [0.0; 3];
    for (w, dofs) in gap.rotor_terms() {
        let va = gather(v, &dofs);
        for k in 0..3 {
            vr[k] += w[k] * va[k];
        }
    }
    let dv = [
        vr[0] - vp[0] + gap.v_slide[0], // [Paper eq. (2)]
        vr[1] - vp[1] + gap.v_slide[1],
        vr[2] - vp[2] + gap.v_slide[2],
    ];
    let dn = dot(dv, n);
    let vt = [dv[0] - dn * n[0], dv[1] - dn * n[1], dv[2] - dn * n[2]]; // [Paper eq. (3)]
    let s = dot(vt, vt).sqrt();
    let friction = set.law_of(gap).evaluate(pressure, s, gap.temperature);
    let ft = friction.mu * gap.area * pressure; // [Paper eq. (4)]
    let (phi, psi) = regularisation(s, set.vtol); // [Paper eq. (5)]
    let c = ft * phi;
    GapOutput {
        pressure,
        slip_velocity: vt,
        slip_speed: s,
        friction,
        friction_force: ft * phi * s,
        force_on_pad: [c * vt[0], c * vt[1], c * vt[2]], // [Paper eq. (6)]
        phi,
        psi,
    }
}

impl GapSet {
    pub(crate) fn check_vectors(
        &self,
        v: &[Real],
        lambda_dot: &[Real],
    ) -> Result<(), ContactError> {
        self.check_lambda_len(lambda_dot)?;
        self.check_dofs(v.len())
    }

    fn check_lambda_len(&self, lambda_dot: &[Real]) -> Result<(), ContactError> {
        if lambda_dot.len() != self.gaps.len() {
            return Err(ContactError::Length {
                what: "lambda_dot",
                len: lambda_dot.len(),
                expected: self.gaps.len(),
            });
        }
        Ok(())
    }

    pub(crate) fn non_finite(&self, ig: usize, what: &'static str, value: Real) -> ContactError {
        ContactError::NonFinite {
            what,
            value,
            gap: ig,
            pad_node: self.gaps[ig].pad_node,
            rotor_node: self.gaps[ig].rotor_node,
        }
    }

    /// Eqs. (1)–(7) for gap `g`: pressure, slip, μ and forces (for outputs and checks).
    pub fn gap_output(
        &self,
        g: usize,
        v: &[Real],
        lambda_dot: &[Real],
    ) -> Result<GapOutput, ContactError> {
        // Only this gap's DOFs are checked: outputs call this per gap and step, and the
        // whole set's check is O(all terms of all gaps) (on an interface-reduced rotor it
        // made the records cost 25 ms a step).
        self.check_lambda_len(lambda_dot)?;
        if g >= self.gaps.len() {
            return Err(ContactError::Length {
                what: "gap index",
                len: g,
                expected: self.gaps.len(),
            });
        }
        self.check_gap_dofs(g, v.len())?;
        Ok(evaluate_gap(self, &self.gaps[g], v, lambda_dot[g]))
    }

    /// Adds the friction forces of all gaps to `f` (length n = `v.len()`): `+F_t V_t/|V_t|` on
    /// the pad DOFs, the opposite on the rotor DOFs (on a tied gap, on each face node times
    /// its weight N_a(ξ*); the rotor velocity of eq. (2) is Σ_a N_a v_a). `lambda_dot` (length ng) are the contact
    /// multipliers (tensile normal force; see the module docs for the sign).
    ///
    /// # Reference
    /// $$p_n = F_z/|S_p| + P_0 \;(1),\quad \Delta v = v_r - v_p + \{0,V_y,0\} \;(2),\quad
    /// V_t = \Delta v - (\Delta v\cdot n)n \;(3),\quad F_t = \mu(p_n,|V_t|,T) A p_n \;(4),$$
    /// $$F_t \leftarrow F_t\,r(|V_t|) \;(5),\quad F_p \mathrel{+}= F_t V_t/|V_t| \;(6),\quad
    /// F_r \mathrel{-}= F_t V_t/|V_t| \;(7)$$ [Paper eqs. (1)–(7)], with F_z = −λ̇ and r( ) as
    /// in [`super::regularisation`].
    ///
    /// # Errors
    /// Wrong lengths, DOF indices out of range, or a non-finite force (names the gap).
    pub fn add_forces(
        &self,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), ContactError> {
        self.check_vectors(v, lambda_dot)?;
        if f.len() != v.len() {
            return Err(ContactError::Length {
                what: "f",
                len: f.len(),
                expected: v.len(),
            });
        }
        for (ig, gap) in self.gaps.iter().enumerate() {
            let out = evaluate_gap(self, gap, v, lambda_dot[ig]);
            let fp = out.force_on_pad;
            for k in 0..3 {
                if !fp[k].is_finite() {
                    return Err(self.non_finite(ig, "friction force on pad", fp[k]));
                }
                for (w, dofs) in gap.pad_terms() {
                    if let Some(d) = dofs[k] {
                        f[d] += w[k] * fp[k]; // [Paper eq. (6)]
                    }
                }
                for (w, dofs) in gap.rotor_terms() {
                    if let Some(d) = dofs[k] {
                        f[d] -= w[k] * fp[k]; // [Paper eq. (7)], spread with the face weights
                    }
                }
            }
        }
        Ok(())
    }
}

impl GapSet {
    /// Slip speed below which a gap counts as near sticking: 3 × the regularisation zone of
    /// [Paper eq. (5)], 30·VTOL (the friction force's slope in |V_t| there is ~μN/VTOL).
    pub fn near_stick_speed(&self) -> Real {
        30.0 * self.vtol
    }

    /// True when some gap slips slower than [`GapSet::near_stick_speed`] (wrong lengths:
    /// false; the force evaluation reports them).
    pub fn near_stick(&self, v: &[Real], lambda_dot: &[Real]) -> bool {
        if self.check_vectors(v, lambda_dot).is_err() {
            return false;
        }
        let limit = self.near_stick_speed();
        self.gaps
            .iter()
            .enumerate()
            .any(|(ig, gap)| evaluate_gap(self, gap, v, lambda_dot[ig]).slip_speed < limit)
    }
}
