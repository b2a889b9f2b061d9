//! The projection basis by shift-invert Lanczos with an inertia count (`basis_solver = "auto"`)
//! against the dense symmetric eigendecomposition (`basis_solver = "dense"`, the reference), and
//! the projected + refined CEA on that basis against the exact dense CEA, root by root.

use squeal_solver::cea::{
    complex_eigen, BasisSolver, CeaMatrices, CeaMethod, CeaOptions, ModalBasis, Mode,
    ProjectionOptions,
};

mod common;
use common::random::RandomConstrained;

/// n DOFs, ng random constraints at friction coefficient μ (`common::random`).
fn random_constrained(n: usize, ng: usize, mu: f64, seed: u64) -> CeaMatrices {
    RandomConstrained::new(n, ng, seed).at(mu)
}

fn opts(band: f64, solver: BasisSolver) -> CeaOptions {
    CeaOptions {
        method: CeaMethod::Projection,
        projection: ProjectionOptions {
            frequency_max_hz: Some(band),
            cutoff_factor: 2.0,
            basis_solver: solver,
            ..ProjectionOptions::default()
        },
        ..CeaOptions::default()
    }
}

/// A 400-DOF model with 20 constraints at μ = 2, band = the 25th exact root's frequency, basis
/// cut at twice that (56 of the 380 constrained modes, so the Lanczos path runs). Both bases
/// have the same number of modes (the inertia count), the same frequencies (1e-8 relative below
/// half the cutoff, where the Ritz pairs are converged to 1e-8; above it they need not be, and
/// agree to 7e-4 here: 1e-2 asserted, each below the cutoff) and span the same
/// space (the M-orthogonal projection of each dense mode on the Lanczos basis keeps its M-norm
/// to 1e-6 below half the cutoff). The projected + refined CEA on the Lanczos basis has every
/// unstable in-band root of the dense exact CEA to 1e-9 relative, and no other.
#[test]
fn lanczos_basis_equals_the_dense_basis_and_refined_roots_equal_the_dense_roots() {
    let sys = random_constrained(400, 20, 2.0, 0x5eed_0bad_cafe_0002);
    let e = complex_eigen(&sys, &CeaOptions::default()).unwrap();
    assert_eq!(e.stats.method, CeaMethod::Exact);
    let complex: Vec<&Mode> = e.modes.iter().filter(|m| m.frequency_hz > 0.0).collect();
    let band = complex[24].frequency_hz * 1.001;

    let dense = ModalBasis::new(&sys, &opts(band, BasisSolver::Dense)).unwrap();
    let fast = ModalBasis::new(&sys, &opts(band, BasisSolver::Auto)).unwrap();
    eprintln!("basis: {} modes (dense {})", fast.len(), dense.len());
    assert!(
        dense.len() <= 380 / 4,
        "the Lanczos path must run: {}",
        dense.len()
    );
    assert_eq!(fast.len(), dense.len());
    let fc = 2.0 * band;
    for (a, b) in fast.frequencies_hz().iter().zip(dense.frequencies_hz()) {
        let rel = (a - b).abs() / b.max(1e-300);
        let tol = if *b <= 0.5 * fc { 1e-8 } else { 1e-2 };
        assert!(*a <= fc * (1.0 + 1e-9));
        assert!(rel < tol, "{a} Hz against {b} Hz ({rel:e})");
    }
    // Same subspace: ‖Ψ_fᵀ M ψ_d‖ = ‖ψ_d‖_M = 1 for the dense modes below half the cutoff.
    let (pf, pd) = (fast.vectors(), dense.vectors());
    let g = sys.g.as_ref().unwrap();
    let cons = |p: faer::MatRef<'_, f64>| (g * p).norm_l2() / (g.norm_l2() * p.norm_l2());
    eprintln!("G psi: fast {:e}, dense {:e}", cons(pf), cons(pd));
    assert!(cons(pf) < 1e-12, "{:e}", cons(pf));
    let c = pf.transpose() * (&sys.m * pd);
    for (j, f) in dense.frequencies_hz().iter().enumerate() {
        if *f <= 0.5 * fc {
            let kept = c.col(j).norm_l2();
            assert!((kept - 1.0).abs() < 1e-6, "dense mode {j} ({f} Hz): {kept}");
        }
    }

    let p = complex_eigen(&sys, &opts(band, BasisSolver::Auto)).unwrap();
    let st = p.stats.refine.as_ref().expect("refinement ran");
    assert_eq!(st.n_failed, 0);
    let unstable = |modes: &[Mode]| -> Vec<Mode> {
        modes
            .iter()
            .filter(|m| m.unstable && m.frequency_hz <= band)
            .cloned()
            .collect()
    };
    let (exact, got) = (unstable(&e.modes), unstable(&p.modes));
    eprintln!(
        "{} exact unstable in-band roots; targets {}, shifts {}, applications {}",
        exact.len(),
        st.n_targets,
        st.n_shifts,
        st.n_applications
    );
    assert!(!exact.is_empty());
    assert_eq!(got.len(), exact.len());
    for x in &exact {
        let d = got
            .iter()
            .map(|r| (r.eigenvalue - x.eigenvalue).norm() / x.eigenvalue.norm())
            .fold(f64::INFINITY, f64::min);
        assert!(
            d < 1e-9,
            "exact root {}: nearest refined {d:e}",
            x.eigenvalue
        );
    }
}
