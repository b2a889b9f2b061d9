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
