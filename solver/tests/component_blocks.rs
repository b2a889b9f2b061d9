//! The saddle matrix factorised by component blocks (`BsqlSystem::set_component_blocks`)
//! against one LU of the whole: a brake-like model of two pads, a caliper reduced to one
//! fixed-interface mode that couples the two pads (by mass), and a rotor with two modes; each pad
//! meets the rotor only through its contact row, with falling friction on the pad's
//! tangential DOF. The blocks are {pad A}, {pad B} and {rotor}; the caliper mode bridges the
//! pads and goes to the border with the two multipliers. The reference is the dense LU of the
//! whole (n + ng) system (`set_modal_elimination(false)`, the path before any elimination);
//! the block path must give the same steps, Newton iterations and states to round-off, also
//! when a friction damping C_f couples pad and rotor (the set-up then falls back to the
//! whole matrix).

mod common;

use common::max_rel_diff;

use faer::Mat;
use squeal_solver::bsql::{BsqlOptions, BsqlSystem, FrictionForces, LoadHistory};
use squeal_solver::{Real, SolverError};

/// DOFs: pad A {0: x, 1: z}, pad B {2: x, 3: z}, caliper mode {4}, rotor {5: z top, 6: z bottom,
/// 7: x}, rotor modes {8, 9}.
const N: usize = 10;

#[allow(non_snake_case)]
fn matrices() -> (Mat<Real>, Mat<Real>, Mat<Real>, Mat<Real>) {
    let mut M = Mat::zeros(N, N);
    let mut K = Mat::zeros(N, N);
    // Pads: coupled 2 x 2 boundary blocks.
    for (i, j, s) in [(0, 1, 1.0), (2, 3, 1.3)] {
        M[(i, i)] = 1.0 * s;
        M[(j, j)] = 1.2 * s;
        M[(i, j)] = 0.1 * s;
        M[(j, i)] = 0.1 * s;
        K[(i, i)] = 40.0 * s;
        K[(j, j)] = 60.0 * s;
        K[(i, j)] = -10.0 * s;
        K[(j, i)] = -10.0 * s;
    }
    // Caliper mode: unit mass, diagonal stiffness, mass coupling with both pads' DOFs.
    M[(4, 4)] = 1.0;
    K[(4, 4)] = (2.0 * std::f64::consts::PI * 4.0).powi(2);
    for (b, x) in [(0, 0.12), (1, -0.08), (2, 0.1), (3, 0.09)] {
        M[(b, 4)] = x;
        M[(4, b)] = x;
    }
    // Rotor boundary 3 x 3, two modes coupled by mass with it.
    let rb = [5, 6, 7];
    for (p, &i) in rb.iter().enumerate() {
        for (q, &j) in rb.iter().enumerate() {
            M[(i, j)] = if p == q { 3.0 } else { 0.2 };
            K[(i, j)] = if p == q { 150.0 } else { -30.0 };
        }
    }
    for (r, q) in [8, 9].into_iter().enumerate() {
        M[(q, q)] = 1.0;
        K[(q, q)] = (2.0 * std::f64::consts::PI * (5.0 + 2.0 * r as Real)).powi(2);
        for (s, &b) in rb.iter().enumerate() {
            let x = 0.1 * (1.0 + r as Real) * (1.0 - 0.4 * s as Real);
            M[(b, q)] = x;
            M[(q, b)] = x;
        }
    }
    let B = Mat::from_fn(N, N, |i, j| 2e-3 * K[(i, j)]);
    let mut G = Mat::zeros(2, N);
    G[(0, 5)] = 1.0; // (u_rotor − u_pad)·n, pad A on top
    G[(0, 1)] = -1.0;
    G[(1, 6)] = -1.0; // pad B below, normal −z
    G[(1, 3)] = 1.0;
    (M, B, K, G)
}

/// Falling friction on each pad's tangential DOF, F = (μ0 − a v_rel) λ'_k with v_rel the belt
/// speed minus the pad's velocity, or (`relative`) minus the pad's velocity relative to the
/// rotor's tangential DOF 7 (then C_f couples pad and rotor).
struct PadFriction {
    relative: bool,
}

impl PadFriction {
    fn v_rel(&self, v: &[Real], pad: usize) -> Real {
        1.0 - v[pad] + if self.relative { v[7] } else { 0.0 }
    }
}

impl FrictionForces for PadFriction {
    fn add_forces(
        &mut self,
        _t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        for (k, pad) in [(0, 0), (1, 2)] {
            let force = (0.5 - 0.5 * self.v_rel(v, pad)) * lambda_dot[k];
            f[pad] += force;
            if self.relative {
                f[7] -= force;
            }
        }
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        let mut d_dv = d_dv;
        for (k, pad) in [(0, 0), (1, 2)] {
            let mu = 0.5 - 0.5 * self.v_rel(v, pad);
            d_dlam[(pad, k)] += mu;
            if self.relative {
                d_dlam[(7, k)] -= mu;
            }
            if let Some(d) = d_dv.as_mut() {
                let c = 0.5 * lambda_dot[k]; // ∂F/∂v_pad
                d[(pad, pad)] += c;
                if self.relative {
                    d[(pad, 7)] -= c;
                    d[(7, pad)] -= c;
                    d[(7, 7)] += c;
                }
            }
        }
        Ok(())
    }
}

fn system(relative: bool, include_cf: bool) -> BsqlSystem<PadFriction> {
    let (m, b, k, g) = matrices();
    let mut p = vec![0.0; N];
    p[1] = 10.0; // pad A pushed down onto the rotor
    p[3] = -8.0; // pad B pushed up
    let load = LoadHistory {
        p_pre: p,
        ..Default::default()
    };
    let opts = BsqlOptions {
        include_friction_damping: include_cf,
        ..Default::default()
    };
    BsqlSystem::new(m, b, k, g, load, PadFriction { relative }, opts).unwrap()
}

