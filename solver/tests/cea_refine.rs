//! The projected CEA with exact refinement (`method = "projection"`, `projection.refine`)
//! against the exact dense CEA (the reference) on small models: every in-band unstable root
//! after refinement equals the dense root to round-off, its shape is the dense shape, and the
//! statistics report what ran.

use squeal_solver::cea::{
    complex_eigen, mac, CeaMatrices, CeaMethod, CeaOptions, Mode, ProjectionOptions, RefineOptions,
};

mod common;
use common::random::RandomConstrained;

/// n DOFs, ng random constraints at friction coefficient μ (`common::random`).
fn random_constrained(n: usize, ng: usize, mu: f64, seed: u64) -> CeaMatrices {
    RandomConstrained::new(n, ng, seed).at(mu)
}

fn nearest(modes: &[Mode], p: squeal_solver::cea::Cplx) -> &Mode {
    modes
        .iter()
        .min_by(|a, b| {
            (a.eigenvalue - p)
                .norm()
                .total_cmp(&(b.eigenvalue - p).norm())
        })
        .unwrap()
}

/// Random 150-DOF model with 12 constraints at μ = 2: the unsymmetric friction stiffness is
/// strong enough to make 7 roots of the band (the lowest quarter of the spectrum) unstable,
/// and to make a basis cut at 2× the band err by up to 5 % on them (the projected roots even
/// pair up with the wrong exact roots). After refinement (plain Arnoldi, and band Arnoldi of
/// block 4; with the constraint and multipliers eliminated by slave DOFs, an LU of size
/// n − ng = 138, and with the bordered LU of size n + ng = 162) every exact unstable in-band
/// root is in the result to 1e-9 relative with its exact shape (MAC > 1 − 1e-8), every
/// unstable in-band root of the result is an exact root, and the backward errors are at
/// round-off.
#[test]
fn refined_roots_equal_the_dense_roots() {
    let sys = random_constrained(150, 12, 2.0, 0x5eed_1234_abcd_0001);
    // The reference: the exact dense CEA (constraint eliminated, all 138 roots).
    let e = complex_eigen(&sys, &CeaOptions::default()).unwrap();
    assert_eq!(e.stats.method, CeaMethod::Exact);
    let band = 0.25 * e.modes.last().unwrap().frequency_hz;
    let in_band_unstable = |modes: &[Mode]| -> Vec<Mode> {
        modes
            .iter()
            .filter(|m| m.unstable && m.frequency_hz <= band)
            .cloned()
            .collect()
    };
    let exact = in_band_unstable(&e.modes);
    assert_eq!(exact.len(), 7);
    let projection = ProjectionOptions {
        frequency_max_hz: Some(band),
        cutoff_factor: 2.0,
        ..ProjectionOptions::default()
    };
    let opts = CeaOptions {
        method: CeaMethod::Projection,
        projection: projection.clone(),
        ..CeaOptions::default()
    };
    let plain = complex_eigen(
        &sys,
        &CeaOptions {
            projection: ProjectionOptions {
                refine: RefineOptions {
                    enabled: false,
                    ..RefineOptions::default()
                },
                ..projection
            },
            ..opts.clone()
        },
    )
    .unwrap();
    assert!(plain.stats.refine.is_none());
    let err_plain = exact
        .iter()
        .map(|x| {
            (nearest(&plain.modes, x.eigenvalue).eigenvalue - x.eigenvalue).norm()
                / x.eigenvalue.norm()
        })
        .fold(0.0, f64::max);
    assert!(
        err_plain > 1e-3,
        "the projection alone is not exact here: {err_plain:e}"
    );

    // Plain Arnoldi (block 1) and the default band Arnoldi (block 4), each with the default
    // null-space factorisation and with the bordered one.
    for (block, null_space) in [(1, true), (4, true), (1, false), (4, false)] {
        let mut opts = opts.clone();
        opts.projection.refine.block = block;
        opts.projection.refine.null_space = null_space;
        let p = complex_eigen(&sys, &opts).unwrap();
        let st = p.stats.refine.as_ref().expect("refinement ran");
        for sh in &st.shifts {
            let (kind, size) = if null_space {
                ("null_space", 150 - 12)
            } else {
                ("bordered", 150 + 12)
            };
            assert_eq!((sh.factorisation, sh.factor_size), (kind, size));
        }
        eprintln!(
            "block {block}, null space {null_space}: targets {}, refined {} ({} targets), shifts {}, applications {}, \
         missed {}, max |dp| {:e}, max residual {:e}, plain error {err_plain:e}",
            st.n_targets,
            st.n_refined,
            st.n_targets_refined,
            st.n_shifts,
            st.n_applications,
            st.n_missed,
            st.max_abs_change,
            st.max_residual
        );
        assert_eq!(st.n_failed, 0);
        assert_eq!(st.n_targets_refined, st.n_targets);
        // With plain Arnoldi the targets (nearest the shifts) converge to round-off; every root
        // refined inside the converged disc, the band method's targets too, to the Ritz
        // tolerance (1e-10).
        let target_residual = st
            .roots
            .iter()
            .filter(|r| r.target)
            .map(|r| r.residual)
            .fold(0.0, f64::max);
        eprintln!("block {block}: largest target residual {target_residual:e}");
        assert!(
            target_residual < if block == 1 { 1e-14 } else { 1e-10 },
            "{target_residual:e}"
        );
        assert!(st.max_residual < 1e-10, "{:e}", st.max_residual);
        assert!(st.max_constraint_residual < 1e-13);
        for x in &exact {
            let r = nearest(&p.modes, x.eigenvalue);
            let d = (r.eigenvalue - x.eigenvalue).norm() / x.eigenvalue.norm();
            assert!(
                d < 1e-9,
                "exact root {} : refined {} ({d:e})",
                x.eigenvalue,
                r.eigenvalue
            );
            assert!(r.unstable);
            let m = mac(&r.shape, &x.shape);
            assert!(m > 1.0 - 1e-8, "MAC {m} at {}", x.eigenvalue);
            // The shape satisfies the constraint.
            let g = sys.g.as_ref().unwrap();
            let gu: f64 = (0..g.nrows())
                .map(|i| {
                    (0..g.ncols())
                        .map(|j| r.shape[j] * g[(i, j)])
                        .sum::<squeal_solver::cea::Cplx>()
                        .norm_sqr()
                })
                .sum();
            assert!(gu.sqrt() < 1e-12);
        }
        let got = in_band_unstable(&p.modes);
        assert_eq!(got.len(), exact.len());
        for r in &got {
            let x = nearest(&exact, r.eigenvalue);
            assert!((r.eigenvalue - x.eigenvalue).norm() < 1e-9 * x.eigenvalue.norm());
        }
        assert_eq!(
            p.stats.n_unstable,
            p.modes.iter().filter(|m| m.unstable).count()
        );
        // Each reported change is the difference of the two roots it lists.
        for r in &st.roots {
            assert_eq!(r.abs_change, (r.exact - r.projected).norm());
        }
    }
}

/// The refinement's options are checked and name the field.
#[test]
fn refine_options_are_validated() {
    let sys = random_constrained(20, 2, 0.5, 7);
    let opts = CeaOptions {
        method: CeaMethod::Projection,
        projection: ProjectionOptions {
            refine: RefineOptions {
                max_krylov_dim: 5,
                ..RefineOptions::default()
            },
            ..ProjectionOptions::default()
        },
        ..CeaOptions::default()
    };
    let e = complex_eigen(&sys, &opts).unwrap_err();
    assert!(e.to_string().contains("refine.max_krylov_dim"), "{e}");
}
