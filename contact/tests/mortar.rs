//! Mortar pairing ([`mortar_gaps`]): dual-Lagrange-multiplier segment-to-segment ties.
//! Checks: coincident meshes give node pairing (weights 1 and 0, the same G as the
//! node-to-surface tie); on a non-matching flat interface the weights sum to one, reproduce
//! linear fields (so G u = 0 for the six rigid motions) and scatter a uniform pressure's
//! multipliers into the rotor's consistent nodal loads; quad8 pad faces are refused.

use squeal_contact::{
    mortar_gaps, tie_gaps, ContactError, ContactNode, FaceKind, MatchOptions, RotorFace, TieOptions,
};

/// A flat grid of quad4 faces over [0, lx] × [0, ly] at z = 0, `nx × ny` faces, node ids
/// from `base`; returns (faces, node id → coordinates). Counterclockwise about `+z` when
/// `up`, else about −z.
fn grid(
    nx: usize,
    ny: usize,
    lx: f64,
    ly: f64,
    base: u64,
    up: bool,
) -> (Vec<RotorFace>, Vec<(u64, [f64; 3])>) {
    let id = |i: usize, j: usize| base + (j * (nx + 1) + i) as u64;
    let x = |i: usize, j: usize| [lx * i as f64 / nx as f64, ly * j as f64 / ny as f64, 0.0];
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push((id(i, j), x(i, j)));
        }
    }
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let mut c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            if !up {
                c.reverse();
            }
            faces.push(RotorFace {
                id: faces.len() as u64,
                kind: FaceKind::Quad4,
                nodes: c.iter().map(|&(a, b)| id(a, b)).collect(),
                coords: c.iter().map(|&(a, b)| x(a, b)).collect(),
            });
        }
    }
    (faces, nodes)
}

/// Pad contact nodes of pad faces (normal −z), with their consistent areas ∫N_j dΓ.
fn pad_nodes(faces: &[RotorFace], nodes: &[(u64, [f64; 3])]) -> Vec<ContactNode> {
    nodes
        .iter()
        .map(|&(id, x)| {
            let mut a = 0.0;
            for f in faces.iter().filter(|f| f.nodes.contains(&id)) {
                let e = [
                    f.coords[1][0] - f.coords[0][0],
                    f.coords[1][1] - f.coords[0][1],
                ];
                let g = [
                    f.coords[3][0] - f.coords[0][0],
                    f.coords[3][1] - f.coords[0][1],
                ];
                a += 0.25 * (e[0] * g[1] - e[1] * g[0]).abs();
            }
            ContactNode {
                id,
                coords: x,
                area: [0.0, 0.0, -a],
            }
        })
        .collect()
}

fn opts() -> MatchOptions {
    MatchOptions {
        rpm: 30.0,
        p0: 2.0,
        ..MatchOptions::default()
    }
}

/// Every node id → 3 consecutive DOFs, in the order given.
fn dof_map(ids: &[u64]) -> impl Fn(u64) -> [Option<usize>; 3] + '_ {
    move |id| {
        let i = ids.iter().position(|&x| x == id).expect("known node");
        [Some(3 * i), Some(3 * i + 1), Some(3 * i + 2)]
    }
}

/// Coincident pad and rotor grids (2×2 faces): every mortar weight is exactly 1 on the
/// coincident rotor node (0 elsewhere, dropped), and G equals the node-to-surface tie's G
/// (which equals node matching's, `tie.rs`) exactly.
#[test]
fn coincident_meshes_give_node_pairing() {
    let (rf, rn) = grid(2, 2, 1.0, 1.0, 0, true);
    let (pf, pn) = grid(2, 2, 1.0, 1.0, 100, false);
    let pad = pad_nodes(&pf, &pn);
    let (out, ms) = mortar_gaps(&pad, &pf, &rf, &opts(), &TieOptions::default()).expect("mortar");
    let mut m = out.gaps;
    let mut t = tie_gaps(&pad, &rf, &opts(), &TieOptions::default())
        .expect("tie")
        .gaps;
    assert_eq!(m.gaps.len(), 9);
    assert_eq!(ms.n_pad_faces, 4);
    assert!((ms.min_coverage - 1.0).abs() < 1e-12, "{ms:?}");
    for g in &m.gaps {
        let tie = g.tie.as_ref().unwrap();
        assert!(tie.mortar);
        assert_eq!(tie.weights, vec![1.0], "pad node {}: {tie:?}", g.pad_node);
        assert_eq!(tie.nodes, vec![g.pad_node - 100]);
        assert_eq!(g.rotor_node, g.pad_node - 100);
    }
    let ids: Vec<u64> = rn.iter().chain(&pn).map(|n| n.0).collect();
    m.assign_dofs(dof_map(&ids));
    t.assign_dofs(dof_map(&ids));
    let n = 3 * ids.len();
    assert!(m.constraint_matrix(n).unwrap() == t.constraint_matrix(n).unwrap());
}

