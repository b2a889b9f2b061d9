//! Verification of the tetrahedra, wedges and pyramids: patch tests on distorted and curved
//! meshes, NAFEMS FV52 in tet10 and wedge15 against hex20, a cantilever convergence study, a
//! conforming mixed hex20/wedge15/pyramid13/tet10 mesh, loads on triangular faces and an
//! orthotropic bar. Meshes come from `squeal_meshes::split` (conforming by construction).

use faer::Mat;
use squeal_fe::*;
use squeal_meshes::split::{split_hexes, to_quadratic, HexSplit};
use squeal_meshes::structured::box_mesh;
use squeal_meshes::CellKind;

fn steel() -> Material {
    Material::steel_si()
}

fn refs() -> serde_json::Value {
    serde_json::from_str(include_str!("data/references.json")).expect("references.json parses")
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Deterministic pseudo-random numbers in [−1, 1) (a fixed LCG: reproducible distortions).
fn noise(n: usize, seed: u64) -> Vec<f64> {
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

fn on_box_boundary(p: [f64; 3], size: [f64; 3]) -> bool {
    (0..3).any(|i| p[i].abs() < 1e-12 || (p[i] - size[i]).abs() < 1e-12)
}

/// A 3×3×3 unit-cube patch of hex8 with its interior corners moved by up to 8 %, split as
/// `split` says, raised to quadratic kinds when `quadratic` (interior mid-edge nodes then moved
/// off their edges by up to 3 %: curved edges).
fn patch_mesh(split: impl Fn(usize) -> HexSplit, quadratic: bool, seed: u64) -> Mesh {
    let mut m = box_mesh(1.0, 1.0, 1.0, 3, 3, 3, CellKind::Hex8);
    let d = noise(3 * m.nodes.len(), seed);
    for (v, p) in m.nodes.iter_mut().enumerate() {
        if !on_box_boundary(*p, [1.0; 3]) {
            for i in 0..3 {
                p[i] += 0.08 / 3.0 * d[3 * v + i];
            }
        }
    }
    let mut m = split_hexes(&m, |_, c| split(c));
    if quadratic {
        let n0 = m.nodes.len();
        m = to_quadratic(&m);
        let d = noise(3 * m.nodes.len(), seed + 1);
        for v in n0..m.nodes.len() {
            if !on_box_boundary(m.nodes[v], [1.0; 3]) {
                for i in 0..3 {
                    m.nodes[v][i] += 0.03 / 3.0 * d[3 * v + i];
                }
            }
        }
    }
    m
}

/// Constant-strain patch test: u prescribed as a linear field on the boundary nodes, K u = 0
/// solved for the interior nodes; the largest interior error relative to the field's scale.
fn patch_error(mesh: &Mesh, materials: &[SolidMaterial]) -> f64 {
    let lin = |p: [f64; 3]| -> [f64; 3] {
        [
            1e-3 * (1.0 + 2.0 * p[0] - 1.5 * p[1] + 0.7 * p[2]),
            1e-3 * (-0.5 + 0.3 * p[0] + 1.1 * p[1] - 0.4 * p[2]),
            1e-3 * (0.2 - 0.9 * p[0] + 0.6 * p[1] + 1.3 * p[2]),
        ]
    };
    let all = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = assemble(mesh, materials, &all, &AssemblyOptions::default()).unwrap();
    let k = asm.k.to_dense();
    let boundary: Vec<bool> = mesh
        .nodes
        .iter()
        .map(|&p| on_box_boundary(p, [1.0; 3]))
        .collect();
    let interior: Vec<usize> = (0..mesh.nodes.len()).filter(|&v| !boundary[v]).collect();
    let mut u = vec![0.0; 3 * mesh.nodes.len()];
    for (v, p) in mesh.nodes.iter().enumerate() {
        if boundary[v] {
            u[3 * v..3 * v + 3].copy_from_slice(&lin(*p));
        }
    }
    let idx: Vec<usize> = interior
        .iter()
        .flat_map(|&v| [3 * v, 3 * v + 1, 3 * v + 2])
        .collect();
    let ni = idx.len();
    let kii = Mat::<f64>::from_fn(ni, ni, |i, j| k[(idx[i], idx[j])]);
    let rhs = Mat::<f64>::from_fn(ni, 1, |i, _| {
        -(0..u.len()).map(|j| k[(idx[i], j)] * u[j]).sum::<f64>()
    });
    let sol = faer::linalg::solvers::Solve::solve(&kii.llt(faer::Side::Lower).unwrap(), &rhs);
    let mut err: f64 = 0.0;
    for (a, &v) in interior.iter().enumerate() {
        let e = lin(mesh.nodes[v]);
        for c in 0..3 {
            err = err.max((sol[(3 * a + c, 0)] - e[c]).abs() / 1e-3);
        }
    }
    err
}

fn kinds(m: &Mesh) -> Vec<CellKind> {
    let mut k: Vec<CellKind> = m.volumes.iter().map(|b| b.kind).collect();
    k.sort();
    k.dedup();
    k
}

/// Every element reproduces constant strain to round-off on distorted meshes (quadratic ones
/// with curved edges), isotropic and orthotropic with rotated axes (reference: the linear
/// field itself, the patch test of Irons; Zienkiewicz & Taylor vol. 1 ch. 9).
#[test]
fn patch_tests_of_every_element_on_distorted_curved_meshes() {
    let ortho = SolidMaterial {
        elasticity: Elasticity::TransverselyIsotropic(TransverselyIsotropic {
            e_plane: 8e9,
            e_axis: 2e9,
            nu_plane: 0.25,
            nu_plane_axis: 0.3,
            g_axis: 1e9,
        }),
        density: 2500.0,
        axes: MaterialAxes::Rectangular {
            e1: [1.0, 0.4, -0.2],
            e2: [0.1, 1.0, 0.5],
        },
    };
    let cases: [(&str, fn(usize) -> HexSplit); 4] = [
        ("tets", |_| HexSplit::Tets),
        ("wedges", |_| HexSplit::Wedges),
        ("hex/tet/pyramid", |c| {
            if c % 2 == 0 {
                HexSplit::Keep
            } else {
                HexSplit::Tets
            }
        }),
        ("all four", |c| match c % 3 {
            0 => HexSplit::Keep,
            1 => HexSplit::Wedges,
            _ => HexSplit::Tets,
        }),
    ];
    for (name, split) in cases {
        for quadratic in [false, true] {
            let m = patch_mesh(split, quadratic, 7);
            for mat in [SolidMaterial::from(steel()), ortho.clone()] {
                let mats = vec![mat; m.volumes.len()];
                let e = patch_error(&m, &mats);
                eprintln!(
                    "patch {name} quadratic {quadratic} {:?}: {e:.2e}",
                    kinds(&m)
                );
                assert!(e < 1e-10, "{name} quadratic {quadratic}: {e:e}");
            }
        }
    }
}

fn lanczos(n: usize) -> ModalOptions {
    ModalOptions {
        n_modes: Some(n),
        dense_below: 0,
        ..Default::default()
    }
}

fn frequencies(mesh: &Mesh, dofs: &DofMap, materials: &[SolidMaterial], n: usize) -> Vec<f64> {
    let asm = assemble(mesh, materials, dofs, &AssemblyOptions::default()).unwrap();
    let m = solve_modes(&asm.k, &asm.m, &lanczos(n)).unwrap();
    assert_eq!(m.status, ModalStatus::Converged, "{:?}", m.stats);
    m.frequencies_hz
}

/// NAFEMS FV52 plate (10 × 10 × 1 m, u_z = 0 on the bottom edges) on an `n × n × nz` grid of
/// hexes, kept (hex20), split into wedges (wedge15, triangles in the plate's plane) or into
/// tetrahedra (tet10): modes 4–9.
fn fv52(n: usize, nz: usize, split: HexSplit) -> Vec<f64> {
    let m = box_mesh(10.0, 10.0, 1.0, n, n, nz, CellKind::Hex8);
    let m = to_quadratic(&split_hexes(&m, |_, _| split));
    // The line support by coordinates (to_quadratic's set rule would add mid-nodes of cut
    // diagonals whose ends lie on two different edges).
    let edges: Vec<usize> = (0..m.nodes.len())
        .filter(|&v| {
            let p = m.nodes[v];
            p[2].abs() < 1e-9
                && (p[0].abs() < 1e-9
                    || (p[0] - 10.0).abs() < 1e-9
                    || p[1].abs() < 1e-9
                    || (p[1] - 10.0).abs() < 1e-9)
        })
        .collect();
    let fixed: Vec<(usize, usize)> = edges.iter().map(|&v| (v, 2)).collect();
    let dofs = DofMap::new(m.nodes.len(), &fixed).unwrap();
    let mats = vec![SolidMaterial::from(steel()); m.volumes.len()];
    let f = frequencies(&m, &dofs, &mats, 9);
    for i in 0..3 {
        assert!(f[i].abs() < 1e-3 * f[3], "in-plane rigid modes: {f:?}");
    }
    f[3..].to_vec()
}

/// FV52 in tet10 and wedge15 against hex20 on the same grids (4×4×1, the published hex20
/// mesh, and 8×8×1) and the NAFEMS target values (references.json: fv52). On 4×4×1 the
/// triangulated meshes are stiffer than hex20 (32 triangles per layer resolve the two-nodal-
/// line modes 7–8 worse than 16 quad8) and split the double mode 5/6 (all diagonals run one
/// way, breaking the square's symmetry); on 8×8×1 all three agree closely. The support is a
/// line of nodes: as a 3-D mesh refines, the region it holds shrinks and the plate softens
/// below the thin-plate target (hex20 4×4×1: mode 4 = 44.80 Hz vs 45.897), so the test bounds
/// the distances, it does not tune to the table.
#[test]
fn fv52_tet10_and_wedge15_against_hex20_and_nafems() {
    let r = refs();
    let target: Vec<f64> = r["fv52"]["analytic_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let mut spread = Vec::new();
    for n in [4, 8] {
        let hex = fv52(n, 1, HexSplit::Keep);
        let wedge = fv52(n, 1, HexSplit::Wedges);
        let tet = fv52(n, 1, HexSplit::Tets);
        eprintln!("FV52 {n}x{n}x1 hex20   {hex:.3?}\nFV52 {n}x{n}x1 wedge15 {wedge:.3?}\nFV52 {n}x{n}x1 tet10   {tet:.3?}");
        let mut worst: f64 = 0.0;
        for i in 0..6 {
            worst = worst.max(rel(wedge[i], hex[i])).max(rel(tet[i], hex[i]));
            for (name, f) in [("hex20", &hex), ("wedge15", &wedge), ("tet10", &tet)] {
                assert!(
                    rel(f[i], target[i]) < 0.08,
                    "{name} {n}x{n} mode {}: {} vs NAFEMS {}",
                    i + 4,
                    f[i],
                    target[i]
                );
            }
        }
        spread.push(worst);
    }
    eprintln!(
        "NAFEMS {target:?}; largest tet10/wedge15 vs hex20 difference: 4x4 {:.4}, 8x8 {:.4}",
        spread[0], spread[1]
    );
    assert!(
        spread[0] < 0.08 && spread[1] < 0.02 && spread[1] < 0.5 * spread[0],
        "{spread:?}"
    );
}

/// Cantilever (0.2 × 0.01 × 0.01 m steel, clamped at x = 0) in tet10 and hex20 on three
/// nested grids: the first bending frequency converges from above; the observed order is fitted
/// from the three levels and the Richardson limit is within 1 % of Euler–Bernoulli
/// (references.json: cantilever; the 3-D beam's shear and Poisson effects are well below that
/// at L/h = 20). The clamped face holds the Poisson contraction, which makes its edges
/// singular; the observed orders (1.62 tet10, 1.97 hex20 on grids 4×1×1, 8×2×2, 16×4×4,
/// below the 2p = 4 of a smooth eigenproblem) are the singularity's, met by both families.
#[test]
fn cantilever_convergence_order() {
    let r = refs();
    let eb = r["cantilever"]["first_bending_hz"].as_f64().unwrap();
    for split in [HexSplit::Tets, HexSplit::Keep] {
        let f: Vec<f64> = [1usize, 2, 4]
            .iter()
            .map(|&k| {
                let m = box_mesh(0.2, 0.01, 0.01, 4 * k, k, k, CellKind::Hex8);
                let m = to_quadratic(&split_hexes(&m, |_, _| split));
                let clamp: Vec<(usize, usize)> = (0..m.nodes.len())
                    .filter(|&v| m.nodes[v][0].abs() < 1e-12)
                    .flat_map(|v| [(v, 0), (v, 1), (v, 2)])
                    .collect();
                let dofs = DofMap::new(m.nodes.len(), &clamp).unwrap();
                let mats = vec![SolidMaterial::from(steel()); m.volumes.len()];
                frequencies(&m, &dofs, &mats, 2)[0]
            })
            .collect();
        let order = ((f[0] - f[1]) / (f[1] - f[2])).log2();
        let limit = f[2] - (f[1] - f[2]) / (2f64.powf(order) - 1.0);
        eprintln!("cantilever {split:?}: {f:.4?} Hz, observed order {order:.2}, extrapolated {limit:.3} Hz, Euler-Bernoulli {eb}");
        assert!(f[0] > f[1] && f[1] > f[2], "monotone from above: {f:?}");
        assert!(order > 1.0 && order < 5.0, "observed order {order}");
        assert!(rel(limit, eb) < 0.01, "{limit} vs {eb}");
    }
}

/// A conforming mixed mesh of the same 0.4 × 0.1 × 0.1 m free block — hex20 at both ends, a
/// tet10 region with pyramid13 transitions, a wedge15 region — against the hex20 mesh of the
/// same grid and a 2× finer hex20 reference: the first six elastic modes agree.
#[test]
fn mixed_hex_wedge_pyramid_tet_mesh_against_hex20() {
    let grid = |k: usize| box_mesh(0.4, 0.1, 0.1, 8 * k, 2 * k, 2 * k, CellKind::Hex8);
    let free = |m: &Mesh| DofMap::new(m.nodes.len(), &[]).unwrap();
    let run = |m: &Mesh| {
        let mats = vec![SolidMaterial::from(steel()); m.volumes.len()];
        frequencies(m, &free(m), &mats, 12)[6..].to_vec()
    };
    let coarse = grid(1);
    let mixed = to_quadratic(&split_hexes(&coarse, |_, c| match c % 8 {
        2 | 3 => HexSplit::Tets,
        4 | 5 => HexSplit::Wedges,
        _ => HexSplit::Keep,
    }));
    let k: Vec<CellKind> = mixed.volumes.iter().map(|b| b.kind).collect();
    for want in [
        CellKind::Hex20,
        CellKind::Tet10,
        CellKind::Wedge15,
        CellKind::Pyramid13,
    ] {
        assert!(k.contains(&want), "{want} missing: {k:?}");
    }
    let fm = run(&mixed);
    let fh = run(&to_quadratic(&coarse));
    let fr = run(&to_quadratic(&grid(2)));
    eprintln!("mixed {fm:.2?}\nhex20 {fh:.2?}\nhex20 fine {fr:.2?}");
    for i in 0..6 {
        assert!(
            rel(fm[i], fh[i]) < 0.01,
            "mode {}: mixed {} vs hex20 {}",
            i + 7,
            fm[i],
            fh[i]
        );
        assert!(
            rel(fm[i], fr[i]) < 0.01,
            "mode {}: mixed {} vs fine {}",
            i + 7,
            fm[i],
            fr[i]
        );
    }
}

/// Uniform pressure on triangular faces (tri3 and tri6, split from the box's faces): the
/// resultant is −p A n on every face of the box, and the tri6 corners carry no load.
#[test]
fn pressure_on_triangle_faces() {
    let p = 2.5e5;
    for quadratic in [false, true] {
        let m = split_hexes(&box_mesh(0.4, 0.2, 0.1, 2, 2, 1, CellKind::Hex8), |_, _| {
            HexSplit::Tets
        });
        let m = if quadratic { to_quadratic(&m) } else { m };
        let dofs = DofMap::new(m.nodes.len(), &[]).unwrap();
        for (set, axis, sign, area) in [
            ("z1", 2, 1.0, 0.08),
            ("x0", 0, -1.0, 0.02),
            ("y1", 1, 1.0, 0.04),
        ] {
            let kinds: Vec<CellKind> = m.faces[set].kinds().collect();
            assert_eq!(
                kinds,
                [if quadratic {
                    CellKind::Tri6
                } else {
                    CellKind::Tri3
                }]
            );
            let f = pressure_load(&m, set, p, &dofs).unwrap();
            let mut s = [0.0; 3];
            for (i, v) in f.iter().enumerate() {
                s[dofs.dof_of(i).1] += v;
            }
            for c in 0..3 {
                let want = if c == axis { -sign * p * area } else { 0.0 };
                assert!((s[c] - want).abs() < 1e-9 * p * area, "{set} {c}: {s:?}");
            }
            if quadratic {
                let corners: Vec<usize> = m.faces[set]
                    .iter()
                    .flat_map(|f| f.nodes[..3].to_vec())
                    .collect();
                for (n, a) in face_areas(&m, set).unwrap() {
                    if corners.contains(&n) {
                        assert!(a.iter().all(|v| v.abs() < 1e-15), "tri6 corner {n}: {a:?}");
                    }
                }
            }
        }
    }
}

/// An orthotropic bar (axis along material direction 1, rotated into the global frame) has the
/// axial frequencies of a bar of modulus E1: f_n = (2n − 1)/(4L) √(E1/ρ) clamped–free
/// (Rayleigh, *Theory of Sound*, §255), independent of E2, E3; the isotropic limit gives the
/// same with E. The 3-D bar's lateral inertia (Love's correction, ν² π² n² r²/L² ~ 1e-4 here
/// for ν12 = 0) is why ν12 = ν13 = 0: the 1-D value is then exact for the 3-D body.
#[test]
fn orthotropic_bar_axial_frequencies() {
    let (l, e1, rho) = (1.0, 70e9, 2700.0);
    let m = to_quadratic(&split_hexes(
        &box_mesh(l, 0.05, 0.05, 12, 1, 1, CellKind::Hex8),
        |_, c| {
            if c % 2 == 0 {
                HexSplit::Wedges
            } else {
                HexSplit::Keep
            }
        },
    ));
    // Rotate the bar by 30° about z; the material axes follow.
    let (c, s) = (0.5f64.powf(0.5) * 3f64.sqrt() / 2f64.sqrt(), 0.5);
    let mut m = m;
    for p in &mut m.nodes {
        *p = [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
    }
    let ortho = SolidMaterial {
        elasticity: Elasticity::Orthotropic(Orthotropic {
            e1,
            e2: 5e9,
            e3: 8e9,
            nu12: 0.0,
            nu13: 0.0,
            nu23: 0.2,
            g12: 3e9,
            g13: 4e9,
            g23: 2e9,
        }),
        density: rho,
        axes: MaterialAxes::Rectangular {
            e1: [c, s, 0.0],
            e2: [-s, c, 0.0],
        },
    };
    let clamp: Vec<(usize, usize)> = (0..m.nodes.len())
        .filter(|&v| (c * m.nodes[v][0] + s * m.nodes[v][1]).abs() < 1e-12)
        .flat_map(|v| [(v, 0), (v, 1), (v, 2)])
        .collect();
    let dofs = DofMap::new(m.nodes.len(), &clamp).unwrap();
    let mats = vec![ortho; m.volumes.len()];
    let asm = assemble(&m, &mats, &dofs, &AssemblyOptions::default()).unwrap();
    let modes = solve_modes(&asm.k, &asm.m, &lanczos(30)).unwrap();
    let exact = |n: f64| (2.0 * n - 1.0) / (4.0 * l) * (e1 / rho).sqrt();
    // The axial modes among the bending and torsion ones: closest frequencies.
    for n in [1.0, 2.0] {
        let want = exact(n);
        let best = modes
            .frequencies_hz
            .iter()
            .copied()
            .min_by(|a, b| rel(*a, want).total_cmp(&rel(*b, want)))
            .unwrap();
        eprintln!("orthotropic bar axial mode {n}: {best:.3} Hz vs {want:.3} Hz");
        assert!(rel(best, want) < 2e-4, "axial {n}: {best} vs {want}");
    }
}

/// squeal's tet10 against an independent code on the same mesh: scikit-fem's P2 tetrahedra
/// (`fe/scripts/skfem_tet10.py`, output committed as `tests/data/skfem_tet10.json`) on gmsh's
/// tet10 bar read by squeal's msh reader (types 11 and 9, gmsh's node order mapped). Both
/// integrate the straight-sided elements exactly, so the frequencies agree to the eigensolvers'
/// tolerance.
#[test]
fn tet10_matches_scikit_fem_on_the_same_gmsh_mesh() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("skfem_tet10.json")).unwrap())
            .unwrap();
    let want: Vec<f64> = reference["frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let m = squeal_meshes::read_msh(&dir.join("skfem_tet10.msh")).unwrap();
    assert_eq!(m.volumes.len(), 1);
    assert_eq!(m.volumes[0].kind, CellKind::Tet10);
    assert_eq!(m.faces["clamp"].kind(), Some(CellKind::Tri6));
    let clamp: Vec<(usize, usize)> = m.node_sets["clamp"]
        .iter()
        .flat_map(|&v| [(v, 0), (v, 1), (v, 2)])
        .collect();
    assert!(m.node_sets["clamp"]
        .iter()
        .all(|&v| m.nodes[v][0].abs() < 1e-12));
    let dofs = DofMap::new(m.nodes.len(), &clamp).unwrap();
    let asm = assemble(&m, &[steel()], &dofs, &AssemblyOptions::default()).unwrap();
    let modes = solve_modes(
        &asm.k,
        &asm.m,
        &ModalOptions {
            tol: 1e-10,
            ..lanczos(6)
        },
    )
    .unwrap();
    eprintln!(
        "tet10 squeal {:.6?}\ntet10 skfem  {want:.6?}",
        modes.frequencies_hz
    );
    for (i, (&f, &w)) in modes.frequencies_hz.iter().zip(&want).enumerate() {
        assert!(rel(f, w) < 1e-8, "mode {}: {f} vs scikit-fem {w}", i + 1);
    }
}
