//! Surface pairing ([`tie_gaps`]): pad nodes tied to points of rotor faces (non-matching
//! meshes). Checks: the weights and G against rigid motions, equality with node matching for
//! coincident nodes, tangents against finite differences, the energy identity of the
//! friction forces (gather and scatter use the same weights), unmatched nodes, and the
//! analytic Hoffmann and belt references through a non-matching two-element patch.

use faer::Mat;
use squeal_contact::{
    match_gaps, tie_gaps, ContactError, ContactNode, FaceKind, FrictionLaw, GapSet, MatchOptions,
    RotorFace, TieOptions, Unmatched,
};
use squeal_solver::cea::{complex_eigen, sweep, CeaMatrices, CeaOptions, SweepOptions};

/// Rotor nodes of the two-element patch: x ∈ {0, 1, 2}, y ∈ {0, 1}, z = 0.
fn patch_nodes() -> Vec<(u64, [f64; 3])> {
    vec![
        (10, [0.0, 0.0, 0.0]),
        (11, [1.0, 0.0, 0.0]),
        (12, [1.0, 1.0, 0.0]),
        (13, [0.0, 1.0, 0.0]),
        (14, [2.0, 0.0, 0.0]),
        (15, [2.0, 1.0, 0.0]),
    ]
}

/// Two quad4 faces [0,1]×[0,1] and [1,2]×[0,1] sharing the edge 11–12 (counterclockwise
/// about +z).
fn two_faces() -> Vec<RotorFace> {
    let at = |id: u64| patch_nodes().into_iter().find(|n| n.0 == id).unwrap().1;
    [[10u64, 11, 12, 13], [11, 14, 15, 12]]
        .iter()
        .enumerate()
        .map(|(i, ids)| RotorFace {
            id: i as u64,
            kind: FaceKind::Quad4,
            nodes: ids.to_vec(),
            coords: ids.iter().map(|&n| at(n)).collect(),
        })
        .collect()
}

