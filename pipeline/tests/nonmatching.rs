//! Non-matching pad/rotor interfaces (`[[contact]] pairing = "surface"`).
//!
//! * Patch test (pure Rust, no gmsh): two elastic blocks stacked on a flat non-matching
//!   interface, a uniform pressure on top; the static solve with the tie constraints against
//!   the exact uniform-stress solution.
//! * The tiny brake with its coincident meshes paired through the projection: the same model
//!   and the same CEA roots as node pairing, to round-off.
//! * A rotor refined under an unchanged pad: the CEA roots approach those of a fine rotor
//!   mesh as the (non-matching) rotor mesh is refined.

use faer::linalg::solvers::Solve;
use faer::Mat;
use squeal_contact::{
    mortar_gaps, tie_gaps, ContactNode, FaceKind, MatchOptions, MortarOptions, RotorFace,
    TieOptions,
};
use squeal_fe::{assemble, face_areas, pressure_load, AssemblyOptions, DofMap, Material};
use squeal_meshes::structured::box_mesh;
use squeal_meshes::{CellKind, Mesh};

/// Offsets a mesh by `dz` in z.
fn shifted(mut m: Mesh, dz: f64) -> Mesh {
    for x in &mut m.nodes {
        x[2] += dz;
    }
    m
}

/// Fixed (node, component) pairs of the nodes at `at` (within 1e-12).
fn fixed_at(m: &Mesh, at: [f64; 3], comps: &[usize]) -> Vec<(usize, usize)> {
    let i = m
        .nodes
        .iter()
        .position(|x| (0..3).all(|k| (x[k] - at[k]).abs() < 1e-12))
        .expect("node exists");
    comps.iter().map(|&c| (i, c)).collect()
}

/// Result of the patch test: the largest error of the pad multipliers against the consistent
/// nodal loads, of the rotor's interface forces against its consistent nodal loads, of the
/// displacements against the exact field, and the errors of the resultant force and moment.
#[derive(Debug)]
struct Patch {
    pad_force_err: f64,
    rotor_force_err: f64,
    displacement_err: f64,
    resultant_err: f64,
    moment_err: f64,
}

/// Rotor [0,1]²×[−h,0] of `nr×nr` hex8 cells under a pad [0,1]²×[0,h] of `np×np` cells
/// (E_r = 2, E_p = 1, ν = 0.3), pressure p on the pad's top, rotor base on rollers, minimal
/// lateral supports (statically determinate: no reaction in the exact solution). The pad's
/// bottom nodes are tied to the rotor's top faces by `tie_gaps`; [K Gᵀ; G 0] solved densely.
///
/// Exact solution (uniaxial stress σ_zz = −p, free lateral expansion): u_z = −p(z + h)/E_r in
/// the rotor, u_z = −p h/E_r − p z/E_p in the pad, u_x = ν p x/E, u_y = ν p y/E; the
/// interface carries p on every point, so each pad node's multiplier is −p·A_g (A_g its
/// consistent area ∫N_g dA) and each rotor top node receives −p ∫N_a dA.
fn patch(nr: usize, np: usize, kind: CellKind) -> Patch {
    patch_with(nr, np, kind, kind, false)
}

/// Moves the corner nodes of `mesh` on the plane z = `z` in the plane, by up to `d` × `h`
/// (a deterministic pseudo-random direction and length; nodes on the unit square's edges
/// only along the edge, its corners not at all), then puts every mid-side node of a hex20 at
/// the midpoint of its edge (straight edges, as a mesher makes them on a flat face).
fn distort_plane(mesh: &mut Mesh, z: f64, d: f64, h: f64, seed: u64) {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut uniform = move || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        let v = s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        2.0 * (v as f64 / (1u64 << 53) as f64) - 1.0
    };
    let block = &mesh.volumes[0];
    let n_corner = 8;
    let mut corner = vec![false; mesh.nodes.len()];
    for c in 0..block.len() {
        for &n in &block.cell(c)[..n_corner] {
            corner[n] = true;
        }
    }
    for (i, x) in mesh.nodes.iter_mut().enumerate() {
        if !corner[i] || (x[2] - z).abs() > 1e-12 {
            continue;
        }
        let (mut dx, mut dy) = (uniform(), uniform());
        let len = (dx * dx + dy * dy).sqrt().max(1.0);
        dx *= d * h / len;
        dy *= d * h / len;
        let on = |v: f64| v.abs() < 1e-12 || (v - 1.0).abs() < 1e-12;
        if !on(x[0]) {
            x[0] += dx;
        }
        if !on(x[1]) {
            x[1] += dy;
        }
    }
    if block.kind == CellKind::Hex20 {
        const EDGES: [(usize, usize); 12] = [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (4, 5),
            (5, 6),
            (6, 7),
            (7, 4),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ];
        let cells: Vec<Vec<usize>> = (0..block.len()).map(|c| block.cell(c).to_vec()).collect();
        for c in cells {
            for (m, (a, b)) in EDGES.iter().enumerate() {
                let (xa, xb) = (mesh.nodes[c[*a]], mesh.nodes[c[*b]]);
                mesh.nodes[c[8 + m]] = [0, 1, 2].map(|k| 0.5 * (xa[k] + xb[k]));
            }
        }
    }
}

/// [`patch`] with the rotor's and the pad's cell kinds apart, tied by the node-to-surface
/// tie or (`mortar`) by [`mortar_gaps`] over the pad's bottom faces.
fn patch_with(nr: usize, np: usize, kind: CellKind, pad_kind: CellKind, mortar: bool) -> Patch {
    patch_distorted(nr, np, kind, pad_kind, mortar, 0.0)
}

