//! Hoffmann's 2-DOF mode-coupling model solved THROUGH squeal's contact formulation:
//! a `GapSet` (eqs. 1–7, 9) supplies G, D = ∂F_f/∂λ̇ and C_f = ∂F_f/∂v, and the null-space
//! CEA of `squeal_solver::cea` finds the critical friction coefficient.
//!
//! # Mapping (Hoffmann, Fischer, Gaul, Wagner, "A minimal model for studying properties
//! of the mode-coupling type instability in friction induced oscillations", Mech. Res.
//! Commun. 29, 2002)
//! Hoffmann's model: a unit mass with DOFs x (tangential) and z (normal), springs giving
//! `K = [[k11, k12], [k21, k22]]`, pressed on a belt by a normal spring k3 whose force k3·z
//! is the normal force increment; friction μ·k3·z acts along the belt, so
//! `K_eff = [[k11, k12 − μ k3], [k21, k22]]`.
//!
//! Here:
//! * DOF 0 = pad x, DOF 1 = pad z (pad y fixed); pad springs `[[k11, k12], [k21, k22 − k3]]`.
//! * DOF 2 = rotor z, a small mass m_r on a normal spring k3 (rotor x, y fixed); the rotor
//!   surface slides at v_slide = (1, 0, 0) (≫ 10·VTOL, so no regularisation).
//! * One gap, n = +z (pad below the rotor), A = 1: G = [0, −1, +1] (rotor − pad), so the pad
//!   and the rotor point move together normally: pad z-stiffness (k22 − k3) + k3 = k22.
//! * The constraint force: from the rotor row `m_r z̈_r + k3 z_r + N = 0`, so the tensile
//!   multiplier perturbation is N = −k3 z (m_r → 0); the compression is F_z = −N = k3 z and
//!   the friction on the pad is μ F_z = μ k3 z along +x. The contact crate gives exactly this
//!   through D = ∂F_f/∂λ̇ = (−μ, 0, 0) on the pad (x, z) and rotor z DOFs; C_f vanishes on the
//!   free DOFs (it only acts on the fixed pad y).
//! * Eliminating N and z_r: `ẍ + k11 x + (k12 − μ k3) z − μ m_r z̈ = 0`,
//!   `(1 + m_r) z̈ + k21 x + k22 z = 0`: Hoffmann's model up to O(m_r). With m_r = 1e-6 the
//!   critical μ moves by ~1e-6, far below the 1e-4 tolerance.
//!
//! Reference values (analytic; derived in `solver/tests/cea.rs`): μc = 1/3 undamped,
//! 0.3425 with c = 0.05 on both DOFs, 0.3 with c = 0.1 on x only.

use faer::Mat;
use squeal_contact::{ContactError, FrictionLaw, Gap, GapSet};
use squeal_solver::cea::{sweep, CeaMatrices, SweepOptions};

const K11: f64 = 1.0;
const K12: f64 = 0.3;
const K21: f64 = 0.3;
const K22: f64 = 1.2;
const K3: f64 = 1.0;
const M_R: f64 = 1e-6;

fn gap_set(mu: f64) -> Result<GapSet, ContactError> {
    let gap = Gap {
        pad_node: 1,
        rotor_node: 2,
        coords: [0.0; 3],
        pad_dofs: [Some(0), None, Some(1)],
        rotor_dofs: [None, None, Some(2)],
        normal: [0.0, 0.0, 1.0],
        area: 1.0,
        v_slide: [1.0, 0.0, 0.0],
        p0: 1.0,
        temperature: 0.0,
        tie: None,
        rotor_rows: Vec::new(),
        pad_side: None,
        friction: None,
    };
    GapSet::new(vec![gap], FrictionLaw::Constant { mu }, 1e-3)
}

/// Linearised matrices at the steady sliding state (v = 0, λ̇ = 0) for friction μ and
/// damping c1 (pad x), c2 (pad z).
fn build(mu: f64, c1: f64, c2: f64) -> Result<CeaMatrices, ContactError> {
    let set = gap_set(mu)?;
    let (v, lam) = ([0.0; 3], [0.0]);
    let mut d = Mat::zeros(3, 1);
    let mut c_f = Mat::zeros(3, 3);
    set.add_tangents(&v, &lam, &mut d, Some(&mut c_f))?;
    let k = [[K11, K12, 0.0], [K21, K22 - K3, 0.0], [0.0, 0.0, K3]];
    let mut s = CeaMatrices::new(
        Mat::from_fn(3, 3, |i, j| if i == j { [1.0, 1.0, M_R][i] } else { 0.0 }),
        Mat::from_fn(3, 3, |i, j| k[i][j]),
    );
    s.b = Some(Mat::from_fn(3, 3, |i, j| {
        if i == j {
            [c1, c2, 0.0][i]
        } else {
            0.0
        }
    }));
    s.g = Some(set.constraint_matrix(3)?);
    s.d = Some(d);
    s.c_f = Some(c_f);
    Ok(s)
}

fn critical_mu(c1: f64, c2: f64) -> f64 {
    let mus: Vec<f64> = (0..26).map(|i| 0.2 + 0.01 * i as f64).collect();
    let s = sweep(|mu| build(mu, c1, c2), &mus, &SweepOptions::default()).unwrap();
    let (_, c) = s.lowest_critical().expect("an onset inside the sweep");
    eprintln!(
        "c1 = {c1}, c2 = {c2}: critical mu = {:.8}, omega = {:.8}",
        c.mu,
        2.0 * std::f64::consts::PI * c.frequency_hz
    );
    c.mu
}

#[test]
fn contact_tangents_have_hoffmann_structure() {
    let s = build(0.4, 0.0, 0.0).unwrap();
    let (g, d, c_f) = (s.g.unwrap(), s.d.unwrap(), s.c_f.unwrap());
    assert_eq!((g[(0, 0)], g[(0, 1)], g[(0, 2)]), (0.0, -1.0, 1.0));
    assert!((d[(0, 0)] + 0.4).abs() < 1e-15 && d[(1, 0)] == 0.0 && d[(2, 0)] == 0.0);
    for i in 0..3 {
        for j in 0..3 {
            assert!(c_f[(i, j)].abs() < 1e-15);
        }
    }
}

#[test]
fn hoffmann_through_contact_undamped() {
    assert!((critical_mu(0.0, 0.0) - 1.0 / 3.0).abs() < 1e-4);
}

#[test]
fn hoffmann_through_contact_equal_damping() {
    assert!((critical_mu(0.05, 0.05) - 0.3425).abs() < 1e-4);
}

#[test]
fn hoffmann_through_contact_damping_destabilises() {
    assert!((critical_mu(0.1, 0.0) - 0.3).abs() < 1e-4);
}
