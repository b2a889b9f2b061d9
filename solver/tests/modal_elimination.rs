//! The Craig–Bampton modal block eliminated before the LU (`BsqlSystem::set_modal_elimination`)
//! against the whole system factorised: a two-component model in Craig–Bampton form (boundary
//! DOFs coupled densely, unit-mass modal DOFs with diagonal stiffness coupled by mass with
//! their own component's boundary only), one contact constraint between the components'
//! normal DOFs and falling friction on the pad's tangential DOF (the belt of
//! `bsql_verification.rs`, there with a flexible pad and rotor). The two paths must give the
//! same steps and the same states to round-off; the reference is the dense LU of the whole
//! (n + ng) system, the path every run took before the elimination.

mod common;

use common::{max_rel_diff, BeltFriction};
use faer::Mat;
use squeal_solver::bsql::{BsqlOptions, BsqlSystem, FrictionForces, LoadHistory};
use squeal_solver::{Real, SolverError};

/// DOFs: pad boundary {0: x (friction), 1: z (contact)}, pad modes {2, 3}; rotor boundary
/// {4: z (contact), 5: x}, rotor modes {6, 7, 8}.
const PAD_B: [usize; 2] = [0, 1];
const PAD_Q: [usize; 2] = [2, 3];
const ROT_B: [usize; 2] = [4, 5];
const ROT_Q: [usize; 3] = [6, 7, 8];

#[allow(non_snake_case)]
fn matrices() -> (Mat<Real>, Mat<Real>, Mat<Real>, Mat<Real>) {
    let n = 9;
    let mut M = Mat::zeros(n, n);
    let mut K = Mat::zeros(n, n);
    let comps: [(&[usize], &[usize], Real); 2] = [(&PAD_B, &PAD_Q, 1.0), (&ROT_B, &ROT_Q, 3.0)];
    for (c, (bnd, modes, scale)) in comps.into_iter().enumerate() {
        // Boundary block: SPD, coupled.
        let (i, j) = (bnd[0], bnd[1]);
        M[(i, i)] = 1.0 * scale;
        M[(j, j)] = 1.2 * scale;
        M[(i, j)] = 0.1 * scale;
        M[(j, i)] = 0.1 * scale;
        K[(i, i)] = 40.0 * scale;
        K[(j, j)] = 60.0 * scale;
        K[(i, j)] = -10.0 * scale;
        K[(j, i)] = -10.0 * scale;
        for (r, &q) in modes.iter().enumerate() {
            M[(q, q)] = 1.0;
            K[(q, q)] = (2.0 * std::f64::consts::PI * (3.0 + 2.0 * r as Real + c as Real)).powi(2);
            for (s, &b) in bnd.iter().enumerate() {
                let x = 0.15 * (1.0 + r as Real) * if s == 0 { 1.0 } else { -0.7 };
                M[(b, q)] = x;
                M[(q, b)] = x;
            }
        }
    }
    let B = Mat::from_fn(n, n, |i, j| 2e-3 * K[(i, j)]);
    let mut G = Mat::zeros(1, n);
    G[(0, 4)] = 1.0; // (u_rotor − u_pad)·n
    G[(0, 1)] = -1.0;
    (M, B, K, G)
}

/// The model with `friction` and N = 10 pressing the pad on the rotor.
fn system<F: FrictionForces>(friction: F) -> BsqlSystem<F> {
    let (m, b, k, g) = matrices();
    let mut p = vec![0.0; 9];
    p[1] = 10.0; // pad pushed towards the rotor (+z)
    p[4] = -10.0; // reaction on the rotor side
    let load = LoadHistory {
        p_pre: p,
        ..Default::default()
    };
    BsqlSystem::new(m, b, k, g, load, friction, BsqlOptions::default()).unwrap()
}

fn belt() -> BeltFriction {
    BeltFriction {
        mu0: 0.5,
        a: 0.5,
        v_belt: 1.0,
    }
}