/// [`patch_with`] with the interface's corner nodes of both meshes moved in its plane by up
/// to `distortion` × their cell size ([`distort_plane`]).
fn patch_distorted(
    nr: usize,
    np: usize,
    kind: CellKind,
    pad_kind: CellKind,
    mortar: bool,
    distortion: f64,
) -> Patch {
    let (h, p, nu) = (0.5, 3.0, 0.3);
    let (er, ep) = (2.0, 1.0);
    let mut rotor = shifted(box_mesh(1.0, 1.0, h, nr, nr, 1, kind), -h);
    let mut pad = box_mesh(1.0, 1.0, h, np, np, 1, pad_kind);
    if distortion > 0.0 {
        distort_plane(&mut rotor, 0.0, distortion, 1.0 / nr as f64, 3);
        distort_plane(&mut pad, 0.0, distortion, 1.0 / np as f64, 4);
    }
    let mat = |e: f64| Material {
        young: e,
        poisson: nu,
        density: 1.0,
    };
    // Rotor: base u_z = 0; x, y at (0,0,−h), y at (1,0,−h). Pad: x, y at (0,0,h), y at (1,0,h).
    let mut rfix: Vec<(usize, usize)> = rotor.node_sets["z0"].iter().map(|&n| (n, 2)).collect();
    rfix.extend(fixed_at(&rotor, [0.0, 0.0, -h], &[0, 1]));
    rfix.extend(fixed_at(&rotor, [1.0, 0.0, -h], &[1]));
    let mut pfix = fixed_at(&pad, [0.0, 0.0, h], &[0, 1]);
    pfix.extend(fixed_at(&pad, [1.0, 0.0, h], &[1]));
    let rd = DofMap::new(rotor.nodes.len(), &rfix).unwrap();
    let pd = DofMap::new(pad.nodes.len(), &pfix).unwrap();
    let opts = AssemblyOptions::default();
    let kr = assemble(&rotor, &[mat(er)], &rd, &opts).unwrap().k;
    let kp = assemble(&pad, &[mat(ep)], &pd, &opts).unwrap().k;
    let (nr_dof, np_dof) = (rd.n_free(), pd.n_free());
    let n = nr_dof + np_dof;
    // Node ids: rotor node i → i, pad node i → 100_000 + i.
    let pad_nodes: Vec<ContactNode> = face_areas(&pad, "z0")
        .unwrap()
        .into_iter()
        .map(|(i, s)| ContactNode {
            id: 100_000 + i as u64,
            coords: pad.nodes[i],
            area: s,
        })
        .collect();
    let block = &rotor.faces["z1"].blocks[0];
    let fk = if kind == CellKind::Hex8 {
        FaceKind::Quad4
    } else {
        FaceKind::Quad8
    };
    let faces: Vec<RotorFace> = (0..block.len())
        .map(|f| RotorFace {
            id: f as u64,
            kind: fk,
            nodes: block.cell(f).iter().map(|&i| i as u64).collect(),
            coords: block.cell(f).iter().map(|&i| rotor.nodes[i]).collect(),
        })
        .collect();
    let mut gaps = if mortar {
        let pb = &pad.faces["z0"].blocks[0];
        let pk = if pad_kind == CellKind::Hex8 {
            FaceKind::Quad4
        } else {
            FaceKind::Quad8
        };
        let pad_faces: Vec<RotorFace> = (0..pb.len())
            .map(|f| RotorFace {
                id: f as u64,
                kind: pk,
                nodes: pb.cell(f).iter().map(|&i| 100_000 + i as u64).collect(),
                coords: pb.cell(f).iter().map(|&i| pad.nodes[i]).collect(),
            })
            .collect();
        mortar_gaps(
            &pad_nodes,
            &pad_faces,
            &faces,
            &MatchOptions::default(),
            &TieOptions::default(),
            &MortarOptions::default(),
        )
        .unwrap()
        .0
        .gaps
    } else {
        tie_gaps(
            &pad_nodes,
            &faces,
            &MatchOptions::default(),
            &TieOptions::default(),
        )
        .unwrap()
        .gaps
    };
    gaps.assign_dofs(|id| {
        if id >= 100_000 {
            let i = (id - 100_000) as usize;
            [0, 1, 2].map(|k| pd.free(i, k).map(|d| nr_dof + d))
        } else {
            [0, 1, 2].map(|k| rd.free(id as usize, k))
        }
    });
    let g = gaps.constraint_matrix(n).unwrap();
    let ng = g.nrows();
    // KKT matrix and right-hand side.
    let mut a = Mat::<f64>::zeros(n + ng, n + ng);
    for (k, off) in [(&kr, 0), (&kp, nr_dof)] {
        for j in 0..k.ncols() {
            let (rows, vals) = (k.row_idx_of_col_raw(j), k.val_of_col(j));
            for (&i, &v) in rows.iter().zip(vals) {
                a[(off + i, off + j)] += v;
            }
        }
    }
    for r in 0..ng {
        for c in 0..n {
            a[(n + r, c)] = g[(r, c)];
            a[(c, n + r)] = g[(r, c)];
        }
    }
    let load = pressure_load(&pad, "z1", p, &pd).unwrap();
    let mut b = Mat::<f64>::zeros(n + ng, 1);
    for (i, &v) in load.iter().enumerate() {
        b[(nr_dof + i, 0)] = v;
    }
    let x = a.partial_piv_lu().solve(&b);
    // Multipliers against −p·A_g.
    let mut pad_force_err = 0.0f64;
    for (ig, gap) in gaps.gaps.iter().enumerate() {
        pad_force_err = pad_force_err.max((x[(n + ig, 0)] + p * gap.area).abs());
    }
    // Rotor interface forces −Gᵀλ against the consistent load of p on the rotor top.
    let mut rotor_force_err = 0.0f64;
    let (mut fz, mut mx, mut my) = (0.0, 0.0, 0.0);
    for (node, s) in face_areas(&rotor, "z1").unwrap() {
        let d = rd.free(node, 2).unwrap();
        let f: f64 = -(0..ng).map(|r| g[(r, d)] * x[(n + r, 0)]).sum::<f64>();
        rotor_force_err = rotor_force_err.max((f - (-p * s[2])).abs());
        fz += f;
        mx += f * rotor.nodes[node][1];
        my += f * rotor.nodes[node][0];
    }
    // Exact resultant −p and moments −p/2 (the centroid of the unit square).
    let resultant_err = (fz + p).abs();
    let moment_err = (mx + 0.5 * p).abs().max((my + 0.5 * p).abs());
    // Displacements against the exact field.
    let mut displacement_err = 0.0f64;
    for (mesh, dofs, off, e, top) in [(&rotor, &rd, 0, er, false), (&pad, &pd, nr_dof, ep, true)] {
        for (i, xn) in mesh.nodes.iter().enumerate() {
            let uz = if top {
                -p * h / er - p * xn[2] / e
            } else {
                -p * (xn[2] + h) / er
            };
            let exact = [nu * p * xn[0] / e, nu * p * xn[1] / e, uz];
            for k in 0..3 {
                if let Some(d) = dofs.free(i, k) {
                    displacement_err = displacement_err.max((x[(off + d, 0)] - exact[k]).abs());
                }
            }
        }
    }
    Patch {
        pad_force_err,
        rotor_force_err,
        displacement_err,
        resultant_err,
        moment_err,
    }
}

