//! The substructured Craig–Bampton reduction against the exact one (the reference: the same
//! component reduced with one factor of its whole interior, `cb::reduce_ordered`), on small
//! hex8 annuli.

use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use squeal_reduction::cb::{self, CbOptions, DofPoint, SubstructureOptions};

type Sparse = SparseColMat<usize, f64>;

#[path = "cb/fem.rs"]
#[allow(dead_code)]
mod fem;

const STEEL: (f64, f64, f64) = (210e9, 0.3, 7850.0);

/// Steel annulus r = 0.06..0.14 m, 25 mm thick, 4 × 48 × 4 hex8, free-free, boundary = the
/// nodes of the friction face z = t on a 60° arc (a pad's footprint).
fn rotor() -> (fem::Hexes, Sparse, Sparse, Vec<usize>, Vec<[f64; 3]>) {
    let t = 0.025;
    let h = fem::annulus_mesh(0.06, 0.14, t, 4, 48, 4);
    let (k, m) = fem::assemble(&h, STEEL.0, STEEL.1, STEEL.2);
    let face: Vec<usize> = (0..h.nodes.len())
        .filter(|&n| {
            let p = h.nodes[n];
            (p[2] - t).abs() < 1e-12 && p[1].atan2(p[0]).abs() < 0.53
        })
        .collect();
    let coords: Vec<[f64; 3]> = (0..k.nrows()).map(|i| h.nodes[i / 3]).collect();
    (h, k, m, fem::dofs_of(&face), coords)
}

fn opts(foi: f64, sub: SubstructureOptions) -> CbOptions {
    CbOptions {
        substructures: sub,
        ..CbOptions::with_frequency_of_interest(foi)
    }
}

/// u = T x for every reduced coordinate: TᵀKT and TᵀMT must be the model's K and M.
fn transformation_consistent(model: &cb::CbModel, k: &Sparse, m: &Sparse) -> (f64, f64) {
    let nr = model.n_reduced();
    let t = model.expand(Mat::<f64>::identity(nr, nr).as_ref());
    let kt = fem::dense_times(k, &t);
    let mt = fem::dense_times(m, &t);
    let kr = t.transpose() * &kt;
    let mr = t.transpose() * &mt;
    let ek = (&kr - &model.k).norm_max() / model.k.norm_max();
    let em = (&mr - &model.m).norm_max() / model.m.norm_max();
    (ek, em)
}

/// Largest relative error of the model's fixed-interface eigenvalues and of its condensed
/// stiffness diagonal against the exact reduction (both are Ritz values: ≥ 0 up to round-off).
fn errors(model: &cb::CbModel, exact: &cb::CbModel) -> (f64, f64) {
    let (nb, ne) = (model.n_boundary_coords(), exact.n_boundary_coords());
    let nq = model.n_modes.min(exact.n_modes);
    let modes = (0..nq)
        .map(|q| rel_signed(model.k[(nb + q, nb + q)], exact.k[(ne + q, ne + q)]))
        .fold(f64::NEG_INFINITY, f64::max);
    let stat = (0..nb)
        .map(|c| rel_signed(model.k[(c, c)], exact.k[(c, c)]))
        .fold(f64::NEG_INFINITY, f64::max);
    (modes, stat)
}

fn rel_signed(a: f64, b: f64) -> f64 {
    (a - b) / b.abs()
}

/// Checks a substructured model against the exact one: the error estimates it reports are the
/// errors it has (to `within`, relative: the estimate is first order, so loose for large
/// errors), every error is from above (Rayleigh–Ritz), and its Ψ, Φ reproduce its K, M.
fn check_against_exact(
    model: &cb::CbModel,
    exact: &cb::CbModel,
    k: &Sparse,
    m: &Sparse,
    within: f64,
) {
    let ml = model.stats.multilevel.as_ref().expect("substructured");
    let (em, es) = errors(model, exact);
    println!(
        "rounds {}: modes {} (exact {}), estimate {:.3e} / error {em:.3e}; static estimate \
         {:.3e} / error {es:.3e}; degrees {:?}, substructure modes {:?}",
        ml.rounds,
        model.n_modes,
        exact.n_modes,
        ml.estimate_modes,
        ml.estimate_static,
        ml.separators.iter().map(|s| s.degree).collect::<Vec<_>>(),
        ml.substructures
            .iter()
            .map(|s| s.n_modes)
            .collect::<Vec<_>>()
    );
    assert!(
        em > -1e-10 && es > -1e-10,
        "below the exact values: {em:e} {es:e}"
    );
    for (est, err) in [(ml.estimate_modes, em), (ml.estimate_static, es)] {
        assert!(
            (est - err).abs() <= within * err + 1e-9,
            "estimate {est:e} vs error {err:e}"
        );
    }
    let (ek, emm) = transformation_consistent(model, k, m);
    assert!(
        ek < 1e-10 && emm < 1e-10,
        "TᵀKT, TᵀMT vs K_r, M_r: {ek:e} {emm:e}"
    );
}

