//! Small stored-matrix models for the work–precision study, the hard-case suite and the
//! effects benchmark: written as `NAME.op4` (KR, MR, BR, PBRAKE; ASCII), `NAME.dofmap.json`
//! and `NAME.gaps.csv`, the inputs of a `[model] from = "op4"` scene.
//!
//! Every model has pads sliding on a rotor along +y: the gap of pad grid `g` sits at
//! (1, 0, 0) with normal +z, and a rotor turning at ω = 1 rad/s about z (`rpm = 60/2π`)
//! slides under it at V = 1. A pad grid has DOFs y (tangential, comp 2) and z (normal,
//! comp 3), its rotor grid one DOF z, tied to the pad's z by the contact constraint.

use crate::error::PipelineError;
use faer::Mat;
use squeal_reduction::matrix::{MatrixForm, NamedMatrix};
use squeal_reduction::op4::{self, Op4WriteOptions};
use squeal_reduction::superelement::{DofKind, ReducedDof, ReducedDofMap};
use std::f64::consts::PI;
use std::path::Path;

use squeal_solver::Real;

/// Rotor speed of every model: ω = 1 rad/s, so the sliding speed at radius 1 is V = 1.
pub const RPM: Real = 60.0 / (2.0 * PI);

/// A stored reduced model: matrices, DOF map (grid, comp) and gap rows.
#[derive(Debug, Clone)]
pub struct StoredModel {
    pub k: Mat<Real>,
    pub m: Mat<Real>,
    pub b: Option<Mat<Real>>,
    pub p_brake: Vec<Real>,
    /// (grid, comp) of each row.
    pub dofs: Vec<(u64, u8)>,
    /// (pad grid, rotor grid, normal, area, p0).
    pub gaps: Vec<(u64, u64, [Real; 3], Real, Real)>,
}