/// The pad mesh nested in the rotor's (4×4 pad faces on 2×2 rotor faces, hex8 and hex20: pad
/// nodes inside rotor faces and on their edges): the one-pass node-to-surface tie passes
/// the patch test exactly. Reference: the exact uniform-stress solution (see [`patch`]).
///
/// Why nested: the rotor nodal forces are Σ_g N_a(ξ_g)·p·A_g, a quadrature of p ∫N_a dA with
/// the pad nodes as points and their consistent areas as weights; it is exact when N_a
/// restricted to each pad face is in the pad face's space (bilinear, or serendipity for
/// quad8), i.e. when each pad face lies inside one rotor face of the same kind.
#[test]
fn patch_test_passes_exactly_on_a_nested_non_matching_interface() {
    for kind in [CellKind::Hex8, CellKind::Hex20] {
        let r = patch(2, 4, kind);
        eprintln!("nested 4x4 pad on 2x2 rotor ({kind:?}): {r:?}");
        assert!(r.pad_force_err < 1e-10, "{r:?}");
        assert!(r.rotor_force_err < 1e-10, "{r:?}");
        assert!(r.displacement_err < 1e-10, "{r:?}");
        assert!(r.resultant_err < 1e-10 && r.moment_err < 1e-10, "{r:?}");
    }
}

/// A coincident interface (2×2 on 2×2) passes too (weights 1 and 0: node pairing's case).
#[test]
fn patch_test_passes_on_a_coincident_interface() {
    let r = patch(2, 2, CellKind::Hex8);
    assert!(
        r.pad_force_err < 1e-10 && r.rotor_force_err < 1e-10,
        "{r:?}"
    );
    assert!(r.displacement_err < 1e-10, "{r:?}");
}

/// 2×2 pad faces on 3×3 rotor faces (no pad face inside one rotor face): the one-pass
/// node-to-surface tie transmits the resultant force and moment exactly (the face
/// interpolation reproduces linear functions: Σ_a N_a(ξ) x_a = x), but not the uniform
/// pressure node by node — the known limit of node-to-surface contact (Taylor and
/// Papadopoulos, "On a patch test for contact problems in two dimensions", 1991; a
/// segment-to-segment/mortar tie would pass it). The measured nodal errors are printed.
#[test]
fn general_non_matching_interface_transmits_resultant_and_moment_exactly() {
    let r = patch(3, 2, CellKind::Hex8);
    eprintln!("2x2 pad on 3x3 rotor: {r:?} (p = 3)");
    assert!(r.resultant_err < 1e-10 && r.moment_err < 1e-10, "{r:?}");
}

/// The mortar tie (dual Lagrange multipliers on the pad's faces) passes the patch test
/// exactly where the node-to-surface tie does not: 2×2 pad faces on 3×3 rotor faces (0.73
/// largest displacement error with the node-to-surface tie), and 2×2 on 4×4; hex8 rotor, and a
/// hex20 rotor under the hex8 pad (serendipity rotor faces). Reference: the exact
/// uniform-stress solution (see [`patch`]); multipliers −p·D_j, rotor nodal forces
/// −p ∫N_a dA, displacements, all to round-off.
#[test]
fn mortar_tie_passes_the_patch_test_on_any_non_matching_interface() {
    for (nr, np, rk) in [
        (3, 2, CellKind::Hex8),
        (4, 2, CellKind::Hex8),
        (3, 2, CellKind::Hex20),
        (2, 3, CellKind::Hex8),
    ] {
        let r = patch_with(nr, np, rk, CellKind::Hex8, true);
        eprintln!("mortar: {np}x{np} hex8 pad on {nr}x{nr} {rk:?} rotor: {r:?}");
        assert!(r.pad_force_err < 1e-10, "{r:?}");
        assert!(r.rotor_force_err < 1e-10, "{r:?}");
        assert!(r.displacement_err < 1e-10, "{r:?}");
        assert!(r.resultant_err < 1e-10 && r.moment_err < 1e-10, "{r:?}");
    }
    // The node-to-surface tie on the same 2×2-on-3×3 interface, for contrast (README: 0.73).
    let r = patch(3, 2, CellKind::Hex8);
    assert!(r.displacement_err > 0.1, "{r:?}");
}

