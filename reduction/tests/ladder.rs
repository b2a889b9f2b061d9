//! The interface ladder ([`cb::InterfaceLadder`]): one K_ii factor and one set of
//! fixed-interface modes for every interface degree, the constraint modes of each basis column
//! solved once. Reference: [`cb::reduce_interface`] with [`cb::polynomial_basis`] of the same
//! degree (an independent reduction from scratch), whose models the ladder must reproduce to
//! round-off.

#![allow(dead_code)]

use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use squeal_reduction::cb::{self, CbOptions, DofPoint};

type Sparse = SparseColMat<usize, f64>;

#[path = "cb/fem.rs"]
mod fem;

/// Steel annulus r = 0.06..0.14 m, 25 mm thick, 2 × 24 × 2 hex8, free-free (as `tests/cb.rs`);
/// kept boundary: the inner-radius nodes of the bottom face; interface: a 90° sector of the
/// friction face z = t (a pad-sized patch, 3 × 7 nodes).
fn annulus() -> (fem::Hexes, Sparse, Sparse, Vec<usize>, Vec<usize>) {
    let t = 0.025;
    let h = fem::annulus_mesh(0.06, 0.14, t, 2, 24, 2);
    let (k, m) = fem::assemble(&h, 210e9, 0.3, 7850.0);
    let kept: Vec<usize> = (0..h.nodes.len())
        .filter(|&n| {
            let p = h.nodes[n];
            p[2].abs() < 1e-12 && (p[0].hypot(p[1]) - 0.06).abs() < 1e-9
        })
        .collect();
    let patch: Vec<usize> = (0..h.nodes.len())
        .filter(|&n| {
            let p = h.nodes[n];
            (p[2] - t).abs() < 1e-12 && p[0] >= -1e-12 && p[1] >= -1e-12
        })
        .collect();
    assert_eq!(patch.len(), 3 * 7);
    (h, k, m, fem::dofs_of(&kept), patch)
}

#[test]
fn ladder_reproduces_reductions_from_scratch_and_solves_each_column_once() {
    let (h, k, m, kept, patch) = annulus();
    let dofs = fem::dofs_of(&patch);
    let points: Vec<cb::InterfaceDof> = patch
        .iter()
        .flat_map(|&n| {
            let point = h.nodes[n];
            (0..3).map(move |d| cb::InterfaceDof {
                point,
                direction: d,
                patch: 0,
            })
        })
        .collect();
    let opts = CbOptions::with_n_modes(12);
    let mut ladder = cb::InterfaceLadder::new(
        &k,
        &m,
        kept.clone(),
        dofs.iter().copied().zip(points.iter().copied()).collect(),
        &opts,
        None,
    )
    .unwrap();
    assert_eq!(ladder.n_constraint_solves(), kept.len());
    for degree in [1, 3, 5] {
        let red = ladder.reduce(degree).unwrap();
        let basis = cb::polynomial_basis(&points, degree).unwrap();
        let np = basis.ncols();
        let iface = cb::InterfaceBasis {
            dofs: dofs.clone(),
            basis,
        };
        let scratch = cb::reduce_interface(&k, &m, None, &kept, Some(&iface), &opts, None).unwrap();
        assert_eq!(red.n_reduced(), scratch.n_reduced(), "degree {degree}");
        // The same coordinates; the fixed-interface modes may differ in sign only, so the
        // boundary blocks and the modal diagonal compare directly.
        let nb = red.n_boundary_coords();
        let e = |a: &Mat<f64>, b: &Mat<f64>| {
            (a.submatrix(0, 0, nb, nb) - b.submatrix(0, 0, nb, nb)).norm_max()
                / b.submatrix(0, 0, nb, nb).norm_max()
        };
        let (ek, em) = (e(&red.k, &scratch.k), e(&red.m, &scratch.m));
        assert!(
            ek < 1e-10 && em < 1e-10,
            "degree {degree}: K {ek:e}, M {em:e}"
        );
        for q in 0..red.n_modes {
            let (a, b) = (red.k[(nb + q, nb + q)], scratch.k[(nb + q, nb + q)]);
            assert!((a - b).abs() <= 1e-10 * b.abs(), "degree {degree} mode {q}");
        }
        // Every column solved once: the kept DOFs and this degree's coordinates so far.
        assert_eq!(
            ladder.n_constraint_solves(),
            kept.len() + np,
            "degree {degree}"
        );
    }
    // Back down: nothing new to solve.
    let before = ladder.n_constraint_solves();
    ladder.reduce(3).unwrap();
    assert_eq!(ladder.n_constraint_solves(), before);
}