/// 2×2 pad faces on 3×3 rotor faces (no pad face inside one rotor face; the case where the
/// node-to-surface tie fails the patch test): the weights of each gap sum to 1, Σ_a W_ja x_a
/// = x_j (linear fields reproduced, biorthogonality), so G u = 0 for the three translations
/// and the three rotations; and the multipliers of a uniform pressure, λ_j = −p D_j, scatter
/// to the rotor's consistent nodal loads −p ∫N_a dΓ exactly.
#[test]
fn non_matching_weights_reproduce_linear_fields_and_pressure() {
    let (rf, rn) = grid(3, 3, 1.0, 1.0, 0, true);
    let (pf, pn) = grid(2, 2, 1.0, 1.0, 100, false);
    let pad = pad_nodes(&pf, &pn);
    let (out, ms) = mortar_gaps(&pad, &pf, &rf, &opts(), &TieOptions::default()).expect("mortar");
    let mut m = out.gaps;
    assert_eq!(m.gaps.len(), 9);
    assert!(ms.n_segments >= 9, "{ms:?}");
    let xr = |id: u64| rn.iter().find(|n| n.0 == id).unwrap().1;
    for g in &m.gaps {
        let t = g.tie.as_ref().unwrap();
        let s: f64 = t.weights.iter().sum();
        assert!((s - 1.0).abs() < 1e-13, "{s}");
        for k in 0..3 {
            let x: f64 = t
                .nodes
                .iter()
                .zip(&t.weights)
                .map(|(&a, &w)| w * xr(a)[k])
                .sum();
            assert!(
                (x - g.coords[k]).abs() < 1e-13,
                "gap {}: {x} vs {:?}",
                g.pad_node,
                g.coords
            );
        }
        assert!(t.nodes.len() > 1, "non-matching: several rotor nodes");
    }
    let ids: Vec<u64> = rn.iter().chain(&pn).map(|n| n.0).collect();
    m.assign_dofs(dof_map(&ids));
    let n = 3 * ids.len();
    let g = m.constraint_matrix(n).unwrap();
    let pos = |i: usize| {
        if i < rn.len() {
            rn[i].1
        } else {
            pn[i - rn.len()].1
        }
    };
    type Motion = Box<dyn Fn([f64; 3]) -> [f64; 3]>;
    let motions: Vec<Motion> = vec![
        Box::new(|_| [1.0, 0.0, 0.0]),
        Box::new(|_| [0.0, 1.0, 0.0]),
        Box::new(|_| [0.0, 0.0, 1.0]),
        Box::new(|x| [0.0, -x[2], x[1]]),
        Box::new(|x| [x[2], 0.0, -x[0]]),
        Box::new(|x| [-x[1], x[0], 0.0]),
    ];
    for (k, f) in motions.iter().enumerate() {
        let mut u = vec![0.0; n];
        for i in 0..ids.len() {
            let v = f(pos(i));
            u[3 * i..3 * i + 3].copy_from_slice(&v);
        }
        for r in 0..g.nrows() {
            let gu: f64 = (0..n).map(|c| g[(r, c)] * u[c]).sum();
            assert!(gu.abs() < 1e-13, "motion {k}, row {r}: {gu}");
        }
    }
    // Uniform pressure p: λ_j = −p A_j; rotor force −Gᵀλ on node a against −p ∫N_a (the
    // consistent load of the rotor's 3×3 grid: (1/3)²/4 per face corner).
    let p = 3.0;
    let h = 1.0 / 3.0;
    for (a, &(id, x)) in rn.iter().enumerate() {
        let f: f64 = -(0..g.nrows())
            .map(|r| g[(r, 3 * a + 2)] * (-p * m.gaps[r].area))
            .sum::<f64>();
        let on_x = x[0] == 0.0 || (x[0] - 1.0).abs() < 1e-12;
        let on_y = x[1] == 0.0 || (x[1] - 1.0).abs() < 1e-12;
        let share = h * h / 4.0 * [4.0, 2.0, 1.0][on_x as usize + on_y as usize];
        assert!(
            (f - (-p * share)).abs() < 1e-13,
            "rotor node {id}: {f} vs {}",
            -p * share
        );
    }
}