/// The solid patch test through the mortar tie on distorted, non-matching interfaces: the
/// interface's corner nodes of both blocks moved in its plane by up to 30 % of their cell
/// size, hex8 and hex20 (quad4 and quad8 faces, mid-side nodes at the midpoints) on either
/// side, 2×2 pad cells on 3×3 rotor cells and 3×3 on 2×2. Reference: the exact
/// uniform-stress solution ([`patch`]: isoparametric elements reproduce it on any mesh):
/// multipliers −p·A_j (A_j the gap's area: D_j, or D̂_j on quad8), the rotor's consistent
/// nodal loads, the displacements, the resultant and moment, all to 1e-10.
#[test]
fn mortar_patch_test_passes_on_distorted_interfaces_of_hex8_and_hex20() {
    for (nr, np) in [(3, 2), (2, 3)] {
        for rk in [CellKind::Hex8, CellKind::Hex20] {
            for pk in [CellKind::Hex8, CellKind::Hex20] {
                let r = patch_distorted(nr, np, rk, pk, true, 0.3);
                eprintln!("mortar, 30 %: {np}x{np} {pk:?} pad on {nr}x{nr} {rk:?} rotor: {r:?}");
                assert!(r.pad_force_err < 1e-10, "{r:?}");
                assert!(r.rotor_force_err < 1e-10, "{r:?}");
                assert!(r.displacement_err < 1e-10, "{r:?}");
                assert!(r.resultant_err < 1e-10 && r.moment_err < 1e-10, "{r:?}");
            }
        }
    }
}

// ------------------------------------------------------------- meshed scenes (gmsh)

use squeal_pipeline::problem::system;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::cea::{self, CeaArgs};
use squeal_pipeline::stages::model::{self, ReducedModel};
use squeal_pipeline::{RunDir, Scene};

/// The tiny brake (`examples/cea/tiny-brake-cea.toml`: block rotor, block pad pressed on it,
/// falling μ(v)) with `np×np` pad cells on `nr×nr` rotor cells (hex8) and the given pairing.
fn tiny_brake(np: usize, nr: usize, pairing: &str) -> String {
    format!(
        r#"title = "tiny brake, pad {np}x{np} on rotor {nr}x{nr}, {pairing}"
units = "consistent"

[[components]]
name = "rotor"
element = "hex8"
geometry = {{ kind = "block", origin = [2.0, -0.5, -0.2], lx = 1.0, ly = 1.0, lz = 0.2, nx = {nr}, ny = {nr}, nz = 1 }}
material = {{ young = 1.0e4, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "z0" }}]

[[components]]
name = "pad"
element = "hex8"
geometry = {{ kind = "block", origin = [2.0, -0.5, 0.0], lx = 1.0, ly = 1.0, lz = 0.2, nx = {np}, ny = {np}, nz = 1 }}
material = {{ young = 5.0e3, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "x0", dofs = "xy" }}]

[reduction]
n_modes = 6

[[contact]]
pad = "pad"
pad_faces = "z0"
rotor = "rotor"
rotor_faces = "z1"
pairing = "{pairing}"
p0 = 1.0

[friction]
law = {{ kind = "linear_speed", mu0 = 0.6, slope = -0.05 }}
vtol = 1e-3

[rotor]
rpm = 10.0

[loads]
pmax = 2.0
tload = 0.01
pressure = [{{ component = "pad", faces = "z1", pressure = 1.0 }}]

[damping]
modal_ratio = 0.01

[cea]
at = "steady_state"
friction_damping = true
"#
    )
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("squeal-nm-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn build(text: &str, dir: &std::path::Path) -> (Scene, ReducedModel) {
    let scene = Scene::from_toml_str(text, dir.to_path_buf(), &[]).unwrap();
    let run = RunDir::create(&dir.join(format!("run{}", text.len()))).unwrap();
    let m = model::build(&scene, &run, &Progress::quiet()).unwrap();
    (scene, m)
}

/// CEA eigenvalues (rad/s) of a scene's model, sorted by |Im|.
fn roots(scene: &Scene, m: &ReducedModel) -> Vec<squeal_solver::cea::Cplx> {
    let c = cea::compute(scene, m, &Progress::quiet(), &CeaArgs::default()).unwrap();
    let mut r: Vec<_> = c.modes.iter().map(|m| m.eigenvalue).collect();
    r.sort_by(|a, b| a.im.abs().total_cmp(&b.im.abs()));
    r
}