/// Against the exact Craig–Bampton reduction (one factor of the whole interior) of the same
/// rotor: with a coarse setting and no refinement the estimates are the errors (tens of %); with
/// a tolerance of 1e-3 the reduction refines itself until both errors are within it.
#[test]
fn substructured_reduction_estimates_its_error_and_meets_the_tolerance() {
    let (_, k, m, boundary, coords) = rotor();
    let foi = 4000.0;
    let exact = cb::reduce_ordered(
        &k,
        &m,
        None,
        &boundary,
        &opts(foi, Default::default()),
        Some(&coords),
    )
    .unwrap();
    let base = SubstructureOptions {
        above_dofs: Some(0),
        max_dofs: 700,
        degree: 2,
        ..Default::default()
    };
    let coarse = SubstructureOptions {
        tol: 0.5,
        max_rounds: 0,
        ..base.clone()
    };
    let model =
        cb::reduce_ordered(&k, &m, None, &boundary, &opts(foi, coarse), Some(&coords)).unwrap();
    let ml = model.stats.multilevel.as_ref().unwrap();
    assert!(ml.substructures.len() >= 4 && ml.separators.len() >= 4);
    assert!(ml.estimate_modes > 1e-2, "{}", ml.estimate_modes);
    check_against_exact(&model, &exact, &k, &m, 0.5);

    let fine = SubstructureOptions {
        tol: 1e-3,
        max_rounds: 6,
        ..base
    };
    let model =
        cb::reduce_ordered(&k, &m, None, &boundary, &opts(foi, fine), Some(&coords)).unwrap();
    let ml = model.stats.multilevel.as_ref().unwrap();
    assert!(ml.converged && ml.rounds > 1, "{} rounds", ml.rounds);
    assert_eq!(model.n_modes, exact.n_modes);
    check_against_exact(&model, &exact, &k, &m, 0.1);
    let (em, es) = errors(&model, &exact);
    assert!(em <= 1e-3 && es <= 1e-3, "{em:e} {es:e}");
}

/// The same with the friction arc reduced to an interface basis (cubic polynomials per
/// direction) instead of kept DOFs, against `cb::reduce_interface` with the same basis.
#[test]
fn substructured_reduction_with_an_interface_basis() {
    let (h, k, m, face_dofs, coords) = rotor();
    let foi = 4000.0;
    let dofs: Vec<cb::InterfaceDof> = face_dofs
        .iter()
        .map(|&d| cb::InterfaceDof {
            point: h.nodes[d / 3],
            direction: d % 3,
            patch: 0,
        })
        .collect();
    let iface = cb::InterfaceBasis {
        basis: cb::polynomial_basis(&dofs, 3).unwrap(),
        dofs: face_dofs,
    };
    let exact = cb::reduce_interface(
        &k,
        &m,
        None,
        &[],
        Some(&iface),
        &opts(foi, Default::default()),
        Some(&coords),
    )
    .unwrap();
    let sub = SubstructureOptions {
        above_dofs: Some(0),
        max_dofs: 700,
        tol: 1e-3,
        ..Default::default()
    };
    let model = cb::reduce_interface(
        &k,
        &m,
        None,
        &[],
        Some(&iface),
        &opts(foi, sub),
        Some(&coords),
    )
    .unwrap();
    assert!(model.stats.multilevel.as_ref().unwrap().converged);
    assert_eq!(model.n_interface(), iface.n_coords());
    check_against_exact(&model, &exact, &k, &m, 0.1);
    let (em, es) = errors(&model, &exact);
    assert!(em <= 1e-3 && es <= 1e-3, "{em:e} {es:e}");
}
