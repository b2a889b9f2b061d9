//! Energy balance of one complex mode: where it gets its energy, where it loses it.

use super::Triplet;
use crate::cea::{CeaError, CeaMatrices, Cplx};
use faer::Mat;
use serde::Serialize;
use std::f64::consts::PI;

/// One component's part of M, K and B, on its DOFs of the reduced model (a superelement).
/// The model's matrices are the sums of the parts scattered to their DOFs (shared boundary
/// DOFs appear in several parts).
#[derive(Debug, Clone)]
pub struct ComponentPart {
    /// Component name.
    pub name: String,
    /// Reduced DOFs of the part (indices into the model's n).
    pub dofs: Vec<usize>,
    /// Mass block (dofs × dofs).
    pub m: Mat<f64>,
    /// Stiffness block (symmetric).
    pub k: Mat<f64>,
    /// Damping block (`None`: undamped).
    pub b: Option<Mat<f64>>,
}

/// One gap's contact row and friction tangents on its DOFs.
#[derive(Debug, Clone)]
pub struct GapPart {
    /// Contact pair of the gap (index into the scene's pairs).
    pub pair: usize,
    /// DOFs the gap touches (pad DOFs and the rotor point's DOFs).
    pub dofs: Vec<usize>,
    /// The gap's row of G on `dofs`.
    pub g: Vec<f64>,
    /// Column of D = ∂F_f/∂λ̇ on `dofs`.
    pub d: Vec<f64>,
    /// Block of C_f = ∂F_f/∂v on `dofs` × `dofs`.
    pub c_f: Mat<f64>,
    /// Normal contact compliance 1/(k_n A) (0: rigid, a constraint row of G).
    pub compliance: f64,
}

/// The model split into the parts whose energy is reported.
#[derive(Debug, Clone, Default)]
pub struct EnergyParts {
    /// Components (Σ M_c = M, Σ K_c = K without the contact springs, Σ B_c = B).
    pub components: Vec<ComponentPart>,
    /// Gaps, in the order of the model's gap table (rigid gaps are G's rows in this order).
    pub gaps: Vec<GapPart>,
}

impl EnergyParts {
    /// The CEA matrices these parts make: M, B, K summed from the components; the rigid gaps'
    /// rows in G and columns in D; C_f summed from every gap; each compliant gap folded into
    /// K as `(gᵀ − d) k g` (k = 1/compliance; the force `N = k g·u`), as
    /// `crate::bsql::compliant_cea` does.
    pub fn assemble(&self, n: usize) -> CeaMatrices {
        let mut m = Mat::<f64>::zeros(n, n);
        let mut k = Mat::<f64>::zeros(n, n);
        let mut b = None::<Mat<f64>>;
        for c in &self.components {
            for (a, &i) in c.dofs.iter().enumerate() {
                for (bb, &j) in c.dofs.iter().enumerate() {
                    m[(i, j)] += c.m[(a, bb)];
                    k[(i, j)] += c.k[(a, bb)];
                    if let Some(cb) = &c.b {
                        b.get_or_insert_with(|| Mat::zeros(n, n))[(i, j)] += cb[(a, bb)];
                    }
                }
            }
        }
        let rigid: Vec<&GapPart> = self.gaps.iter().filter(|g| g.compliance == 0.0).collect();
        let mut g = Mat::<f64>::zeros(rigid.len(), n);
        let mut d = Mat::<f64>::zeros(n, rigid.len());
        for (r, gp) in rigid.iter().enumerate() {
            for (a, &i) in gp.dofs.iter().enumerate() {
                g[(r, i)] += gp.g[a];
                d[(i, r)] += gp.d[a];
            }
        }
        let mut c_f = Mat::<f64>::zeros(n, n);
        for gp in &self.gaps {
            for (a, &i) in gp.dofs.iter().enumerate() {
                for (bb, &j) in gp.dofs.iter().enumerate() {
                    c_f[(i, j)] += gp.c_f[(a, bb)];
                }
            }
            if gp.compliance > 0.0 {
                let kn = 1.0 / gp.compliance;
                for (a, &i) in gp.dofs.iter().enumerate() {
                    for (bb, &j) in gp.dofs.iter().enumerate() {
                        k[(i, j)] += (gp.g[a] - gp.d[a]) * kn * gp.g[bb];
                    }
                }
            }
        }
        let has_rigid = !rigid.is_empty();
        CeaMatrices {
            m,
            k,
            b,
            g: has_rigid.then_some(g),
            d: has_rigid.then_some(d),
            c_f: Some(c_f),
        }
    }
}