impl StoredModel {
    /// Writes `NAME.op4`, `NAME.dofmap.json`, `NAME.gaps.csv` into `dir`.
    pub fn write(&self, dir: &Path, name: &str) -> Result<(), PipelineError> {
        let n = self.k.nrows();
        std::fs::create_dir_all(dir).map_err(|source| PipelineError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
        let mut mats = vec![
            NamedMatrix::real("KR", self.k.clone()),
            NamedMatrix::real("MR", self.m.clone()),
        ];
        if let Some(b) = &self.b {
            mats.push(NamedMatrix::real("BR", b.clone()));
        }
        mats.push(
            NamedMatrix::real("PBRAKE", Mat::from_fn(n, 1, |i, _| self.p_brake[i]))
                .with_form(MatrixForm::Rectangular),
        );
        let refs: Vec<&NamedMatrix> = mats.iter().collect();
        let bytes = op4::write_bytes(
            &refs,
            &Op4WriteOptions {
                binary: false,
                ..Default::default()
            },
        )
        .map_err(|source| PipelineError::Reduction {
            what: format!("writing {name}.op4"),
            source,
        })?;
        let w = |file: String, bytes: &[u8]| {
            let p = dir.join(file);
            std::fs::write(&p, bytes).map_err(|source| PipelineError::Io { path: p, source })
        };
        w(format!("{name}.op4"), &bytes)?;
        let map = ReducedDofMap {
            recovered: Vec::new(),
            dofs: self
                .dofs
                .iter()
                .map(|&(grid, comp)| ReducedDof {
                    component: if grid > 100_000 { "rotor" } else { "pad" }.into(),
                    shared_with: Vec::new(),
                    kind: DofKind::Grid { grid, comp },
                })
                .collect(),
        };
        let json = map
            .to_json()
            .map_err(|e| PipelineError::Model(format!("dofmap: {e}")))?;
        w(format!("{name}.dofmap.json"), json.as_bytes())?;
        let mut csv = String::from("pad_grid,rotor_grid,x,y,z,nx,ny,nz,area,p0,temperature\n");
        for &(p, r, nrm, a, p0) in &self.gaps {
            csv.push_str(&format!(
                "{p},{r},1,0,0,{},{},{},{a},{p0},0\n",
                nrm[0], nrm[1], nrm[2]
            ));
        }
        w(format!("{name}.gaps.csv"), csv.as_bytes())
    }
}

/// The mass on a belt with falling friction (Popp's classic; the model of
/// `solver/examples/galpha_vs_bdf.rs`): pad y with m = 1, k = (2π)², c = 0.3; normal force
/// N = A·P0 = 10 through the preload; μ = 0.5 − 0.05|V_t| (`linear_speed`, mu0 = 0.5,
/// slope = −0.05) so the friction's negative damping N·0.05 = 0.5 beats c: the linearised
/// growth rate is σ = (N·0.05 − c)/(2m) = +0.1 /s at ω_d = √(k − σ²) ≈ 2π.
/// DOFs: [pad y, pad z, rotor z]; z masses 2 and 1, stiffnesses 50 (no normal load, so the
/// contact force stays 0 and N stays A·P0). PBRAKE = a unit tangential force on pad y.
pub fn belt() -> StoredModel {
    let k = (2.0 * PI).powi(2);
    StoredModel {
        k: diag(&[k, 50.0, 50.0]),
        m: diag(&[1.0, 2.0, 1.0]),
        b: Some(diag(&[0.3, 0.0, 0.0])),
        p_brake: vec![1.0, 0.0, 0.0],
        dofs: vec![(1, 2), (1, 3), (100_001, 3)],
        gaps: vec![(1, 100_001, [0.0, 0.0, 1.0], 1.0, 10.0)],
    }
}

/// Analytic growth rate σ (1/s) and damped frequency (Hz) of [`belt`].
pub fn belt_reference() -> (Real, Real) {
    let sigma = (10.0 * 0.05 - 0.3) / 2.0;
    let w = ((2.0 * PI).powi(2) - sigma * sigma).sqrt();
    (sigma, w / (2.0 * PI))
}

/// Hoffmann's 2-DOF mode-coupling model (Hoffmann, Fischer, Bieser & Gaul 2002) with the
/// normal spring carried by a rotor DOF, as in the CEA test
/// `friction_tangent_d_is_projected_exactly`: DOFs [pad y, pad z, rotor z],
/// M = diag(1, 1, m_r = 0.5), K = w0²·[[1, 0.3, 0], [0.3, 0.2, 0], [0, 0, 1]] with
/// w0 = 2π (time scaled so that the modes are near 1 Hz), constant μ, N = A·P0 − λ'.
/// Eliminating λ' gives (1 + m_r) s² + (1.2 + (1 + m_r) + 0.3 μ m_r) s + 1.2 − 0.3 (0.3 − μ) = 0
/// for s = (p/w0)²: flutter above μ ≈ 0.646. PBRAKE = a unit normal force on pad z.
pub fn coupling() -> StoredModel {
    let w2 = (2.0 * PI).powi(2);
    let kk = [[1.0, 0.3, 0.0], [0.3, 0.2, 0.0], [0.0, 0.0, 1.0]];
    StoredModel {
        k: Mat::from_fn(3, 3, |i, j| w2 * kk[i][j]),
        m: diag(&[1.0, 1.0, 0.5]),
        b: None,
        p_brake: vec![0.0, 1.0, 0.0],
        dofs: vec![(1, 2), (1, 3), (100_001, 3)],
        gaps: vec![(1, 100_001, [0.0, 0.0, 1.0], 1.0, 10.0)],
    }
}

/// Analytic root (σ 1/s, frequency Hz) of [`coupling`] with the largest real part at μ.
pub fn coupling_reference(mu: Real) -> (Real, Real) {
    let m_r = 0.5;
    let (a, b, c) = (
        1.0 + m_r,
        1.2 + (1.0 + m_r) + 0.3 * mu * m_r,
        1.2 - 0.3 * (0.3 - mu),
    );
    let d = b * b - 4.0 * a * c;
    // Roots s = (x, ±y) of the quadratic in s = (p/w0)².
    let roots: Vec<(Real, Real)> = if d < 0.0 {
        let y = (-d).sqrt() / (2.0 * a);
        vec![(-b / (2.0 * a), y), (-b / (2.0 * a), -y)]
    } else {
        vec![
            ((-b + d.sqrt()) / (2.0 * a), 0.0),
            ((-b - d.sqrt()) / (2.0 * a), 0.0),
        ]
    };
    let w0 = 2.0 * PI;
    roots
        .iter()
        .flat_map(|&(x, y)| {
            // Principal square root of x + iy, and its negative.
            let r = (x * x + y * y).sqrt();
            let re = ((r + x) / 2.0).sqrt();
            let im = ((r - x) / 2.0).sqrt().copysign(y);
            [(re, im), (-re, -im)]
        })
        .filter(|p| p.1 > 0.0)
        .map(|(re, im)| (w0 * re, w0 * im / (2.0 * PI)))
        .max_by(|x, y| x.0.total_cmp(&y.0))
        .unwrap_or((0.0, 0.0))
}

/// [`belt`] with a pad x DOF (k = 50, m = 1) and a second gap on the same pad and rotor grids
/// whose normal is tilted by `tilt` rad towards x (P0 = 0): G's two rows differ by O(tilt),
/// its condition number is O(1/tilt). Both constraints together hold pad x at rest, so the
/// y motion is the belt's: same σ and frequency ([`belt_reference`]).
/// DOFs: [pad x, pad y, pad z, rotor z].
pub fn belt_redundant(tilt: Real) -> StoredModel {
    let k = (2.0 * PI).powi(2);
    StoredModel {
        k: diag(&[50.0, k, 50.0, 50.0]),
        m: diag(&[1.0, 1.0, 2.0, 1.0]),
        b: Some(diag(&[0.0, 0.3, 0.0, 0.0])),
        p_brake: vec![0.0, 1.0, 0.0, 0.0],
        dofs: vec![(1, 1), (1, 2), (1, 3), (100_001, 3)],
        gaps: vec![
            (1, 100_001, [0.0, 0.0, 1.0], 1.0, 10.0),
            (1, 100_001, [tilt.sin(), 0.0, tilt.cos()], 1.0, 0.0),
        ],
    }
}

/// `count` belt-like pads in a row, each pad's y tied to its neighbours' by springs
/// k_c = 0.2·(2π)² (a chain: n = 3·count DOFs, `count` gaps); the pad masses and stiffnesses
/// vary ±20 % along the row so the modes are distinct. PBRAKE = a unit force on pad 0's y.
pub fn pad_row(count: usize) -> StoredModel {
    let n = 3 * count;
    let w2 = (2.0 * PI).powi(2);
    let mut k = Mat::zeros(n, n);
    let mut m = Mat::zeros(n, n);
    let mut b = Mat::zeros(n, n);
    let mut dofs = Vec::with_capacity(n);
    let mut gaps = Vec::new();
    let kc = 0.2 * w2;
    for p in 0..count {
        let f = 1.0 + 0.2 * ((p as Real) * 0.7).sin();
        let (y, z, r) = (3 * p, 3 * p + 1, 3 * p + 2);
        m[(y, y)] = f;
        m[(z, z)] = 2.0;
        m[(r, r)] = 1.0;
        k[(y, y)] += w2 * f;
        k[(z, z)] += 50.0;
        k[(r, r)] += 50.0;
        b[(y, y)] = 0.3 * f;
        if p + 1 < count {
            let y2 = 3 * (p + 1);
            k[(y, y)] += kc;
            k[(y2, y2)] += kc;
            k[(y, y2)] -= kc;
            k[(y2, y)] -= kc;
        }
        let (pg, rg) = (1 + p as u64, 100_001 + p as u64);
        dofs.extend([(pg, 2), (pg, 3), (rg, 3)]);
        gaps.push((pg, rg, [0.0, 0.0, 1.0], 1.0, 10.0));
    }
    let mut p_brake = vec![0.0; n];
    p_brake[0] = 1.0;
    StoredModel {
        k,
        m,
        b: Some(b),
        p_brake,
        dofs,
        gaps,
    }
}

fn diag(d: &[Real]) -> Mat<Real> {
    Mat::from_fn(d.len(), d.len(), |i, j| if i == j { d[i] } else { 0.0 })
}
