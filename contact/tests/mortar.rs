//! Mortar pairing ([`mortar_gaps`]): dual-Lagrange-multiplier segment-to-segment ties.
//! Checks: coincident meshes give node pairing (weights 1 and 0, the same G as the
//! node-to-surface tie); on a non-matching flat interface the weights sum to one, reproduce
//! linear fields (so G u = 0 for the six rigid motions) and scatter a uniform pressure's
//! multipliers into the rotor's consistent nodal loads; the interface patch test on
//! distorted quad4/quad8/tri3/tri6 pad and rotor faces (nodes moved by up to 30 %) and on
//! coincident distorted meshes; curved faces converge with refinement.

mod common;

use squeal_contact::{
    mortar_gaps, tie_gaps, ContactNode, FaceKind, MatchOptions, MortarOptions, RotorFace,
    TieOptions,
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
    let (out, ms) = mortar_gaps(
        &pad,
        &pf,
        &rf,
        &opts(),
        &TieOptions::default(),
        &MortarOptions::default(),
    )
    .expect("mortar");
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
    let (out, ms) = mortar_gaps(
        &pad,
        &pf,
        &rf,
        &opts(),
        &TieOptions::default(),
        &MortarOptions::default(),
    )
    .expect("mortar");
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

/// Pad faces that are not parallelograms (trapezoids, as on an annular-sector pad) on a
/// non-matching rotor grid: every pad node is tied with its coverage 1 and the weights
/// reproduce linear fields to round-off (the adaptive rule integrates the non-polynomial
/// dual functions to 1e-13; with the former single 7-point rule these were 3.2e-7).
#[test]
fn trapezoidal_pad_faces_are_covered_exactly() {
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
    let (out, ms) = mortar_gaps(
        &pad,
        &pf,
        &rf,
        &opts(),
        &TieOptions::default(),
        &MortarOptions::default(),
    )
    .expect("mortar");
    assert_eq!(out.gaps.gaps.len(), 9, "every pad node tied");
    eprintln!("min coverage 1 {:+.3e}", ms.min_coverage - 1.0);
    assert!((ms.min_coverage - 1.0).abs() <= 1e-12, "{ms:?}");
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
    assert!(worst <= 1e-12, "{worst}");
}

// ------------------------------------------------ patch tests on distorted and curved faces

use common::{area_vectors, contact_nodes, surface, tilted_plane, Map, Surface};
use squeal_contact::{Gap, MortarStats};
use std::collections::HashMap;

const KINDS: [FaceKind; 4] = [
    FaceKind::Quad4,
    FaceKind::Quad8,
    FaceKind::Tri3,
    FaceKind::Tri6,
];

/// The largest errors of the interface patch test (see [`patch`]), per unit of the
/// quantity's scale.
#[derive(Debug, Default, Clone, Copy)]
struct PatchErrors {
    /// |Σ_a W_ja − 1|.
    weight_sum: f64,
    /// |Σ_a W_ja x_a − x̂_j| / side length: linear fields (and so rigid motions and the
    /// uniform-strain displacement) reproduced, G u = 0.
    linear: f64,
    /// |Σ_j W_ja A_j n_j + S_a^rotor| / face area: the rotor's nodal forces of a uniform
    /// pressure are its consistent load.
    rotor_force: f64,
    /// |Σ_j w_jk A_j n_j − S_k^pad| / face area: the pad's nodal forces are its consistent
    /// load (with the quad8 corners' −1/12 and the tri6 corners' 0).
    pad_force: f64,
}

impl PatchErrors {
    fn max(&self) -> f64 {
        self.weight_sum
            .max(self.linear)
            .max(self.rotor_force)
            .max(self.pad_force)
    }
}

/// The pad side of a gap as (node, weight) terms.
fn pad_terms(g: &Gap) -> Vec<(u64, f64)> {
    match &g.pad_side {
        Some(p) => p
            .nodes
            .iter()
            .copied()
            .zip(p.weights.iter().copied())
            .collect(),
        None => vec![(g.pad_node, 1.0)],
    }
}

/// The interface patch test of a uniform pressure p through the mortar tie of `pad` on
/// `rotor`: the multipliers λ_j = −p A_j (uniform contact pressure p_n = p, eq. (1)) must
/// be in equilibrium with the consistent nodal loads of p on both surfaces, −Gᵀλ = p S, and
/// the exact displacement field of the uniform-stress solution (linear) must satisfy G u = 0.
/// Those are the four identities of [`PatchErrors`]; reference: the consistent loads
/// ∫N_a n dA by Gauss quadrature in each face's own coordinates ([`area_vectors`]).
fn patch_errors(pad: &Surface, rotor: &Surface, scale: f64) -> (PatchErrors, MortarStats) {
    patch_errors_with(
        pad,
        rotor,
        scale,
        &TieOptions::default(),
        &MortarOptions::default(),
    )
}

/// [`patch_errors`] with the given mortar options.
fn patch_errors_with(
    pad: &Surface,
    rotor: &Surface,
    scale: f64,
    tie: &TieOptions,
    mo: &MortarOptions,
) -> (PatchErrors, MortarStats) {
    let pad_nodes = contact_nodes(pad);
    let (out, ms) = mortar_gaps(
        &pad_nodes,
        &pad.faces,
        &rotor.faces,
        &MatchOptions::default(),
        tie,
        mo,
    )
    .expect("mortar");
    assert_eq!(out.gaps.gaps.len(), pad_nodes.len(), "every pad node tied");
    let (xr, xp) = (rotor.xyz(), pad.xyz());
    let (sr, sp) = (area_vectors(rotor), area_vectors(pad));
    let area = scale * scale / rotor.faces.len() as f64;
    let mut e = PatchErrors::default();
    let mut fr: HashMap<u64, [f64; 3]> = HashMap::new();
    let mut fp: HashMap<u64, [f64; 3]> = HashMap::new();
    for g in &out.gaps.gaps {
        let t = g.tie.as_ref().unwrap();
        e.weight_sum = e
            .weight_sum
            .max((t.weights.iter().sum::<f64>() - 1.0).abs());
        let xhat = pad_terms(g).iter().fold([0.0; 3], |s, &(n, w)| {
            [0, 1, 2].map(|k| s[k] + w * xp[&n][k])
        });
        for k in 0..3 {
            let x: f64 = t
                .nodes
                .iter()
                .zip(&t.weights)
                .map(|(n, w)| w * xr[n][k])
                .sum();
            e.linear = e.linear.max((x - xhat[k]).abs() / scale);
        }
        for (n, w) in t.nodes.iter().zip(&t.weights) {
            let f = fr.entry(*n).or_insert([0.0; 3]);
            (0..3).for_each(|k| f[k] += w * g.area * g.normal[k]);
        }
        for (n, w) in pad_terms(g) {
            let f = fp.entry(n).or_insert([0.0; 3]);
            (0..3).for_each(|k| f[k] += w * g.area * g.normal[k]);
        }
    }
    for (n, s) in &sr {
        let f = fr.get(n).copied().unwrap_or([0.0; 3]);
        for k in 0..3 {
            e.rotor_force = e.rotor_force.max((f[k] + s[k]).abs() / area);
        }
    }
    for (n, s) in &sp {
        let f = fp.get(n).copied().unwrap_or([0.0; 3]);
        for k in 0..3 {
            e.pad_force = e.pad_force.max((f[k] - s[k]).abs() / area);
        }
    }
    (e, ms)
}

/// Pad (3×2 cells) and rotor (4×3 cells) of the given kinds on one tilted plane, the
/// interior nodes of each moved by up to `distortion` of the cell size.
fn flat_pair(pk: FaceKind, rk: FaceKind, distortion: f64, seed: u64) -> (Surface, Surface) {
    let map = tilted_plane([0.3, -0.2, 0.5], 2.0);
    let m: Map = &map;
    let rotor = surface(rk, 4, 3, distortion, seed, 0, true, m);
    let pad = surface(pk, 3, 2, distortion, seed + 17, 1_000_000, false, m);
    (pad, rotor)
}

/// The patch test on flat non-matching interfaces of every pad × rotor face kind (quad4,
/// quad8, tri3, tri6), with the interior nodes of both meshes moved by up to 0, 10, 20 and
/// 30 % of the cell size (smallest quad angles 90°, 80°, 70°, 61°; triangles 34° to 21°) and
/// the plane tilted out of every axis: the uniform pressure is transmitted as a uniform contact pressure to 1e-10
/// (every identity of [`PatchErrors`]), against the consistent loads computed
/// independently. Prints the table of `docs/pairing.md`.
#[test]
fn patch_test_passes_on_distorted_faces_of_every_kind() {
    let mut worst = 0.0f64;
    eprintln!("| pad | rotor | distortion | max error | segments (exact) | triangles | quadrature estimate |");
    eprintln!("|---|---|---|---|---|---|---|");
    for pk in KINDS {
        for rk in KINDS {
            for d in [0.0, 0.1, 0.2, 0.3] {
                let (pad, rotor) = flat_pair(pk, rk, d, 5);
                let (e, ms) = patch_errors(&pad, &rotor, 2.0);
                let angle = common::min_angle_deg(&pad).min(common::min_angle_deg(&rotor));
                eprintln!(
                    "| {pk:?} | {rk:?} | {:.0} % ({angle:.0}°) | {:.1e} | {} ({}) | {} | {:.1e} |",
                    100.0 * d,
                    e.max(),
                    ms.n_segments,
                    ms.n_exact_segments,
                    ms.n_triangles,
                    ms.quadrature_error
                );
                assert!(e.max() < 1e-10, "pad {pk:?} on rotor {rk:?}, {d}: {e:?}");
                worst = worst.max(e.max());
            }
        }
    }
    eprintln!("worst patch-test error over the 64 cases: {worst:.2e}");
}

/// Coincident distorted meshes (the pad's faces are the rotor's, reversed, nodes moved by up
/// to 30 %), every kind: linear faces get exactly one weight 1 on the coincident node; on
/// quadratic faces a corner gap is nodal and a mid-side gap's rotor weights are exactly its
/// pad-side weights (5/3, −1/3, −1/3 on the same nodes: the rows are the transformed nodal
/// equalities, so G u = 0 ⇔ u_rotor = u_pad at every node).
#[test]
fn coincident_distorted_meshes_give_nodal_weights() {
    let map = tilted_plane([0.3, -0.2, 0.5], 2.0);
    for kind in KINDS {
        let rotor = surface(kind, 3, 3, 0.3, 9, 0, true, &map);
        let pad = surface(kind, 3, 3, 0.3, 9, 1_000_000, false, &map);
        let pad_nodes = contact_nodes(&pad);
        let (out, ms) = mortar_gaps(
            &pad_nodes,
            &pad.faces,
            &rotor.faces,
            &MatchOptions::default(),
            &TieOptions::default(),
            &MortarOptions::default(),
        )
        .expect("mortar");
        assert_eq!(ms.n_coincident_faces, pad.faces.len(), "{kind:?}");
        // Pad node id → the coincident rotor node id.
        let xr = rotor.xyz();
        let twin = |x: [f64; 3]| {
            *xr.iter()
                .find(|(_, y)| (0..3).all(|k| (x[k] - y[k]).abs() < 1e-12))
                .unwrap()
                .0
        };
        let xp = pad.xyz();
        for g in &out.gaps.gaps {
            let t = g.tie.as_ref().unwrap();
            let mut want: Vec<(u64, f64)> = pad_terms(g)
                .iter()
                .map(|&(n, w)| (twin(xp[&n]), w))
                .collect();
            want.sort_by_key(|x| x.0);
            let got: Vec<(u64, f64)> = t
                .nodes
                .iter()
                .copied()
                .zip(t.weights.iter().copied())
                .collect();
            assert_eq!(
                got.len(),
                want.len(),
                "{kind:?} pad node {}: {got:?}",
                g.pad_node
            );
            for (a, b) in got.iter().zip(&want) {
                assert_eq!(a.0, b.0, "{kind:?}");
                assert!(
                    (a.1 - b.1).abs() <= 1e-14,
                    "{kind:?} pad node {}: {got:?} vs {want:?}",
                    g.pad_node
                );
            }
            if !kind.is_quadratic() {
                assert_eq!(t.weights, vec![1.0], "{kind:?}");
            }
        }
    }
}

/// Curved faces (a cylinder of radius 1 under a 90° arc, pad and rotor meshes apart, nodes
/// moved by 10 %): the patch identities no longer hold exactly (the two faceted or quadratic
/// surfaces differ between their nodes, and the shadows' chords differ from the arcs; at the
/// pad's edges, which are the rotor's, the two surfaces' boundaries differ by their
/// sagitta, so the coverage tolerance is opened to 1e-2), but their error falls with the
/// mesh size: for each kind, refining both meshes by 2 reduces the largest error each time,
/// and by more than 2.8 over two refinements (observed orders are printed: the nodal forces'
/// ~1, from the pad and rotor normals' O(h) difference; the linear fields' ~2 on linear
/// faces and ~2.5 on quadratic ones).
#[test]
fn curved_faces_converge_with_refinement() {
    let map = common::cylinder(1.0, std::f64::consts::FRAC_PI_2, 1.0);
    for kind in KINDS {
        let (mut prev, mut first): (Option<f64>, Option<f64>) = (None, None);
        for level in 0..3 {
            let r = 1usize << level;
            let rotor = surface(kind, 4 * r, 3 * r, 0.1, 3, 0, true, &map);
            let pad = surface(kind, 3 * r, 2 * r, 0.1, 4, 1_000_000, false, &map);
            let mo = MortarOptions {
                coverage_tolerance: 1e-2,
                ..MortarOptions::default()
            };
            // The faceted surfaces of the coarsest meshes are their sagitta (~0.02) apart.
            let tie = TieOptions {
                max_distance: Some(0.05),
                ..TieOptions::default()
            };
            let t0 = std::time::Instant::now();
            let (e, ms) = patch_errors_with(&pad, &rotor, 1.0, &tie, &mo);
            eprintln!(
                "  coverage 1 {:+.1e}, {} pad faces, {} segments, {} triangles, {:.2} s",
                ms.min_coverage - 1.0,
                ms.n_pad_faces,
                ms.n_segments,
                ms.n_triangles,
                t0.elapsed().as_secs_f64()
            );
            let order = prev.map(|p| (p / e.max()).log2());
            eprintln!("{kind:?} curved, level {level}: {e:?}, observed order {order:?}");
            if let Some(p) = prev {
                assert!(e.max() < p, "{kind:?} level {level}: {} vs {p}", e.max());
            }
            first.get_or_insert(e.max());
            prev = Some(e.max());
        }
        let (a, b) = (first.unwrap(), prev.unwrap());
        eprintln!("{kind:?}: error / {:.2} over two refinements", a / b);
        assert!(a / b > 2.8, "{kind:?}: {a} -> {b}");
    }
}

/// Timing probe (run by hand with `--ignored --nocapture`): an annular-sector pad (quad8 or
/// quad4 trapezoids, 12 × 6 faces) on a finer annular rotor ring, both flat.
#[test]
#[ignore]
fn timing_annular_pad() {
    let ring = |r0: f64, r1: f64, a0: f64, a1: f64| {
        move |p: [f64; 2]| {
            let (r, a) = (r0 + (r1 - r0) * p[1], a0 + (a1 - a0) * p[0]);
            [r * a.cos(), r * a.sin(), 0.0]
        }
    };
    for kind in KINDS {
        let rm = ring(0.06, 0.14, -0.6, 0.6);
        let pm = ring(0.07, 0.13, -0.4, 0.4);
        let rotor = surface(kind, 60, 20, 0.0, 1, 0, true, &rm);
        let pad = surface(kind, 24, 12, 0.0, 2, 1_000_000, false, &pm);
        let nodes = contact_nodes(&pad);
        let t0 = std::time::Instant::now();
        let (out, ms) = mortar_gaps(
            &nodes,
            &pad.faces,
            &rotor.faces,
            &MatchOptions::default(),
            &TieOptions::default(),
            &MortarOptions::default(),
        )
        .unwrap();
        eprintln!(
            "{kind:?}: {} pad faces, {} gaps, {} segments ({} exact), {} triangles, {:.2} s, quadrature error {:.1e}",
            ms.n_pad_faces,
            out.gaps.gaps.len(),
            ms.n_segments,
            ms.n_exact_segments,
            ms.n_triangles,
            t0.elapsed().as_secs_f64(),
            ms.quadrature_error
        );
    }
}

/// A bonded tie's explicit rows u_s = Σ_a w_a u_a ([`squeal_contact::bond_rows`]), from the
/// mortar pairing of every slave × master kind at 30 % distortion: the weights sum to 1 and
/// interpolate every slave node's position from the master nodes (so a linear displacement
/// field, e.g. a constant strain, passes the bonded interface exactly), including the
/// mid-side nodes of quadratic slave faces, whose gaps constrain the transformed value.
#[test]
fn bonded_rows_reproduce_linear_fields() {
    for pk in KINDS {
        for rk in KINDS {
            let (pad, rotor) = flat_pair(pk, rk, 0.3, 8);
            let nodes = contact_nodes(&pad);
            let (out, _) = mortar_gaps(
                &nodes,
                &pad.faces,
                &rotor.faces,
                &MatchOptions::default(),
                &TieOptions::default(),
                &MortarOptions::default(),
            )
            .unwrap();
            let rows = squeal_contact::bond_rows(&out.gaps).unwrap();
            assert_eq!(rows.len(), nodes.len());
            let xr = rotor.xyz();
            for r in &rows {
                let s: f64 = r.masters.iter().map(|m| m.1).sum();
                assert!((s - 1.0).abs() < 1e-13, "{pk:?}/{rk:?}: {s}");
                for k in 0..3 {
                    let x: f64 = r.masters.iter().map(|&(a, w)| w * xr[&a][k]).sum();
                    assert!(
                        (x - r.coords[k]).abs() < 1e-13,
                        "{pk:?}/{rk:?} node {}",
                        r.node
                    );
                }
            }
        }
    }
}