/// Steady state, a kick on pad A's tangential velocity, consistent y'; BDF2 to t = 2.
/// Returns (final y, steps, Newton iterations).
fn run<F: FrictionForces>(sys: &mut BsqlSystem<F>) -> (Vec<Real>, u64, u64) {
    common::kicked_run(sys, 2.0)
}

#[test]
fn pads_and_rotor_are_factorised_apart_and_match_the_whole_lu() {
    let mut sys = system(false, false);
    // Pad A, pad B, rotor (its modes eliminated or in its block); the caliper mode and the
    // two multipliers in the border.
    let (sizes, border) = sys.component_block_sizes().expect("blocks found");
    assert_eq!(sizes.len(), 3, "{sizes:?}");
    assert_eq!(border, 3, "caliper mode + 2 multipliers");
    assert_eq!(sys.stats().component_blocks, 3);
    let (y_blk, steps_blk, newton_blk) = run(&mut sys);
    assert_eq!(sys.stats().block_fallbacks, 0);
    assert!(sys.component_block_sizes().is_some());
    let mut dense = system(false, false);
    dense.set_modal_elimination(false);
    assert!(dense.component_block_sizes().is_none());
    let (y_dense, steps_dense, newton_dense) = run(&mut dense);
    let mut elim_only = system(false, false);
    elim_only.set_component_blocks(false);
    assert!(elim_only.component_block_sizes().is_none());
    let (y_elim, steps_elim, _) = run(&mut elim_only);
    let moved = max_rel_diff(&y_blk, &y_dense);
    println!(
        "blocks: {steps_blk} steps, {newton_blk} Newton; whole LU: {steps_dense} steps, \
         {newton_dense} Newton; final states differ by {moved:.2e}"
    );
    assert_eq!((steps_blk, newton_blk), (steps_dense, newton_dense));
    assert_eq!(steps_elim, steps_dense);
    // Round-off of a different factorisation, grown over the run.
    assert!(moved < 1e-9, "moved {moved:e}");
    assert!(max_rel_diff(&y_elim, &y_dense) < 1e-9);
    // The kick did something.
    assert!(y_blk[0].abs() > 1e-6);
}

#[test]
fn a_friction_damping_coupling_pad_and_rotor_falls_back_to_the_whole_lu() {
    // C_f in every matrix, with entries between the pads' and the rotor's tangential DOFs.
    let mut sys = system(true, true);
    assert!(sys.component_block_sizes().is_some());
    let (y_blk, steps_blk, _) = run(&mut sys);
    assert!(sys.stats().block_fallbacks > 0);
    let mut dense = system(true, true);
    dense.set_modal_elimination(false);
    let (y_dense, steps_dense, _) = run(&mut dense);
    assert_eq!(steps_blk, steps_dense);
    let moved = max_rel_diff(&y_blk, &y_dense);
    assert!(moved < 1e-9, "moved {moved:e}");
}

#[test]
fn without_friction_damping_the_relative_friction_keeps_the_blocks() {
    // The same friction with the paper's matrix (no C_f): D sits in the multiplier columns
    // (pad and rotor rows), which the border takes; no fall-back.
    let mut sys = system(true, false);
    let (y_blk, _, _) = run(&mut sys);
    let stats = sys.stats().clone();
    let mut dense = system(true, false);
    dense.set_modal_elimination(false);
    let (y_dense, _, _) = run(&mut dense);
    assert!(max_rel_diff(&y_blk, &y_dense) < 1e-9);
    // C_f may have been switched on by a Newton failure (friction_damping_after_failure);
    // only then may a set-up fall back.
    assert!(stats.block_fallbacks == 0 || stats.friction_damping_after_failure > 0);
}

#[test]
fn a_block_singular_alone_falls_back_to_the_whole_lu() {
    use squeal_solver::bdf::DaeSystem;
    // Pad A's normal DOF massless and uncoupled in M: ∂F/∂y' (A = M) has a singular pad-A
    // block, while the saddle matrix [M, Gᵀ; G, 0] is regular (G holds that DOF).
    let build = || {
        let (mut m, b, k, g) = matrices();
        for j in 0..N {
            m[(1, j)] = 0.0;
            m[(j, 1)] = 0.0;
        }
        BsqlSystem::new(
            m,
            b,
            k,
            g,
            LoadHistory::default(),
            PadFriction { relative: false },
            BsqlOptions::default(),
        )
        .unwrap()
    };
    let mut sys = build();
    assert!(sys.component_block_sizes().is_some());
    let mut dense = build();
    dense.set_modal_elimination(false);
    let len = 2 * N + 2;
    let y = vec![0.0; len];
    let mut yp = vec![0.0; len];
    yp[N] = 1.0; // λ'
    yp[N + 1] = 0.5;
    let rhs: Vec<Real> = (0..len).map(|i| (0.3 * i as Real).sin()).collect();
    let solve = |s: &mut BsqlSystem<PadFriction>| {
        assert!(s.setup_derivative_jacobian(0.0, &y, &yp).unwrap());
        let mut x = rhs.clone();
        s.solve_jacobian(&mut x).unwrap();
        x
    };
    let x = solve(&mut sys);
    assert_eq!(sys.stats().block_fallbacks, 1);
    let want = solve(&mut dense);
    assert!(max_rel_diff(&x, &want) < 1e-12);
}