/// Largest relative distance from each of the first `k` roots of `a` to the nearest root of `b`.
fn root_error(a: &[squeal_solver::cea::Cplx], b: &[squeal_solver::cea::Cplx], k: usize) -> f64 {
    a.iter()
        .take(k)
        .map(|x| {
            b.iter()
                .map(|y| (x - y).norm() / x.norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// The tiny brake's coincident meshes paired by projection: every gap has weight 1 on its
/// node, the reduced matrices are the node-paired model's bit for bit, and the CEA roots agree
/// to 1e-10 relative (reference: node pairing, PREBSQL's rule).
#[test]
fn surface_pairing_of_coincident_meshes_equals_node_pairing() {
    let d = tmp("coincident");
    let (sa, ma) = build(&tiny_brake(2, 2, "nodes"), &d);
    let (sb, mb) = build(&tiny_brake(2, 2, "surface"), &d);
    assert_eq!(ma.gap_geometry.len(), mb.gap_geometry.len());
    for (a, b) in ma.gap_geometry.gaps.iter().zip(&mb.gap_geometry.gaps) {
        assert_eq!((a.pad_node, a.rotor_node), (b.pad_node, b.rotor_node));
        let t = b.tie.as_ref().expect("tied");
        assert_eq!(t.weights.iter().filter(|&&w| w == 1.0).count(), 1);
        assert_eq!(t.weights.iter().filter(|&&w| w == 0.0).count(), 3);
    }
    assert!(
        ma.k == mb.k && ma.m == mb.m,
        "same boundary DOFs, same reduction"
    );
    let (ra, rb) = (roots(&sa, &ma), roots(&sb, &mb));
    assert_eq!(ra.len(), rb.len());
    let e = root_error(&ra, &rb, ra.len());
    eprintln!(
        "coincident via projection: {} roots, max relative difference {e:.2e}",
        ra.len()
    );
    assert!(e < 1e-10, "{e}");
}

/// Refinement: at each level the coincident tiny brake (pad n×n on rotor n×n, node pairing)
/// against the same brake with a finer, non-matching rotor (1.5n × 1.5n cells, surface
/// pairing: pad nodes fall inside rotor faces and on their edges). Both converge to the same
/// continuum, so their lowest six CEA roots (the modes the 6 fixed-interface modes per
/// component resolve) must agree within a discretisation error that falls with refinement.
/// Measured (debug build, `--nocapture`): 4.08e-2 (n = 2), 3.48e-3 (4), 1.66e-3 (6), and
/// 9.9e-4 at n = 8 (not run here: 45 s).
#[test]
fn finer_non_matching_rotor_converges_with_refinement() {
    let d = tmp("refine");
    let mut errors = Vec::new();
    for (n, m) in [(2, 3), (4, 6), (6, 9)] {
        let (sa, ma) = build(&tiny_brake(n, n, "nodes"), &d);
        let (sb, mb) = build(&tiny_brake(n, m, "surface"), &d);
        let inside = mb
            .gap_geometry
            .gaps
            .iter()
            .filter(|g| {
                g.tie
                    .as_ref()
                    .is_some_and(|t| t.weights.iter().all(|&w| w < 1.0))
            })
            .count();
        assert!(inside > 0, "some pad nodes are not on rotor nodes");
        let e = root_error(&roots(&sa, &ma), &roots(&sb, &mb), 6);
        eprintln!("pad {n}x{n}: rotor {n}x{n} (nodes) vs {m}x{m} (surface, {inside} gaps between rotor nodes): lowest 6 CEA roots differ by {e:.3e}");
        errors.push(e);
    }
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "{errors:?}");
    assert!(errors[2] < 3e-3 && errors[0] < 0.1, "{errors:?}");
}

/// The short transient of the tiny brake (0.03 s: the brake load ramps to 2 in 0.01 s, then
/// the pad rings): the displacements of three pad grids averaged over the loaded phase,
/// coincident (pad n×n on rotor n×n) against the finer non-matching rotor (1.5n × 1.5n,
/// surface pairing). The relative difference falls with refinement, as the CEA roots do.
#[test]
fn short_transient_converges_with_refinement() {
    use squeal_pipeline::stages::transient::{self, TransientOptions};
    let d = tmp("transient");
    let extra = "\n[transient]\ntfinal = 0.03\natol1 = 1e-9\nrtol1 = 1e-4\nnoutpt = 2\n";
    let last = |text: &str| {
        let (s, m) = build(text, &d);
        let r = transient::compute(
            &s,
            &m,
            &Progress::quiet(),
            &TransientOptions {
                keep_history: true,
                ..Default::default()
            },
        )
        .unwrap();
        let h = r.history.expect("history kept");
        let t = h.column("t").unwrap();
        assert!((t[t.len() - 1] - 0.03).abs() < 1e-12);
        // Time average over the loaded phase [0.01, 0.03] (trapezoids on the recorded steps):
        // less sensitive to the phase of the ringing than the end value.
        let mut u = Vec::new();
        for c in &h.columns {
            if c.name.starts_with("u_") {
                let x = h.column(&c.name).unwrap();
                let mut acc = 0.0;
                for i in 1..t.len() {
                    if t[i - 1] >= 0.01 {
                        acc += 0.5 * (x[i] + x[i - 1]) * (t[i] - t[i - 1]);
                    }
                }
                u.push((c.name.clone(), acc / 0.02));
            }
        }
        u
    };
    let mut errors = Vec::new();
    for (n, m) in [(2, 3), (4, 6)] {
        let a = last(&format!("{}{extra}", tiny_brake(n, n, "nodes")));
        let b = last(&format!("{}{extra}", tiny_brake(n, m, "surface")));
        assert_eq!(
            a.iter().map(|x| &x.0).collect::<Vec<_>>(),
            b.iter().map(|x| &x.0).collect::<Vec<_>>()
        );
        let scale = a.iter().fold(0.0f64, |s, x| s.max(x.1.abs()));
        let e = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |s, (x, y)| s.max((x.1 - y.1).abs()))
            / scale;
        eprintln!("transient, pad {n}x{n}: rotor {n}x{n} vs {m}x{m}: mean pad displacements over [0.01, 0.03] s differ by {e:.3e} (largest {scale:.3e})");
        errors.push(e);
    }
    assert!(errors[1] < errors[0], "{errors:?}");
}

/// `squeal reduce`'s files of a surface-paired model read back as a stored model (`[model]
/// from = "op4"`, `gaps = "gaps.csv"` with the face columns): the same ties and the same CEA
/// roots as the meshed model (reference: the meshed model itself; the CSV keeps every digit).
#[test]
fn surface_paired_gap_table_round_trips_through_a_stored_model() {
    stored_round_trip(
        &tiny_brake(2, 3, "surface"),
        "stored",
        ",face,xi,eta,face_grids,weights",
    );
}

/// The same round trip for hex20 pads paired by mortar (the default): the gaps' pad sides
/// (`pad_grids`, `pad_weights`) come back with the ties, and the CEA roots with them.
#[test]
fn mortar_gap_table_with_pad_sides_round_trips_through_a_stored_model() {
    let text = tiny_brake(2, 3, "nodes")
        .replace("element = \"hex8\"", "element = \"hex20\"")
        .replace("pairing = \"nodes\"\n", "");
    stored_round_trip(&text, "stored-mortar", ",weights,pad_grids,pad_weights");
}

/// Builds `text`, writes it as `squeal reduce` does, reads it back through `gaps.csv` (whose
/// header ends with `header_end`) and compares ties, pad sides and CEA roots.
fn stored_round_trip(text: &str, name: &str, header_end: &str) {
    let d = tmp(name);
    let (s, m) = build(text, &d);
    let run = RunDir::create(&d.join("reduced")).unwrap();
    let gaps = system::problem(&s, &m).unwrap().gaps;
    model::write_stored(&m, &gaps, &run).unwrap();
    let csv = std::fs::read_to_string(d.join("reduced/gaps.csv")).unwrap();
    assert!(csv.lines().next().unwrap().ends_with(header_end), "{csv}");
    let stored = r#"title = "stored tiny brake, surface paired"
units = "consistent"

[model]
from = "op4"
matrices = "reduced/reduced.op4"
dofmap = "reduced/dofmap.json"
gaps = "reduced/gaps.csv"

[friction]
law = { kind = "linear_speed", mu0 = 0.6, slope = -0.05 }
vtol = 1e-3

[rotor]
rpm = 10.0

[loads]
pmax = 2.0
tload = 0.01

[damping]
modal_ratio = 0.01

[cea]
at = "steady_state"
friction_damping = true
"#;
    let (s2, m2) = build(stored, &d);
    // The gaps at the operating point: geometry, pairing and sliding velocities.
    let (ga, gb) = (gaps, system::problem(&s2, &m2).unwrap().gaps);
    assert_eq!(ga.len(), gb.len());
    for (a, b) in ga.gaps.iter().zip(&gb.gaps) {
        let (ta, tb) = (a.tie.as_ref().unwrap(), b.tie.as_ref().unwrap());
        assert_eq!(
            (ta.face, ta.xi, &ta.nodes, &ta.weights),
            (tb.face, tb.xi, &tb.nodes, &tb.weights)
        );
        assert_eq!(a.rotor_terms().count(), b.rotor_terms().count());
        assert_eq!(a.pad_side, b.pad_side);
        assert_eq!(a.pad_terms().count(), b.pad_terms().count());
        assert_eq!(a.v_slide, b.v_slide);
    }
    let e = root_error(&roots(&s, &m), &roots(&s2, &m2), 12);
    eprintln!("stored {name} model: lowest 12 CEA roots differ by {e:.2e}");
    assert!(e < 1e-10, "{e}");
}

/// A pad overhanging the rotor by 0.3 (pad nodes at x = 3.3, the rotor ends at 3): with
/// `unmatched = "error"` (the default) the build stops naming the pair and every overhanging
/// node with its coordinates; with `"exclude"` those nodes get no gap and a warning lists them.
/// Setting a surface key on a node-paired pair is an error naming it.
#[test]
fn overhanging_pad_nodes_are_an_error_or_excluded_with_a_warning() {
    let d = tmp("overhang");
    let text = tiny_brake(2, 3, "surface")
        .replace("origin = [2.0, -0.5, 0.0]", "origin = [2.3, -0.5, 0.0]");
    let scene = Scene::from_toml_str(&text, d.clone(), &[]).unwrap();
    let run = RunDir::create(&d.join("err")).unwrap();
    let msg = model::build(&scene, &run, &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(msg.contains("contact[0]"), "{msg}");
    assert!(msg.contains("gap matching failed for 3 node(s)"), "{msg}");
    assert_eq!(msg.matches("at (3.300000e0, ").count(), 3, "{msg}");
    let text = text.replace(
        "pairing = \"surface\"",
        "pairing = \"surface\"\nunmatched = \"exclude\"",
    );
    let (_, m) = build(&text, &d);
    assert_eq!(m.gap_geometry.len(), 6);
    // One warning lists the excluded nodes. The only other warnings allowed are the reduction
    // checks': this test's `n_modes = 6` truncates the pad (34.8 % error at its 18th mode),
    // which the Craig–Bampton check reports as a warning since the cheap checks landed.
    let unmatched: Vec<_> = m
        .warnings
        .iter()
        .filter(|w| w.input == "contact[0].unmatched")
        .collect();
    assert_eq!(unmatched.len(), 1, "{:?}", m.warnings);
    assert_eq!(unmatched[0].value, 3.0);
    assert!(
        m.warnings
            .iter()
            .all(|w| w.input == "contact[0].unmatched" || w.input.starts_with("reduction.checks")),
        "{:?}",
        m.warnings
    );
    let bad = tiny_brake(2, 2, "nodes").replace("p0 = 1.0\n", "p0 = 1.0\nextension = 0.5\n");
    let e = Scene::from_toml_str(&bad, d.clone(), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("contact[0].extension"), "{e}");
    // Every pad node off the rotor (issue 26): the pair has no gap, and the error names the
    // pair's key and the exclusion instead of a singular factorisation.
    let off = tiny_brake(2, 3, "surface")
        .replace("origin = [2.0, -0.5, 0.0]", "origin = [5.0, -0.5, 0.0]")
        .replace(
            "pairing = \"surface\"",
            "pairing = \"surface\"\nunmatched = \"exclude\"",
        );
    let scene = Scene::from_toml_str(&off, d.clone(), &[]).unwrap();
    let run = RunDir::create(&d.join("off")).unwrap();
    let msg = model::build(&scene, &run, &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("contact[0].unmatched")
            && msg.contains("\"exclude\" left this pair without a gap")
            && msg.contains("all 9 pad node(s)"),
        "{msg}"
    );
}

/// Quadratic pads pair by mortar unless the scene says otherwise, and that is what keeps their
/// corners in contact: the tiny brake in hex20 (quad8 contact faces, coincident 2×2 meshes)
/// under its brake load, CEA at the steady state. With no `pairing`: the mortar gaps (the
/// mid-side gaps with their transformed pad side), no tensile gap, every contact pressure
/// positive. With `pairing = "nodes"` (and "surface"), as before: a warning naming the pair,
/// and the corner gaps in tension (their multipliers are the consistent corner forces, −1/12
/// of a face's; docs/pairing.md). The CEA runs on all three.
#[test]
fn quadratic_pads_pair_by_mortar_by_default_without_tensile_corners() {
    use squeal_pipeline::stages::cea;
    let d = tmp("quadratic-default");
    let hex20 = |pairing: &str| {
        let t = tiny_brake(2, 2, "nodes").replace("element = \"hex8\"", "element = \"hex20\"");
        match pairing {
            "" => t.replace("pairing = \"nodes\"\n", ""),
            p => t.replace("pairing = \"nodes\"", &format!("pairing = \"{p}\"")),
        }
    };
    for pairing in ["", "nodes", "surface"] {
        let (scene, m) = build(&hex20(pairing), &d);
        let args = cea::CeaArgs::default();
        let c = cea::compute(&scene, &m, &Progress::quiet(), &args).unwrap();
        let run = RunDir::create(&d.join(format!("cea-{pairing}"))).unwrap();
        let r = cea::write(&c, &m, &run, &args, None, std::time::Instant::now()).unwrap();
        let pmin = r.min_contact_pressure.unwrap();
        let sided = m
            .gap_geometry
            .gaps
            .iter()
            .filter(|g| g.pad_side.is_some())
            .count();
        let warned = m.warnings.iter().any(|w| w.input == "contact[0].pairing");
        eprintln!(
            "hex20 pads, pairing {pairing:?}: {} gaps ({sided} with a pad side), {} tensile, \
             smallest p_n {pmin:.4}, {} modes",
            m.gap_geometry.len(),
            r.n_tensile_gaps,
            c.modes.len()
        );
        assert!(!c.modes.is_empty());
        if pairing.is_empty() {
            assert!(m
                .gap_geometry
                .gaps
                .iter()
                .all(|g| g.tie.as_ref().is_some_and(|t| t.mortar)));
            assert_eq!(sided, 12, "the 12 mid-side nodes of the 2×2 quad8 face set");
            assert_eq!(r.n_tensile_gaps, 0);
            assert!(pmin > 0.0 && !warned);
        } else {
            assert!(warned, "{:?}", m.warnings);
            assert!(r.n_tensile_gaps > 0 && pmin < 0.0, "{pmin}");
        }
    }
}

// ------------------------------------------- pad position sweep: the rotor reduced once

/// A block rotor (1.4 × 1.4, 5×5 hex8 cells) under a smaller block pad (1 × 1, 3×3 cells)
/// tied by surface pairing, the rotor's whole top face its Craig–Bampton boundary
/// (`boundary = "contact_faces"`), the pad turned by `rotate` (a `rotate_deg` line or "").
fn turning_pad(rotate: &str) -> String {
    format!(
        r#"title = "pad turning on a block rotor"
units = "consistent"

[[components]]
name = "rotor"
element = "hex8"
geometry = {{ kind = "block", origin = [1.8, -0.7, -0.2], lx = 1.4, ly = 1.4, lz = 0.2, nx = 5, ny = 5, nz = 1 }}
material = {{ young = 1.0e4, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "z0" }}]
boundary = "contact_faces"

[[components]]
name = "pad"
element = "hex8"
geometry = {{ kind = "block", origin = [2.0, -0.5, 0.0], lx = 1.0, ly = 1.0, lz = 0.2, nx = 3, ny = 3, nz = 1 }}
material = {{ young = 5.0e3, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "x0", dofs = "xy" }}]
{rotate}

[reduction]
n_modes = 6

[[contact]]
pad = "pad"
pad_faces = "z0"
rotor = "rotor"
rotor_faces = "z1"
pairing = "surface"
p0 = 1.0

[friction]
law = {{ kind = "constant", mu = 0.5 }}

[rotor]
rpm = 10.0

[loads]
pmax = 2.0
pressure = [{{ component = "pad", faces = "z1", pressure = 1.0 }}]

[cea]
at = "steady_state"
"#
    )
}

/// A sweep over the pad's angular position through the model cache reduces the rotor once:
/// turning the pad (by 3°, a continuous parameter) changes the pad's reduction and the gaps
/// but not the rotor's Craig–Bampton inputs, so the rotor's reduction is read from the
/// component cache (hit), and the model equals, bit for bit, the one built without any cache.
/// Angle 0 written out is the unrotated scene (same key, same model); a full turn (360°) is
/// the unrotated model to round-off.
#[test]
fn pad_angle_sweep_reuses_the_rotor_reduction() {
    use squeal_pipeline::stages::model::cache::key::ModelKey;
    use squeal_pipeline::stages::model::ModelCache;
    let d = tmp("turning");
    let cache = ModelCache::new(d.join("cache"));
    let scene = |rotate: &str| Scene::from_toml_str(&turning_pad(rotate), d.clone(), &[]).unwrap();
    let run = RunDir::create(&d.join("run")).unwrap();
    let q = Progress::quiet();
    let use_of = |m: &ReducedModel, name: &str| {
        m.components
            .iter()
            .find(|c| c.name == name)
            .and_then(|c| c.reduction_cache.clone())
            .expect("built through the cache")
    };

    let s0 = scene("");
    let (m0, u0) = cache.get_or_build(&s0, &run, &q).unwrap();
    assert!(!u0.hit);
    let (r0, p0) = (use_of(&m0, "rotor"), use_of(&m0, "pad"));
    assert!(!r0.hit && !p0.hit, "first build reduces both");
    // The rotor's boundary is its whole top face: 6×6 nodes × 3 DOFs.
    let rotor = m0.components.iter().find(|c| c.name == "rotor").unwrap();
    assert_eq!(rotor.n_boundary_dofs, 36 * 3);

    let s3 = scene("rotate_deg = 3.0");
    let (m3, u3) = cache.get_or_build(&s3, &run, &q).unwrap();
    assert!(!u3.hit, "a new pad angle is a new model");
    let (r3, p3) = (use_of(&m3, "rotor"), use_of(&m3, "pad"));
    assert!(r3.hit, "the rotor's reduction is read back, not recomputed");
    assert_eq!(r3.key, r0.key);
    assert!(
        !p3.hit && p3.key != p0.key,
        "the turned pad is reduced anew"
    );
    assert!(m3
        .components
        .iter()
        .all(|c| c.cb_stats.is_none() == (c.name == "rotor")));
    let entries = std::fs::read_dir(d.join("cache").join("components"))
        .unwrap()
        .filter(|e| {
            let n = e.as_ref().unwrap().file_name();
            !n.to_string_lossy().starts_with('.')
        })
        .count();
    assert_eq!(entries, 3, "rotor once, pad at 0° and 3°");

    // The same model as built without any cache, bit for bit, and the same CEA.
    let fresh = model::build(&s3, &run, &q).unwrap();
    assert!(fresh.k == m3.k && fresh.m == m3.m && fresh.p_brake == m3.p_brake);
    assert_eq!(fresh.gap_geometry.gaps, m3.gap_geometry.gaps);
    let (ra, rb) = (roots(&s3, &fresh), roots(&s3, &m3));
    assert!(root_error(&ra, &rb, ra.len()) == 0.0);
    // The gaps moved with the pad: the pad turned, the rotor points followed on its faces.
    assert_ne!(
        m0.gap_geometry.gaps[0].coords,
        m3.gap_geometry.gaps[0].coords
    );

    // Angle 0 written out is the unrotated scene.
    let z = scene("rotate_deg = 0.0");
    assert_eq!(ModelKey::of(&z).unwrap(), ModelKey::of(&s0).unwrap());
    let (mz, uz) = cache.get_or_build(&z, &run, &q).unwrap();
    assert!(uz.hit && mz.k == m0.k && mz.m == m0.m);
    // A full turn: the unrotated model to round-off (sin 2π ≈ −2.4e-16).
    let full = model::build(&scene("rotate_deg = 360.0"), &run, &q).unwrap();
    let base = model::build(&s0, &run, &q).unwrap();
    let rel = |a: &faer::Mat<f64>, b: &faer::Mat<f64>| (a - b).norm_l2() / b.norm_l2();
    assert!(rel(&full.k, &base.k) < 1e-12 && rel(&full.m, &base.m) < 1e-12);
    let (rf, rz) = (roots(&s0, &full), roots(&s0, &base));
    let e = root_error(&rf, &rz, rf.len());
    assert!(e < 1e-10, "{e}");
}

/// A stored surface-paired model read from `gaps.json` places every tied rotor node: the
/// gap table records each tie's face-node coordinates, so `cea_modes.vtu` has a point for
/// every grid of the reduced model (before: only the gaps' pad and main rotor grids, the
/// other face nodes left out), at the meshed model's coordinates.
#[test]
fn stored_tied_model_writes_every_face_node_to_the_vtu() {
    use squeal_pipeline::stages::cea::outputs::write_mode_shapes;
    use squeal_reduction::superelement::DofKind;
    let d = tmp("stored-vtu");
    let (s, m) = build(&tiny_brake(2, 3, "surface"), &d);
    let run = RunDir::create(&d.join("reduced")).unwrap();
    let gaps = system::problem(&s, &m).unwrap().gaps;
    model::write_stored(&m, &gaps, &run).unwrap();
    let stored = r#"title = "stored tiny brake, surface paired, gaps.json"
units = "consistent"

[model]
from = "op4"
matrices = "reduced/reduced.op4"
dofmap = "reduced/dofmap.json"
gaps = "reduced/gaps.json"

[friction]
law = { kind = "linear_speed", mu0 = 0.6, slope = -0.05 }

[rotor]
rpm = 10.0

[loads]
pmax = 2.0

[cea]
at = "steady_state"
"#;
    let (s2, m2) = build(stored, &d);
    let c = cea::compute(&s2, &m2, &Progress::quiet(), &CeaArgs::default()).unwrap();
    let out = RunDir::create(&d.join("vtu")).unwrap();
    let n = write_mode_shapes(&out, &m2, &[(0, &c.modes[0])]).unwrap();
    let grids: std::collections::BTreeSet<u64> = m2
        .dofs
        .dofs
        .iter()
        .filter_map(|x| match x.kind {
            DofKind::Grid { grid, .. } => Some(grid),
            _ => None,
        })
        .collect();
    let tied_others = m
        .gap_geometry
        .gaps
        .iter()
        .flat_map(|g| g.tie.as_ref().unwrap().nodes.clone())
        .filter(|id| !m.gap_geometry.gaps.iter().any(|g| g.rotor_node == *id))
        .filter(|id| grids.contains(id))
        .count();
    assert!(
        tied_others > 0,
        "some face nodes are no gap's main rotor grid"
    );
    assert_eq!(
        n,
        grids.len(),
        "one VTU point per grid of the reduced model"
    );
    let vtu = std::fs::read_to_string(d.join("vtu/cea_modes.vtu")).unwrap();
    assert!(vtu.contains(&format!("NumberOfPoints=\"{n}\"")));
    // Face-node coordinates as the meshed model has them.
    for g in &m2.gap_geometry.gaps {
        let t = g.tie.as_ref().unwrap();
        for (id, x) in t.nodes.iter().zip(&t.coords) {
            let meshed = m.grids.iter().find(|gi| gi.grid == *id).unwrap().coords;
            assert_eq!(*x, meshed, "grid {id}");
        }
    }
}