/// A quad8 pad face has no usable dual basis (negative corner integrals): an error naming
/// the face.
#[test]
fn quad8_pad_faces_are_refused() {
    let (rf, _) = grid(1, 1, 1.0, 1.0, 0, true);
    let (pf, pn) = grid(1, 1, 1.0, 1.0, 100, false);
    let pad = pad_nodes(&pf, &pn);
    let mut q8 = pf[0].clone();
    q8.kind = FaceKind::Quad8;
    q8.nodes.extend([200, 201, 202, 203]);
    let c = q8.coords.clone();
    for a in 0..4 {
        let (p, q) = (c[a], c[(a + 1) % 4]);
        q8.coords
            .push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.0]);
    }
    let e = mortar_gaps(&pad, &[q8], &rf, &opts(), &TieOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, ContactError::InvalidOption { .. }), "{msg}");
    assert!(
        msg.contains("pad_faces[0]") && msg.contains("quad4"),
        "{msg}"
    );
}

/// Pad faces that are not parallelograms (trapezoids, as on an annular-sector pad) on a
/// non-matching rotor grid: every pad node is tied (its coverage is 1 to within the
/// quadrature error of the non-polynomial dual function, not to round-off: the cad brake's
/// pads were refused at a tolerance of 1e-9), and the weights still reproduce linear fields
/// to that error.
#[test]
fn trapezoidal_pad_faces_are_covered_to_the_quadrature_error() {
    let (rf, rn) = grid(3, 3, 1.0, 1.0, 0, true);
    let (nx, ny) = (2usize, 2usize);
    let id = |i: usize, j: usize| 100 + (j * (nx + 1) + i) as u64;
    let x = |i: usize, j: usize| {
        let (s, t) = (i as f64 / nx as f64, j as f64 / ny as f64);
        // Each row is wider than the one below it: trapezoids.
        [0.1 + 0.5 * s * (1.0 + 0.6 * t), 0.15 + 0.7 * t, 0.0]
    };
    let mut pn = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            pn.push((id(i, j), x(i, j)));
        }
    }
    let mut pf = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let mut c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            c.reverse();
            pf.push(RotorFace {
                id: pf.len() as u64,
                kind: FaceKind::Quad4,
                nodes: c.iter().map(|&(a, b)| id(a, b)).collect(),
                coords: c.iter().map(|&(a, b)| x(a, b)).collect(),
            });
        }
    }
    let pad = pad_nodes(&pf, &pn);
    let (out, ms) = mortar_gaps(&pad, &pf, &rf, &opts(), &TieOptions::default()).expect("mortar");
    assert_eq!(out.gaps.gaps.len(), 9, "every pad node tied");
    eprintln!("min coverage 1 {:+.3e}", ms.min_coverage - 1.0);
    assert!((ms.min_coverage - 1.0).abs() <= 1e-6, "{ms:?}");
    let xr: std::collections::HashMap<u64, [f64; 3]> = rn.iter().copied().collect();
    let mut worst: f64 = 0.0;
    for g in &out.gaps.gaps {
        let tie = g.tie.as_ref().unwrap();
        let s: f64 = tie.weights.iter().sum();
        assert!((s - 1.0).abs() < 1e-12, "weights sum {s}");
        let xp = pn.iter().find(|n| n.0 == g.pad_node).unwrap().1;
        for k in 0..2 {
            let xw: f64 = tie
                .nodes
                .iter()
                .zip(&tie.weights)
                .map(|(n, w)| w * xr[n][k])
                .sum();
            worst = worst.max((xw - xp[k]).abs());
        }
    }
    eprintln!("linear field reproduced to {worst:.3e}");
    assert!(worst <= 1e-6, "{worst}");
}