/// Energy balance of one mode (see [`mode_energy`] for the identity and the scaling).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeEnergy {
    /// Root p = σ + iω, `[re, im]`.
    pub eigenvalue: [f64; 2],
    /// ω/2π, Hz.
    pub frequency_hz: f64,
    /// σ = Re p, 1/s.
    pub growth_rate_per_s: f64,
    /// Mode energy E (cycle average of kinetic + strain energy at the reference amplitude:
    /// φ of unit 2-norm).
    pub energy: f64,
    /// Cycle-average kinetic energy per component (same order as the parts).
    pub kinetic: Vec<f64>,
    /// Cycle-average strain energy per component.
    pub strain: Vec<f64>,
    /// Cycle-average strain energy of the compliant contact springs (0 when all are rigid).
    pub contact_strain: f64,
    /// Mean power fed in by the friction forces of each gap (positive: the gap feeds the mode).
    pub friction_power: Vec<f64>,
    /// Mean power of the damping forces of each component (≤ 0 for a positive semi-definite
    /// damping block: dissipated).
    pub damping_power: Vec<f64>,
    /// Σ friction power + Σ damping power.
    pub net_power: f64,
    /// `|2σE − net power| / (|p| E + Σ|powers|)`: the identity's closure relative to the
    /// mode's own power scale |p|E (round-off and the eigenvector's residual only).
    pub identity_residual: f64,
    /// Period 2π/ω (s; infinite for a real root): power × period is the work per cycle.
    pub period_s: f64,
}

impl ModeEnergy {
    /// Work per cycle fed in by each gap's friction (power × period).
    pub fn friction_work_per_cycle(&self) -> Vec<f64> {
        self.friction_power
            .iter()
            .map(|p| p * self.period_s)
            .collect()
    }
}

fn quad(block: &Mat<f64>, dofs: &[usize], x: &[Cplx], y: &[Cplx]) -> Cplx {
    // xᴴ A y on the part's DOFs.
    let mut s = Cplx::new(0.0, 0.0);
    for (a, &i) in dofs.iter().enumerate() {
        let mut r = Cplx::new(0.0, 0.0);
        for (b, &j) in dofs.iter().enumerate() {
            r += block[(a, b)] * y[j];
        }
        s += x[i].conj() * r;
    }
    s
}

