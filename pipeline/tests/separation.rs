//! Hoffmann's mode-coupling model above its critical μ, with unilateral contact: the
//! flutter grows until the gap separates, then settles into a limit cycle, through squeal's
//! contact formulation (a `GapSet` as the friction callback), the solver's events and the
//! pipeline's limit-cycle analysis.
//!
//! Model (as `contact/tests/hoffmann.rs`, Hoffmann et al., Mech. Res. Commun. 29, 2002): DOF 0
//! pad x, DOF 1 pad z, DOF 2 a rotor point z of mass m_r on the normal spring k3 with a
//! damper c_r (m_r = 0.05 instead of 1e-6 so that the free rotor point is integrable after
//! separation); one gap, n = +z, A = 1, preload P0, rotor sliding at 1 along x, constant μ.

use faer::Mat;
use squeal_contact::{FrictionLaw, Gap, GapSet};
use squeal_pipeline::stages::transient::limit_cycle;
use squeal_pipeline::stages::transient::system::GapFriction;
use squeal_solver::bdf::{consistent_initial_conditions, Bdf, BdfOptions};
use squeal_solver::bsql::{
    steady_state, BsqlOptions, BsqlSystem, EnergyBalance, LoadHistory, Unilateral,
    UnilateralOptions,
};
use squeal_solver::cea::{complex_eigen, CeaMatrices, CeaOptions};

type Real = f64;

const K11: Real = 1.0;
const K12: Real = 0.3;
const K21: Real = 0.3;
const K22: Real = 1.2;
const K3: Real = 1.0;
const M_R: Real = 0.05;
const C_R: Real = 0.05;
const C_PAD: Real = 0.02;
const P0: Real = 0.2;
const MU: Real = 0.6;

fn gaps() -> GapSet {
    let gap = Gap {
        pad_node: 1,
        rotor_node: 2,
        coords: [0.0; 3],
        pad_dofs: [Some(0), None, Some(1)],
        rotor_dofs: [None, None, Some(2)],
        normal: [0.0, 0.0, 1.0],
        area: 1.0,
        v_slide: [1.0, 0.0, 0.0],
        p0: P0,
        temperature: 0.0,
    };
    GapSet::new(vec![gap], FrictionLaw::Constant { mu: MU }, 1e-3).unwrap()
}

#[allow(non_snake_case)]
fn matrices() -> (Mat<Real>, Mat<Real>, Mat<Real>) {
    let k = [[K11, K12, 0.0], [K21, K22 - K3, 0.0], [0.0, 0.0, K3]];
    let M = Mat::from_fn(3, 3, |i, j| if i == j { [1.0, 1.0, M_R][i] } else { 0.0 });
    let B = Mat::from_fn(
        3,
        3,
        |i, j| {
            if i == j {
                [C_PAD, C_PAD, C_R][i]
            } else {
                0.0
            }
        },
    );
    let K = Mat::from_fn(3, 3, |i, j| k[i][j]);
    (M, B, K)
}

#[test]
#[allow(non_snake_case)]
fn hoffmann_above_critical_mu_settles_into_a_limit_cycle_with_separation() {
    let set = gaps();
    let (M, B, K) = matrices();
    let G = set.constraint_matrix(3).unwrap();
    // The steady sliding state is unstable at this μ: a CEA root with positive real part.
    let mut d = Mat::zeros(3, 1);
    let mut c_f = Mat::zeros(3, 3);
    set.add_tangents(&[0.0; 3], &[0.0], &mut d, Some(&mut c_f))
        .unwrap();
    let mut cea = CeaMatrices::new(M.clone(), K.clone());
    cea.b = Some(B.clone());
    cea.g = Some(G.clone());
    cea.d = Some(d);
    cea.c_f = Some(c_f);
    let roots = complex_eigen(&cea, &CeaOptions::default()).unwrap();
    let growth = roots
        .modes
        .iter()
        .map(|m| m.eigenvalue.re)
        .fold(Real::NEG_INFINITY, Real::max);
    println!("CEA: largest real part {growth:.5}");
    assert!(
        growth > 0.0,
        "the steady state must be unstable at μ = {MU}"
    );

    let mut sys = BsqlSystem::new(
        M,
        B,
        K,
        G,
        LoadHistory::default(),
        GapFriction { set: set.clone() },
        BsqlOptions::default(),
    )
    .unwrap();
    let st = steady_state(&mut sys, 0.0, &Default::default()).unwrap();
    // Perturb the pad's normal velocity; λ = 0.
    let mut y = sys.join(&[0.0, 1e-3, 1e-3], &[0.0], &st.u);
    let mut yp = vec![0.0; y.len()];
    consistent_initial_conditions(&mut sys, 0.0, &mut y, &mut yp, None, &Default::default())
        .unwrap();
    let opts = BdfOptions {
        tolerances: sys.tolerances(1e-6, 1e-9, 1e-6, 1e20),
        max_steps: 200_000,
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y, &yp).unwrap();
    let mut uni = Unilateral::new(
        &mut sys,
        vec![P0 * 1.0],
        None,
        &y,
        &yp,
        UnilateralOptions::default(),
    )
    .unwrap();
    let mut bal = EnergyBalance::new();
    bal.push(&sys.observe(0.0, &y, &yp).unwrap());
    let (mut t_rec, mut peak, mut ms, mut vz) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let t_end = 400.0;
    let status = uni
        .step_to(&mut bdf, &mut sys, t_end, |s, t, y, yp| {
            bal.push(&s.observe(t, y, yp)?);
            // Rotor friction face normal velocity: v_rotor · n = v[2].
            t_rec.push(t);
            peak.push(y[2].abs());
            ms.push(y[2] * y[2]);
            vz.push(y[2]);
            Ok(true)
        })
        .unwrap();
    assert!(status.is_success(), "{status:?}");
    bal.impact_dissipated = uni.stats().impact_dissipated;
    let ev = uni.stats().clone();
    // Frequency of the cycle from the upward zero crossings of the rotor velocity over the
    // last half of the run.
    let half = t_rec.partition_point(|&t| t < 0.5 * t_end);
    let ups: Vec<Real> = (half + 1..t_rec.len())
        .filter(|&i| vz[i - 1] < 0.0 && vz[i] >= 0.0)
        .map(|i| t_rec[i])
        .collect();
    assert!(ups.len() >= 3, "no oscillation in the second half");
    let f = (ups.len() - 1) as Real / (ups[ups.len() - 1] - ups[0]);
    let lc = limit_cycle::analyse(&t_rec, &peak, &ms, 0.0, f).expect("cycles recorded");
    println!(
        "frequency {f:.5} Hz\nevents {ev:?}\nlimit cycle {lc:?}\nenergy: friction work {:.6e}, damping {:.6e}, impact \
         {:.6e}, ΔE {:.6e}, constraint work {:.6e}, residual {:.3e}, quadrature error {:.3e}",
        bal.friction_work,
        bal.damping_dissipated,
        bal.impact_dissipated,
        bal.kinetic + bal.strain - bal.initial_energy,
        bal.constraint_work,
        bal.residual(),
        bal.quadrature_error
    );
    assert!(ev.openings >= 10 && ev.closings >= 10, "{ev:?}");
    assert!(lc.reached, "{lc:?}");
    // Friction work = damping + impact dissipation + change of energy (+ the preload's work
    // on the open gap, the constraint work), to the integration accuracy.
    assert!(
        bal.residual().abs() < 1e-3 * bal.friction_work,
        "energy residual {:e} vs friction work {:e}",
        bal.residual(),
        bal.friction_work
    );
}