/// Steady state, a kick on the pad's tangential velocity, consistent y'; then BDF2 to t = 3
/// (about ten periods of the lowest mode). Returns (final y, steps, Newton iterations).
fn run<F: FrictionForces>(sys: &mut BsqlSystem<F>) -> (Vec<Real>, u64, u64) {
    common::kicked_run(sys, 3.0)
}

#[test]
fn the_modal_block_is_found_and_kept_clear_of_the_friction_dofs() {
    let mut sys = system(belt());
    // By pattern: the five modal DOFs (the tangential DOFs 0 and 5 carry no constraint, but
    // each couples with its component's modes, which go first).
    let (d, groups, _) = sys.modal_elimination();
    assert_eq!((d, groups), (5, 2));
    let (y_elim, steps_elim, newton_elim) = run(&mut sys);
    assert_eq!(sys.stats().eliminated_dofs, 5);
    assert_eq!(sys.stats().modal_redetections, 0);
    let mut dense = system(belt());
    dense.set_modal_elimination(false);
    assert_eq!(dense.modal_elimination().0, 0);
    let (y_dense, steps_dense, newton_dense) = run(&mut dense);
    let moved = max_rel_diff(&y_elim, &y_dense);
    println!(
        "elimination: {steps_elim} steps, {newton_elim} Newton; dense: {steps_dense} steps, \
         {newton_dense} Newton; final states differ by {moved:.2e}"
    );
    assert_eq!(steps_elim, steps_dense);
    assert_eq!(newton_elim, newton_dense);
    // Round-off of a different factorisation, grown over ~1000 steps of a growing response.
    assert!(moved < 1e-9, "moved {moved:e}");
    // The response did something (the kick grew or decayed, it did not stay at zero).
    assert!(y_elim[0].abs() > 1e-6);
}

/// Friction on a modal DOF (not a Craig–Bampton model's way, but a friction callback may
/// touch any DOF): the set-up sees it, keeps that DOF, finds the block again, and the results
/// still match the dense path.
struct ModalDrag(BeltFriction);

impl FrictionForces for ModalDrag {
    fn add_forces(
        &mut self,
        t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        self.0.add_forces(t, v, lambda_dot, f)?;
        f[7] -= 0.05 * lambda_dot[0] * v[7];
        Ok(())
    }
    fn add_tangents(
        &mut self,
        t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        let mut d_dv = d_dv;
        if let Some(d) = d_dv.as_mut() {
            d[(7, 7)] -= 0.05 * lambda_dot[0];
        }
        self.0.add_tangents(t, v, lambda_dot, d_dlam, d_dv)?;
        d_dlam[(7, 0)] -= 0.05 * v[7];
        Ok(())
    }
}

#[test]
fn friction_on_an_eliminated_dof_keeps_it_and_matches_the_dense_path() {
    let mut sys = system(ModalDrag(belt()));
    assert_eq!(sys.modal_elimination().0, 5);
    let (y_elim, steps_elim, _) = run(&mut sys);
    assert!(sys.stats().modal_redetections >= 1);
    assert_eq!(sys.stats().eliminated_dofs, 4, "DOF 7 kept");
    let mut dense = system(ModalDrag(belt()));
    dense.set_modal_elimination(false);
    let (y_dense, steps_dense, _) = run(&mut dense);
    assert_eq!(steps_elim, steps_dense);
    let moved = max_rel_diff(&y_elim, &y_dense);
    assert!(moved < 1e-9, "moved {moved:e}");
}

#[test]
fn a_model_without_a_diagonal_block_is_factorised_whole() {
    // Modal damping couples every mode with every other: no DOF can be eliminated.
    let (m, _, k, g) = matrices();
    let b = Mat::from_fn(9, 9, |_, _| 1e-3);
    let sys = BsqlSystem::new(
        m,
        b,
        k,
        g,
        LoadHistory::default(),
        belt(),
        BsqlOptions::default(),
    )
    .unwrap();
    assert_eq!(sys.modal_elimination().0, 0);
    assert_eq!(sys.stats().eliminated_dofs, 0);
}