/// The energy balance of the mode `t` of the model made of `parts`.
///
/// # Reference
/// With the motion `u = Re(φ e^{pt})`, `v = u̇ = Re(pφ e^{pt})`, the normal-force perturbation
/// of gap k `N_k = Re(ν_k e^{pt})` (rigid gaps: the multiplier part of the right eigenvector;
/// compliant gaps: `N_k = k_k g_k·φ`), premultiplying the eigen-equation
/// `(p²M + pC + K)φ + Σ_k (g_kᵀ − d_k) N_k = 0` by `(pφ)ᴴ` and taking the real part gives,
/// since `g_k φ = 0` on rigid rows and `Re(φᴴAφ) = φᴴA_sym φ` for real A:
/// ```text
/// 2σ E = Σ_k P_k + Σ_c P_c,
/// E   = ¼ (|p|² φᴴMφ + φᴴKφ + Σ_compliant k_k |g_k φ|²),
/// P_k = ½ Re[(pφ)ᴴ (C_f,k pφ + d_k ν_k)]      (friction of gap k),
/// P_c = −½ |p|² φ_cᴴ B_c φ_c                  (damping of component c).
/// ```
/// For σ = 0 these are the cycle averages of the energy and of the powers of a harmonic
/// motion of amplitude φ; for σ ≠ 0 the same quadratic forms at t = 0 (the averages over a
/// cycle scaled by e^{2σt}): "net power in = 2σ × the mode's energy". The friction power of
/// a gap is the work it does on the mode per unit time, the feed-in density of the
/// energy-flow analyses of brake squeal (e.g. Guan & Huang, *Modal energy analysis of a
/// disc-brake squeal*, J. Sound Vib. 2003; Sinou et al. 2018). Derivation: `docs/insight.md`.
///
/// # Errors
/// Parts whose lengths do not match, DOFs out of range, or a rigid-gap count that does not
/// match the length of `t.nu`.
pub fn mode_energy(parts: &EnergyParts, t: &Triplet) -> Result<ModeEnergy, CeaError> {
    let n = t.phi.len();
    let bad = |what: &'static str, rows: usize, expected: usize| CeaError::Shape {
        what,
        rows,
        cols: 1,
        expected_rows: expected,
        expected_cols: 1,
    };
    let n_rigid = parts.gaps.iter().filter(|g| g.compliance == 0.0).count();
    if n_rigid != t.nu.len() {
        return Err(bad("rigid gaps vs multipliers", n_rigid, t.nu.len()));
    }
    for c in &parts.components {
        if c.dofs.iter().any(|&i| i >= n) {
            return Err(bad("component DOF index", n, n));
        }
        let r = c.dofs.len();
        for (what, mm) in [
            ("component M", Some(&c.m)),
            ("component K", Some(&c.k)),
            ("component B", c.b.as_ref()),
        ] {
            if let Some(mm) = mm {
                if mm.nrows() != r || mm.ncols() != r {
                    return Err(bad(what, mm.nrows(), r));
                }
            }
        }
    }
    for g in &parts.gaps {
        let r = g.dofs.len();
        if g.dofs.iter().any(|&i| i >= n) {
            return Err(bad("gap DOF index", n, n));
        }
        if g.g.len() != r || g.d.len() != r || g.c_f.nrows() != r || g.c_f.ncols() != r {
            return Err(bad("gap part", g.g.len(), r));
        }
    }
    let p = t.p;
    let p2 = p.norm_sqr();
    let v: Vec<Cplx> = t.phi.iter().map(|z| p * z).collect();
    let mut kinetic = Vec::with_capacity(parts.components.len());
    let mut strain = Vec::with_capacity(parts.components.len());
    let mut damping_power = Vec::with_capacity(parts.components.len());
    for c in &parts.components {
        kinetic.push(0.25 * p2 * quad(&c.m, &c.dofs, &t.phi, &t.phi).re);
        strain.push(0.25 * quad(&c.k, &c.dofs, &t.phi, &t.phi).re);
        damping_power.push(match &c.b {
            Some(b) => -0.5 * quad(b, &c.dofs, &v, &v).re,
            None => 0.0,
        });
    }
    let mut friction_power = Vec::with_capacity(parts.gaps.len());
    let mut contact_strain = 0.0;
    let mut rigid = 0;
    for g in &parts.gaps {
        let nk = if g.compliance == 0.0 {
            rigid += 1;
            t.nu[rigid - 1]
        } else {
            let gu: Cplx = g.dofs.iter().zip(&g.g).map(|(&i, &w)| w * t.phi[i]).sum();
            contact_strain += 0.25 * gu.norm_sqr() / g.compliance;
            gu / g.compliance
        };
        // ½ Re[vᴴ (C_f,k v + d_k N_k)] on the gap's DOFs.
        let mut s = quad(&g.c_f, &g.dofs, &v, &v);
        for (a, &i) in g.dofs.iter().enumerate() {
            s += v[i].conj() * g.d[a] * nk;
        }
        friction_power.push(0.5 * s.re);
    }
    let energy = kinetic.iter().sum::<f64>() + strain.iter().sum::<f64>() + contact_strain;
    let net_power = friction_power.iter().sum::<f64>() + damping_power.iter().sum::<f64>();
    let lhs = 2.0 * p.re * energy;
    let scale = t.p.norm() * energy
        + friction_power.iter().map(|x| x.abs()).sum::<f64>()
        + damping_power.iter().map(|x| x.abs()).sum::<f64>();
    let identity_residual = if scale > 0.0 {
        (lhs - net_power).abs() / scale
    } else {
        0.0
    };
    Ok(ModeEnergy {
        eigenvalue: [p.re, p.im],
        frequency_hz: p.im.abs() / (2.0 * PI),
        growth_rate_per_s: p.re,
        energy,
        kinetic,
        strain,
        contact_strain,
        friction_power,
        damping_power,
        net_power,
        identity_residual,
        period_s: if p.im != 0.0 {
            2.0 * PI / p.im.abs()
        } else {
            f64::INFINITY
        },
    })
}