/// A pad node above the rotor (normal −z, toward the rotor) with area `a`.
fn pad_node(id: u64, x: f64, y: f64, a: f64) -> ContactNode {
    ContactNode {
        id,
        coords: [x, y, 0.0],
        area: [0.0, 0.0, -a],
    }
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

fn non_matching_pad() -> Vec<ContactNode> {
    let mut pad = Vec::new();
    for (i, &x) in [0.1, 0.75, 1.3, 1.9].iter().enumerate() {
        for (j, &y) in [0.2, 0.85].iter().enumerate() {
            pad.push(pad_node(100 + 2 * i as u64 + j as u64, x, y, 0.1));
        }
    }
    pad
}

fn all_ids(pad: &[ContactNode]) -> Vec<u64> {
    let mut ids: Vec<u64> = patch_nodes().iter().map(|n| n.0).collect();
    ids.extend(pad.iter().map(|p| p.id));
    ids
}

fn coords_of(id: u64, pad: &[ContactNode]) -> [f64; 3] {
    patch_nodes()
        .into_iter()
        .find(|n| n.0 == id)
        .map(|n| n.1)
        .or_else(|| pad.iter().find(|p| p.id == id).map(|p| p.coords))
        .unwrap()
}

/// Face coordinates and weights of bilinear quads (x = 1.3 on face 1 is ξ = 2·0.3 − 1 =
/// −0.4), weights summing to 1, and G u = 0 for the six rigid motions (translations: the
/// weights sum to 1; rotations: the pad and face points coincide, so the interpolated rotor
/// point moves with the pad node).
#[test]
fn weights_and_rigid_motions() {
    let pad = non_matching_pad();
    let out = tie_gaps(&pad, &two_faces(), &opts(), &TieOptions::default()).unwrap();
    assert_eq!(out.stats.n_tied, 8);
    assert!(out.unmatched.is_empty());
    let mut set = out.gaps;
    for g in &set.gaps {
        let t = g.tie.as_ref().unwrap();
        let x = g.coords[0];
        let (face, xi0) = if x < 1.0 {
            (0, 2.0 * x - 1.0)
        } else {
            (1, 2.0 * (x - 1.0) - 1.0)
        };
        assert_eq!(t.face, face);
        assert!((t.xi[0] - xi0).abs() < 1e-14, "{:?}", t.xi);
        assert!((t.xi[1] - (2.0 * g.coords[1] - 1.0)).abs() < 1e-14);
        assert!((t.weights.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!(t.distance < 1e-15);
    }
    let ids = all_ids(&pad);
    set.assign_dofs(dof_map(&ids));
    let n = 3 * ids.len();
    let g = set.constraint_matrix(n).unwrap();
    type Motion = Box<dyn Fn([f64; 3]) -> [f64; 3]>;
    let rigid: Vec<Motion> = vec![
        Box::new(|_| [1.0, 0.0, 0.0]),
        Box::new(|_| [0.0, 1.0, 0.0]),
        Box::new(|_| [0.0, 0.0, 1.0]),
        Box::new(|x| [0.0, -x[2], x[1]]),
        Box::new(|x| [x[2], 0.0, -x[0]]),
        Box::new(|x| [-x[1], x[0], 0.0]),
    ];
    for (r, motion) in rigid.iter().enumerate() {
        let mut u = vec![0.0; n];
        for (i, &id) in ids.iter().enumerate() {
            let d = motion(coords_of(id, &pad));
            u[3 * i..3 * i + 3].copy_from_slice(&d);
        }
        for row in 0..g.nrows() {
            let gu: f64 = (0..n).map(|j| g[(row, j)] * u[j]).sum();
            assert!(gu.abs() < 1e-14, "rigid motion {r}: (G u)_{row} = {gu}");
        }
    }
    // Each row sums to zero in each direction.
    for row in 0..g.nrows() {
        for k in 0..3 {
            let s: f64 = (0..ids.len()).map(|i| g[(row, 3 * i + k)]).sum();
            assert!(s.abs() < 1e-15);
        }
    }
}

fn law() -> FrictionLaw {
    FrictionLaw::Equation {
        mu0: 0.4,
        a: 0.05,
        b: -0.03,
        c: 0.0,
        t0: 0.0,
    }
}

fn pseudo_random(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

/// Pad nodes on the rotor nodes: the projection gives weight 1 on the coincident node and 0
/// on the others, and forces, both tangents and G equal those of node matching exactly.
#[test]
fn coincident_nodes_through_projection_equal_node_matching() {
    let pad: Vec<ContactNode> = patch_nodes()
        .iter()
        .map(|&(id, x)| pad_node(200 + id, x[0], x[1], 0.25))
        .collect();
    let rotor: Vec<ContactNode> = patch_nodes()
        .iter()
        .map(|&(id, coords)| ContactNode {
            id,
            coords,
            area: [0.0; 3],
        })
        .collect();
    let mut ids: Vec<u64> = patch_nodes().iter().map(|n| n.0).collect();
    ids.extend(pad.iter().map(|p| p.id));
    let n = 3 * ids.len();
    let mut a = match_gaps(&pad, &rotor, &opts())
        .unwrap()
        .with_friction(law(), 1e-3)
        .unwrap();
    let out = tie_gaps(&pad, &two_faces(), &opts(), &TieOptions::default()).unwrap();
    assert_eq!(out.stats.n_on_node, 6);
    let mut b = out.gaps.with_friction(law(), 1e-3).unwrap();
    a.assign_dofs(dof_map(&ids));
    b.assign_dofs(dof_map(&ids));
    for (ga, gb) in a.gaps.iter().zip(&b.gaps) {
        assert_eq!(ga.rotor_node, gb.rotor_node);
        let w = &gb.tie.as_ref().unwrap().weights;
        assert_eq!(w.iter().filter(|&&x| x == 1.0).count(), 1);
        assert_eq!(w.iter().filter(|&&x| x == 0.0).count(), 3);
        assert_eq!(gb.rotor_nodes(), vec![ga.rotor_node]);
    }
    let v: Vec<f64> = pseudo_random(n, 3).iter().map(|x| 0.2 * x).collect();
    let lam: Vec<f64> = pseudo_random(6, 5).iter().map(|x| -0.3 + 0.1 * x).collect();
    let (mut fa, mut fb) = (vec![0.0; n], vec![0.0; n]);
    a.add_forces(&v, &lam, &mut fa).unwrap();
    b.add_forces(&v, &lam, &mut fb).unwrap();
    assert_eq!(fa, fb);
    let (mut da, mut db) = (Mat::zeros(n, 6), Mat::zeros(n, 6));
    let (mut ca, mut cb) = (Mat::zeros(n, n), Mat::zeros(n, n));
    a.add_tangents(&v, &lam, &mut da, Some(&mut ca)).unwrap();
    b.add_tangents(&v, &lam, &mut db, Some(&mut cb)).unwrap();
    assert!(da == db && ca == cb);
    assert!(a.constraint_matrix(n).unwrap() == b.constraint_matrix(n).unwrap());
}

fn tied_set() -> (GapSet, usize) {
    let pad = non_matching_pad();
    let mut set = tie_gaps(&pad, &two_faces(), &opts(), &TieOptions::default())
        .unwrap()
        .gaps
        .with_friction(law(), 1e-3)
        .unwrap();
    let ids = all_ids(&pad);
    set.assign_dofs(dof_map(&ids));
    (set, 3 * ids.len())
}

fn forces(set: &GapSet, v: &[f64], lam: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; v.len()];
    set.add_forces(v, lam, &mut f).unwrap();
    f
}

/// ∂F/∂v and ∂F/∂λ̇ of tied gaps against central differences of the forces (states in and
/// out of the regularisation zone).
#[test]
fn tied_tangents_match_finite_differences() {
    let (set, n) = tied_set();
    let ng = set.len();
    for (seed, scale) in [(1, 1e-3), (2, 0.05), (3, 1.0)] {
        let v: Vec<f64> = pseudo_random(n, seed).iter().map(|x| x * scale).collect();
        let lam: Vec<f64> = pseudo_random(ng, seed + 10)
            .iter()
            .map(|x| -0.2 + 0.1 * x)
            .collect();
        let mut dl = Mat::zeros(n, ng);
        let mut dv = Mat::zeros(n, n);
        set.add_tangents(&v, &lam, &mut dl, Some(&mut dv)).unwrap();
        let dvmax = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .fold(0.0f64, |m, (i, j)| m.max(dv[(i, j)].abs()));
        for j in 0..n {
            let h = 1e-6 * scale;
            let (mut vp, mut vm) = (v.clone(), v.clone());
            vp[j] += h;
            vm[j] -= h;
            let (fp, fm) = (forces(&set, &vp, &lam), forces(&set, &vm, &lam));
            for i in 0..n {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                assert!(
                    (fd - dv[(i, j)]).abs() <= 1e-6 * (dv[(i, j)].abs() + dvmax),
                    "scale {scale}: d f{i}/d v{j}: fd {fd} vs {}",
                    dv[(i, j)]
                );
            }
        }
        for g in 0..ng {
            let h = 1e-6;
            let (mut lp, mut lm) = (lam.clone(), lam.clone());
            lp[g] += h;
            lm[g] -= h;
            let (fp, fm) = (forces(&set, &v, &lp), forces(&set, &v, &lm));
            for i in 0..n {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                assert!((fd - dl[(i, g)]).abs() <= 1e-6 * (1.0 + dl[(i, g)].abs()));
            }
        }
    }
}

/// The power of the scattered forces on the DOF velocities plus that on the sliding
/// velocities equals −Σ F_t r |V_t| computed from the gathered slip (eq. 6–7 dissipation):
/// scatter and gather use the same weights, so the energy balance closes.
#[test]
fn tied_friction_power_matches_dissipation() {
    let (set, n) = tied_set();
    let v: Vec<f64> = pseudo_random(n, 7).iter().map(|x| 0.3 * x).collect();
    let lam: Vec<f64> = pseudo_random(set.len(), 8)
        .iter()
        .map(|x| -0.2 + 0.05 * x)
        .collect();
    let f = forces(&set, &v, &lam);
    let mut power: f64 = f.iter().zip(&v).map(|(a, b)| a * b).sum();
    let mut dissipated = 0.0;
    for (g, gap) in set.gaps.iter().enumerate() {
        let o = set.gap_output(g, &v, &lam).unwrap();
        power -= (0..3)
            .map(|k| o.force_on_pad[k] * gap.v_slide[k])
            .sum::<f64>();
        dissipated += o.friction_force * o.slip_speed;
    }
    assert!(dissipated > 0.0, "{dissipated} {power}");
    assert!(
        (power + dissipated).abs() < 1e-13 * dissipated,
        "power {power} vs −{dissipated}"
    );
}

/// A pad node beyond the patch (x = 2.5) and one 0.5 above it are listed: with
/// `unmatched = error` in the error (ids and coordinates), with `exclude` in the outcome.
#[test]
fn unmatched_nodes_are_listed() {
    let mut pad = non_matching_pad();
    pad.push(pad_node(900, 2.5, 0.5, 0.1));
    pad.push(ContactNode {
        id: 901,
        coords: [0.5, 0.5, 0.5],
        area: [0.0, 0.0, -0.1],
    });
    let err = tie_gaps(&pad, &two_faces(), &opts(), &TieOptions::default()).unwrap_err();
    let msg = err.to_string();
    assert!(
        matches!(err, ContactError::Matching { ref nodes, .. } if nodes.len() == 2),
        "{msg}"
    );
    assert!(
        msg.contains("node 900 at (2.500000e0, 5.000000e-1, 0.000000e0)"),
        "{msg}"
    );
    assert!(msg.contains("node 901"), "{msg}");
    let ex = TieOptions {
        unmatched: Unmatched::Exclude,
        ..TieOptions::default()
    };
    let out = tie_gaps(&pad, &two_faces(), &opts(), &ex).unwrap();
    assert_eq!(out.gaps.len(), 8);
    assert_eq!(out.stats.n_excluded, 2);
    let ids: Vec<u64> = out.unmatched.iter().map(|r| r.id).collect();
    assert_eq!(ids, vec![900, 901]);
    // Inside the 1 % extension: x = 2.009 is ξ = 1.018 > 1.01 (out), x = 2.004 is 1.008 (in).
    let edge = [pad_node(1, 2.009, 0.5, 0.1), pad_node(2, 2.004, 0.5, 0.1)];
    let out = tie_gaps(&edge, &two_faces(), &opts(), &ex).unwrap();
    assert_eq!(
        out.unmatched.iter().map(|r| r.id).collect::<Vec<_>>(),
        vec![1]
    );
    assert!((out.stats.largest_outside - 0.008).abs() < 1e-12);
}

// ------------------------------------------------ analytic references through a tied patch

/// The pad node of the references: at (1.3, 0.4), inside face 1 at (ξ, η) = (−0.4, −0.2);
/// the rotor point is the bilinear combination of nodes 11, 14, 15, 12.
fn reference_gap(law: FrictionLaw, p0: f64) -> (GapSet, Vec<f64>) {
    let pad = [ContactNode {
        id: 1,
        coords: [1.3, 0.4, 0.0],
        area: [0.0, 0.0, 1.0],
    }];
    let o = MatchOptions {
        p0,
        ..MatchOptions::default()
    };
    let mut set = tie_gaps(&pad, &two_faces(), &o, &TieOptions::default())
        .unwrap()
        .gaps
        .with_friction(law, 1e-3)
        .unwrap();
    // Sliding velocity (1, 0, 0) (≫ 10·VTOL: no regularisation).
    set.gaps[0].v_slide = [1.0, 0.0, 0.0];
    // DOFs: pad x = 0, pad z = 1 (pad y fixed); rotor nodes 11, 14, 15, 12: z only, 2..5.
    set.assign_dofs(|id| match id {
        1 => [Some(0), None, Some(1)],
        11 => [None, None, Some(2)],
        14 => [None, None, Some(3)],
        15 => [None, None, Some(4)],
        12 => [None, None, Some(5)],
        _ => [None; 3],
    });
    let t = set.gaps[0].tie.clone().unwrap();
    assert_eq!(t.face, 1);
    assert!((t.xi[0] + 0.4).abs() < 1e-14 && (t.xi[1] + 0.2).abs() < 1e-14);
    (set, t.weights)
}

/// Rotor: each tied node a on a normal spring k_a = k3·Σ_b w_b² / ... chosen so the rotor
/// point's normal stiffness is k3 (a force F at the point puts w_a F on node a, which moves
/// w_a F/k_a; the point moves Σ w_a² F/k_a = F/k3 with k_a = k3 Σ_b w_b²), and a small mass
/// m_r each.
fn rotor_springs(w: &[f64], k3: f64) -> Vec<f64> {
    let s: f64 = w.iter().map(|x| x * x).sum();
    w.iter().map(|_| k3 * s).collect()
}

const K11: f64 = 1.0;
const K12: f64 = 0.3;
const K21: f64 = 0.3;
const K22: f64 = 1.2;
const K3: f64 = 1.0;
const M_R: f64 = 1e-6;

/// Hoffmann's 2-DOF model (see `hoffmann.rs` for the mapping) with the rotor point
/// interpolated on a face of a two-element patch. Reference (analytic, `solver/tests/cea.rs`):
/// μc = 1/3 undamped, 0.3425 with c = 0.05 on both DOFs, 0.3 with c = 0.1 on x only.
fn hoffmann(mu: f64, c1: f64, c2: f64) -> Result<CeaMatrices, ContactError> {
    let (set, w) = reference_gap(FrictionLaw::Constant { mu }, 1.0);
    let n = 6;
    let mut d = Mat::zeros(n, 1);
    let mut c_f = Mat::zeros(n, n);
    set.add_tangents(&[0.0; 6], &[0.0], &mut d, Some(&mut c_f))?;
    // Face node order 11, 14, 15, 12 = DOFs 2..5.
    let kr = rotor_springs(&w, K3);
    let mut k = Mat::zeros(n, n);
    k[(0, 0)] = K11;
    k[(0, 1)] = K12;
    k[(1, 0)] = K21;
    k[(1, 1)] = K22 - K3;
    let mut m = Mat::zeros(n, n);
    m[(0, 0)] = 1.0;
    m[(1, 1)] = 1.0;
    for a in 0..4 {
        k[(2 + a, 2 + a)] = kr[a];
        m[(2 + a, 2 + a)] = M_R;
    }
    let mut s = CeaMatrices::new(m, k);
    s.b = Some(Mat::from_fn(n, n, |i, j| {
        if i == j && i < 2 {
            [c1, c2][i]
        } else {
            0.0
        }
    }));
    s.g = Some(set.constraint_matrix(n)?);
    s.d = Some(d);
    s.c_f = Some(c_f);
    Ok(s)
}

fn critical_mu(c1: f64, c2: f64) -> f64 {
    let mus: Vec<f64> = (0..26).map(|i| 0.2 + 0.01 * i as f64).collect();
    let s = sweep(|mu| hoffmann(mu, c1, c2), &mus, &SweepOptions::default()).unwrap();
    let (_, c) = s.lowest_critical().expect("an onset inside the sweep");
    eprintln!(
        "tied patch, c1 = {c1}, c2 = {c2}: critical mu = {:.8}",
        c.mu
    );
    c.mu
}

#[test]
fn hoffmann_through_a_non_matching_patch() {
    let s = hoffmann(0.4, 0.0, 0.0).unwrap();
    let g = s.g.as_ref().unwrap();
    let row: Vec<f64> = (0..6).map(|j| g[(0, j)]).collect();
    assert_eq!(row[0], 0.0);
    assert_eq!(row[1], -1.0);
    assert!((row[2..].iter().sum::<f64>() - 1.0).abs() < 1e-15);
    assert!((critical_mu(0.0, 0.0) - 1.0 / 3.0).abs() < 1e-4);
    assert!((critical_mu(0.05, 0.05) - 0.3425).abs() < 1e-4);
    assert!((critical_mu(0.1, 0.0) - 0.3).abs() < 1e-4);
}

/// The belt of `solver/tests/bsql_verification.rs` through a tied gap: the pad's tangential
/// DOF (m, c, k) on a belt sliding at V = 1 with μ = μ0 − a|V_t|, pressed with N = P0·A; the
/// linearised tangential motion is m ẍ + (c − N a) ẋ + k x = 0, so the CEA root is
/// σ = (N a − c)/(2m), ω_d = √(k/m − σ²) (analytic), whatever the weights.
#[test]
fn belt_through_a_non_matching_patch() {
    let (m, k, c, n_load, mu0, a) = (
        1.0,
        (2.0 * std::f64::consts::PI).powi(2),
        0.3,
        10.0,
        0.5,
        0.05,
    );
    let law = FrictionLaw::LinearSpeed { mu0, slope: -a };
    let (set, w) = reference_gap(law, n_load);
    let n = 6;
    let mut d = Mat::zeros(n, 1);
    let mut c_f = Mat::zeros(n, n);
    set.add_tangents(&[0.0; 6], &[0.0], &mut d, Some(&mut c_f))
        .unwrap();
    let kr = rotor_springs(&w, 50.0);
    let mut mm = Mat::zeros(n, n);
    let mut kk = Mat::zeros(n, n);
    mm[(0, 0)] = m;
    kk[(0, 0)] = k;
    mm[(1, 1)] = 2.0;
    for i in 0..4 {
        mm[(2 + i, 2 + i)] = 0.01;
        kk[(2 + i, 2 + i)] = kr[i];
    }
    let mut s = CeaMatrices::new(mm, kk);
    s.b = Some(Mat::from_fn(
        n,
        n,
        |i, j| if i == 0 && j == 0 { c } else { 0.0 },
    ));
    s.g = Some(set.constraint_matrix(n).unwrap());
    s.d = Some(d);
    s.c_f = Some(c_f);
    let r = complex_eigen(&s, &CeaOptions::default()).unwrap();
    let sigma = (n_load * a - c) / (2.0 * m);
    let wd = (k / m - sigma * sigma).sqrt();
    let mode = r
        .modes
        .iter()
        .min_by(|p, q| {
            let e = |x: &squeal_solver::cea::Mode| (x.eigenvalue.im.abs() - wd).abs();
            e(p).total_cmp(&e(q))
        })
        .unwrap();
    eprintln!(
        "belt through a tied gap: root {} vs σ = {sigma}, ω = {wd}",
        mode.eigenvalue
    );
    assert!(
        (mode.eigenvalue.re - sigma).abs() < 1e-10,
        "{}",
        mode.eigenvalue
    );
    assert!((mode.eigenvalue.im.abs() - wd).abs() < 1e-10);
}

// ------------------------------------------------ every face kind, distorted

mod common;
use common::{contact_nodes, surface, tilted_plane};

/// Pad nodes of a non-matching pad (quad4 or tri3, nodes moved by up to 30 %) projected on
/// distorted rotor faces of every kind (quad4, quad8, tri3, tri6) on a tilted plane: every
/// node is tied at distance 0, its weights interpolate its own position (Σ N_a x_a = x: the
/// faces reproduce linear fields), and the rotor forces of a uniform pressure have the
/// exact resultant and moment (the one-pass tie's exact quantities; nodal forces are not,
/// see the mortar tests). Reference: the pad's consistent loads, summed.
#[test]
fn every_rotor_face_kind_interpolates_linear_fields() {
    let map = tilted_plane([0.1, 0.4, -0.3], 1.5);
    for rk in [
        FaceKind::Quad4,
        FaceKind::Quad8,
        FaceKind::Tri3,
        FaceKind::Tri6,
    ] {
        for pk in [FaceKind::Quad4, FaceKind::Tri3] {
            let rotor = surface(rk, 4, 3, 0.3, 11, 0, true, &map);
            let pad = surface(pk, 3, 2, 0.3, 12, 1_000_000, false, &map);
            let nodes = contact_nodes(&pad);
            let out = tie_gaps(&nodes, &rotor.faces, &opts(), &TieOptions::default())
                .unwrap_or_else(|e| panic!("{rk:?}: {e}"));
            assert_eq!(out.stats.n_tied, nodes.len());
            let xr = rotor.xyz();
            let (mut force, mut moment) = ([0.0; 3], [0.0; 3]);
            let (mut load, mut load_moment) = ([0.0; 3], [0.0; 3]);
            for (g, pn) in out.gaps.gaps.iter().zip(&nodes) {
                let t = g.tie.as_ref().unwrap();
                assert!(t.distance < 1e-12, "{rk:?}: {}", t.distance);
                for k in 0..3 {
                    let x: f64 = t
                        .nodes
                        .iter()
                        .zip(&t.weights)
                        .map(|(n, w)| w * xr[n][k])
                        .sum();
                    assert!((x - g.coords[k]).abs() < 1e-12, "{rk:?} {pk:?}");
                }
                // The rotor's share of the pressure force p·S_p (p = 1) at each face node.
                let f = pn.area;
                for (n, w) in t.nodes.iter().zip(&t.weights) {
                    let r = xr[n];
                    for k in 0..3 {
                        force[k] += w * f[k];
                    }
                    let m = [
                        r[1] * f[2] - r[2] * f[1],
                        r[2] * f[0] - r[0] * f[2],
                        r[0] * f[1] - r[1] * f[0],
                    ];
                    (0..3).for_each(|k| moment[k] += w * m[k]);
                }
                let r = pn.coords;
                (0..3).for_each(|k| load[k] += f[k]);
                let m = [
                    r[1] * f[2] - r[2] * f[1],
                    r[2] * f[0] - r[0] * f[2],
                    r[0] * f[1] - r[1] * f[0],
                ];
                (0..3).for_each(|k| load_moment[k] += m[k]);
            }
            for k in 0..3 {
                assert!(
                    (force[k] - load[k]).abs() < 1e-12,
                    "{rk:?} {pk:?} resultant"
                );
                assert!(
                    (moment[k] - load_moment[k]).abs() < 1e-12,
                    "{rk:?} {pk:?} moment"
                );
            }
        }
    }
}

/// A tri6 pad under node-to-surface pairing: its corners' consistent areas are 0 (∫N_corner
/// dΓ = 0 on a quadratic triangle), so the pairing refuses them by name and points to the
/// mortar pairing, instead of making gaps with round-off normals.
#[test]
fn tri6_pad_corners_are_refused_by_node_to_surface() {
    let map = tilted_plane([0.0; 3], 1.0);
    let rotor = surface(FaceKind::Quad4, 3, 3, 0.0, 1, 0, true, &map);
    let pad = surface(FaceKind::Tri6, 2, 2, 0.0, 2, 1_000_000, false, &map);
    let nodes = contact_nodes(&pad);
    let e = tie_gaps(&nodes, &rotor.faces, &opts(), &TieOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("use the mortar pairing"), "{msg}");
    // Exactly the corners (ids below the mid-side base) are named.
    let ContactError::Matching { nodes: bad, .. } = e else {
        panic!("{msg}")
    };
    assert_eq!(bad.len(), 9, "{msg}");
    assert!(bad.iter().all(|n| n.id < 1_100_000));
}
