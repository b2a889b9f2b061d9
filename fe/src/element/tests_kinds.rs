//! Property tests of the tetrahedra, wedges and pyramids (and the hexahedra through the same
//! generic path): shape functions (partition of unity, Kronecker at the nodes, completeness,
//! derivatives), element matrices (symmetry, rigid-body null space with exactly six zero
//! eigenvalues, mass = ρV) and quadrature exactness on straight-sided elements.

use super::kinds::{element_matrices, shape_functions};
use crate::assembly::Hex8Formulation;
use crate::elasticity::{Elasticity, MaterialAxes, Orthotropic};
use crate::{Material, Real, SolidMaterial};
use proptest::prelude::*;
use squeal_meshes::topology::node_coords;
use squeal_meshes::CellKind;

const KINDS: [CellKind; 8] = [
    CellKind::Hex8,
    CellKind::Hex20,
    CellKind::Tet4,
    CellKind::Tet10,
    CellKind::Wedge6,
    CellKind::Wedge15,
    CellKind::Pyramid5,
    CellKind::Pyramid13,
];

fn is_pyramid(kind: CellKind) -> bool {
    matches!(kind, CellKind::Pyramid5 | CellKind::Pyramid13)
}

/// Natural point → the coordinates the shape functions take (pyramids: collapsed).
fn eval_point(kind: CellKind, p: [Real; 3]) -> [Real; 3] {
    if is_pyramid(kind) {
        let s = 1.0 - p[2];
        if s < 1e-14 {
            [0.0, 0.0, 1.0]
        } else {
            [p[0] / s, p[1] / s, p[2]]
        }
    } else {
        p
    }
}

/// A point inside the reference cell from three numbers in [0, 1).
fn inside(kind: CellKind, u: [Real; 3]) -> [Real; 3] {
    match kind.linear() {
        CellKind::Hex8 => u.map(|v| 2.0 * v - 1.0),
        CellKind::Tet4 => {
            // Fold the unit cube into the tetrahedron.
            let (a, b, c) = (
                u[0],
                u[1] * (1.0 - u[0]),
                u[2] * (1.0 - u[0]) * (1.0 - u[1]),
            );
            [a * 0.98, b * 0.98, c * 0.98]
        }
        CellKind::Wedge6 => [u[0] * 0.98, u[1] * (1.0 - u[0]) * 0.98, 2.0 * u[2] - 1.0],
        _ => {
            let z = u[2] * 0.98;
            [
                (2.0 * u[0] - 1.0) * (1.0 - z),
                (2.0 * u[1] - 1.0) * (1.0 - z),
                z,
            ]
        }
    }
}

fn steel() -> SolidMaterial {
    Material::steel_si().into()
}

/// The reference nodes under x = A ξ + b, then (for quadratic kinds) mid-edge nodes moved off
/// their edges by `bend` (fraction of the size) and corners by `d`.
fn element_nodes(kind: CellKind, d: &[Real], bend: &[Real]) -> Vec<[Real; 3]> {
    let a = [[0.9, 0.2, 0.1], [-0.1, 1.1, 0.15], [0.05, -0.2, 0.8]];
    let nc = kind.n_corners();
    let mut x: Vec<[Real; 3]> = (0..nc)
        .map(|n| {
            let p = node_coords(kind, n);
            std::array::from_fn(|i| (0..3).map(|k| a[i][k] * p[k]).sum::<Real>() + d[3 * n + i])
        })
        .collect();
    for (e, &[p, q]) in kind
        .edges()
        .iter()
        .enumerate()
        .filter(|_| kind.is_quadratic())
    {
        let m: [Real; 3] =
            std::array::from_fn(|i| 0.5 * (x[p][i] + x[q][i]) + bend[(3 * e + i) % bend.len()]);
        x.push(m);
    }
    x
}

fn rigid_modes(x: &[[Real; 3]]) -> Vec<nalgebra::DVector<Real>> {
    let mut out = Vec::new();
    for t in 0..3 {
        out.push(nalgebra::DVector::from_fn(3 * x.len(), |i, _| {
            if i % 3 == t {
                1.0
            } else {
                0.0
            }
        }));
    }
    for axis in 0..3 {
        let w = [0, 1, 2].map(|i| if i == axis { 1.0 } else { 0.0 });
        out.push(nalgebra::DVector::from_fn(3 * x.len(), |i, _| {
            let p = x[i / 3];
            let r = [
                w[1] * p[2] - w[2] * p[1],
                w[2] * p[0] - w[0] * p[2],
                w[0] * p[1] - w[1] * p[0],
            ];
            r[i % 3]
        }));
    }
    out
}

fn check_matrices(
    kind: CellKind,
    x: &[[Real; 3]],
    mat: &SolidMaterial,
) -> Result<(), TestCaseError> {
    let (k, m) = element_matrices(kind, x, mat, Hex8Formulation::Incompatible).unwrap();
    let kmax = k.amax();
    prop_assert!(
        (&k - k.transpose()).amax() <= 1e-12 * kmax,
        "{kind}: K asymmetric"
    );
    prop_assert!(
        (&m - m.transpose()).amax() <= 1e-12 * m.amax(),
        "{kind}: M asymmetric"
    );
    for r in rigid_modes(x) {
        let kr = &k * &r;
        prop_assert!(
            kr.amax() <= 1e-9 * kmax * r.amax(),
            "{kind}: rigid residual"
        );
    }
    let mut ev: Vec<Real> = k.clone().symmetric_eigenvalues().iter().copied().collect();
    ev.sort_by(|a, b| a.total_cmp(b));
    prop_assert!(
        ev[6] > 1e-7 * kmax,
        "{kind}: spurious zero-energy mode {:e}",
        ev[6] / kmax
    );
    // Total mass: uᵀ M u for a unit translation is ρ V, V from the same map (∫ det J).
    let u = nalgebra::DVector::from_fn(3 * x.len(), |i, _| if i % 3 == 0 { 1.0 } else { 0.0 });
    let mass = (u.transpose() * &m * &u)[(0, 0)];
    let v = volume(kind, x);
    prop_assert!(
        (mass - mat.density * v).abs() <= 1e-10 * mat.density * v,
        "{kind}: {mass} vs {}",
        mat.density * v
    );
    Ok(())
}

/// ∫ det J over the reference cell with a high-order collapsed Gauss rule (4⁴-free: 6 points
/// per direction, exact beyond every element's degree).
fn volume(kind: CellKind, x: &[[Real; 3]]) -> Real {
    high_rule(kind)
        .iter()
        .map(|&(p, w)| w * squeal_meshes::jacobian::jacobian_at(kind, x, p))
        .sum()
}

/// A 6×6×6 collapsed (Duffy) Gauss rule on the reference cell of `kind`, in the coordinates its
/// shape functions take (exact for polynomial integrands of degree ≤ 8 in ξ on tets, wedges
/// and pyramids: far above every element's stiffness and mass).
fn high_rule(kind: CellKind) -> Vec<([Real; 3], Real)> {
    let g: Vec<(Real, Real)> = {
        // 6-point Gauss–Legendre on [−1, 1].
        let p = [
            0.932_469_514_203_152,
            0.661_209_386_466_264_5,
            0.238_619_186_083_196_9,
        ];
        let w = [
            0.171_324_492_379_170_3,
            0.360_761_573_048_138_6,
            0.467_913_934_572_691,
        ];
        let mut v = Vec::new();
        for i in 0..3 {
            v.push((-p[i], w[i]));
            v.push((p[i], w[i]));
        }
        v
    };
    let mut r = Vec::new();
    for &(a, wa) in &g {
        for &(b, wb) in &g {
            for &(c, wc) in &g {
                let (u, v, t) = (0.5 * (1.0 + a), 0.5 * (1.0 + b), 0.5 * (1.0 + c));
                let w = wa * wb * wc;
                match kind.linear() {
                    CellKind::Hex8 => r.push(([a, b, c], w)),
                    CellKind::Tet4 => r.push((
                        [u, v * (1.0 - u), t * (1.0 - u) * (1.0 - v)],
                        w / 8.0 * (1.0 - u) * (1.0 - u) * (1.0 - v),
                    )),
                    CellKind::Wedge6 => r.push(([u, v * (1.0 - u), c], w / 4.0 * (1.0 - u))),
                    _ => r.push(([a, b, t], w / 2.0 * (1.0 - t) * (1.0 - t))),
                }
            }
        }
    }
    r
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    #[test]
    fn shape_functions_sum_to_one_and_reproduce_quadratics(
        u in proptest::array::uniform3(0.0..1.0f64),
    ) {
        for kind in KINDS {
            let p = inside(kind, u);
            let (n, d) = shape_functions(kind, eval_point(kind, p));
            prop_assert!((n.iter().sum::<Real>() - 1.0).abs() < 1e-13, "{kind}");
            for j in 0..3 {
                prop_assert!(d.iter().map(|g| g[j]).sum::<Real>().abs() < 1e-12, "{kind}");
            }
            // Linear (and for quadratic kinds quadratic) fields are reproduced, with their
            // derivatives: Σ N_a f(ξ_a) = f(ξ), Σ ∂N_a f(ξ_a) = ∂f.
            #[allow(clippy::type_complexity)]
            let fields: Vec<(fn([Real; 3]) -> Real, fn([Real; 3]) -> [Real; 3])> = vec![
                (|q| 1.0 + 2.0 * q[0] - q[1] + 0.5 * q[2], |_| [2.0, -1.0, 0.5]),
                (|q| q[0] * q[1] + q[2] * q[2] - 0.3 * q[0] * q[2],
                 |q| [q[1] - 0.3 * q[2], q[0], 2.0 * q[2] - 0.3 * q[0]]),
            ];
            for (i, (f, df)) in fields.iter().enumerate() {
                if i == 1 && !kind.is_quadratic() {
                    continue;
                }
                let v: Real = (0..n.len()).map(|a| n[a] * f(node_coords(kind, a))).sum();
                prop_assert!((v - f(p)).abs() < 1e-12, "{kind} field {i}: {v} vs {}", f(p));
                let g = df(p);
                for j in 0..3 {
                    let dv: Real = (0..n.len()).map(|a| d[a][j] * f(node_coords(kind, a))).sum();
                    prop_assert!((dv - g[j]).abs() < 1e-11, "{kind} field {i} d{j}: {dv} vs {}", g[j]);
                }
            }
        }
    }

    #[test]
    fn element_matrices_symmetric_rigid_free_and_mass_exact(
        d in proptest::collection::vec(-0.12..0.12f64, 24),
        bend in proptest::collection::vec(-0.04..0.04f64, 36),
    ) {
        let ortho = SolidMaterial {
            elasticity: Elasticity::Orthotropic(Orthotropic {
                e1: 8e9, e2: 6e9, e3: 2e9, nu12: 0.25, nu13: 0.35, nu23: 0.3,
                g12: 2.5e9, g13: 1e9, g23: 0.9e9,
            }),
            density: 2500.0,
            axes: MaterialAxes::Rectangular { e1: [1.0, 0.3, 0.1], e2: [0.0, 1.0, 0.4] },
        };
        for kind in KINDS {
            let x = element_nodes(kind, &d, &bend);
            check_matrices(kind, &x, &steel())?;
            check_matrices(kind, &x, &ortho)?;
        }
    }
}

/// Kronecker property: N_a(ξ_b) = δ_ab at every node (pyramid apex from several directions).
#[test]
fn shape_functions_are_nodal() {
    for kind in KINDS {
        for b in 0..kind.n_nodes() {
            let pb = node_coords(kind, b);
            let pts: Vec<[Real; 3]> = if is_pyramid(kind) && b == 4 {
                vec![[0.3, -0.7, 1.0], [1.0, 1.0, 1.0], [-1.0, 0.2, 1.0]]
            } else {
                vec![eval_point(kind, pb)]
            };
            for p in pts {
                let (n, _) = shape_functions(kind, p);
                for a in 0..kind.n_nodes() {
                    let e = if a == b { 1.0 } else { 0.0 };
                    assert!(
                        (n[a] - e).abs() < 1e-14,
                        "{kind}: N_{a}(node {b}) = {}",
                        n[a]
                    );
                }
            }
        }
    }
}

/// The derivatives are those of the functions (central differences in natural coordinates;
/// pyramids: in (ξ, η, ζ) through the collapsed map).
#[test]
fn derivatives_match_finite_differences() {
    let h = 1e-6;
    for kind in KINDS {
        let p = inside(kind, [0.31, 0.62, 0.27]);
        let (_, d) = shape_functions(kind, eval_point(kind, p));
        for j in 0..3 {
            let (mut pp, mut pm) = (p, p);
            pp[j] += h;
            pm[j] -= h;
            let np = shape_functions(kind, eval_point(kind, pp)).0;
            let nm = shape_functions(kind, eval_point(kind, pm)).0;
            for a in 0..kind.n_nodes() {
                let fd = (np[a] - nm[a]) / (2.0 * h);
                assert!(
                    (fd - d[a][j]).abs() < 1e-7,
                    "{kind} N_{a} d{j}: {fd} vs {}",
                    d[a][j]
                );
            }
        }
    }
}

/// On straight-sided (affine) elements each kind's rules are exact: K and M equal those of
/// the 6×6×6 collapsed Gauss rule (exact far beyond their degrees) to round-off.
#[test]
fn rules_are_exact_on_straight_sided_elements() {
    use super::solid::{mass_scalar, stiffness, Law};
    use super::{pyramid, shape, simplex, wedge};
    let law = Law::Isotropic {
        lambda: 1.2,
        mu: 0.8,
    };
    fn cmp<const N: usize, const D: usize>(
        kind: CellKind,
        f: super::solid::ShapeFn<N>,
        krule: &[([Real; 3], Real)],
        mrule: &[([Real; 3], Real)],
        law: &Law,
    ) {
        let xv = element_nodes(kind, &[0.0; 24], &[0.0]);
        let x: [[Real; 3]; N] = std::array::from_fn(|a| xv[a]);
        let hr = high_rule(kind);
        let (mut k1, mut k2) = (
            nalgebra::SMatrix::<Real, D, D>::zeros(),
            nalgebra::SMatrix::<Real, D, D>::zeros(),
        );
        stiffness(&x, f, krule, law, &mut k1).unwrap();
        stiffness(&x, f, &hr, law, &mut k2).unwrap();
        let (mut m1, mut m2) = (
            nalgebra::SMatrix::<Real, N, N>::zeros(),
            nalgebra::SMatrix::<Real, N, N>::zeros(),
        );
        mass_scalar(&x, f, mrule, 1.0, &mut m1).unwrap();
        mass_scalar(&x, f, &hr, 1.0, &mut m2).unwrap();
        let ek = (k1 - k2).amax() / k2.amax();
        let em = (m1 - m2).amax() / m2.amax();
        assert!(ek < 1e-13 && em < 1e-13, "{kind}: K {ek:e}, M {em:e}");
    }
    use super::rules::{hexahedron, pyramid as pr, tetrahedron, wedge as wr};
    cmp::<20, 60>(
        CellKind::Hex20,
        shape::hex20,
        hexahedron(3),
        hexahedron(3),
        &law,
    );
    cmp::<4, 12>(
        CellKind::Tet4,
        simplex::tet4,
        tetrahedron(1),
        tetrahedron(2),
        &law,
    );
    cmp::<10, 30>(
        CellKind::Tet10,
        simplex::tet10,
        tetrahedron(5),
        tetrahedron(5),
        &law,
    );
    cmp::<6, 18>(CellKind::Wedge6, wedge::wedge6, wr(2, 2), wr(2, 2), &law);
    cmp::<15, 45>(CellKind::Wedge15, wedge::wedge15, wr(4, 3), wr(4, 3), &law);
    cmp::<5, 15>(
        CellKind::Pyramid5,
        pyramid::pyramid5,
        pr(2, 3),
        pr(2, 3),
        &law,
    );
    cmp::<13, 39>(
        CellKind::Pyramid13,
        pyramid::pyramid13,
        pr(3, 3),
        pr(3, 4),
        &law,
    );
}

/// The anisotropic path with an isotropic D equals the isotropic fast path.
#[test]
fn matrix_law_equals_isotropic_law() {
    use super::solid::{isotropic_law_matrix, stiffness, Law};
    let xv = element_nodes(CellKind::Tet10, &[0.01; 24], &[0.02, -0.01, 0.03]);
    let x: [[Real; 3]; 10] = std::array::from_fn(|a| xv[a]);
    let r = super::rules::tetrahedron(5);
    let (mut k1, mut k2) = (
        nalgebra::SMatrix::<Real, 30, 30>::zeros(),
        nalgebra::SMatrix::<Real, 30, 30>::zeros(),
    );
    stiffness(
        &x,
        super::simplex::tet10,
        r,
        &Law::Isotropic {
            lambda: 1.1,
            mu: 0.7,
        },
        &mut k1,
    )
    .unwrap();
    stiffness(
        &x,
        super::simplex::tet10,
        r,
        &isotropic_law_matrix(1.1, 0.7),
        &mut k2,
    )
    .unwrap();
    assert!((k1 - k2).amax() < 1e-13 * k1.amax());
}

/// Pyramid13 is conforming: on a triangular face its functions are the tri6 functions of the
/// face, on the base the quad8 ones (the functions of nodes off the face vanish there).
#[test]
fn pyramid13_traces_are_tri6_and_quad8() {
    use super::{pyramid::pyramid13, shape::quad8, simplex::tri6};
    // Face (0, 1, 4): η = −(1 − ζ); face tri6 order (0, 1, 4, mid(0,1)=5, mid(1,4)=10, mid(4,0)=9).
    let face = [0usize, 1, 4, 5, 10, 9];
    for &(s, t) in &[(0.2, 0.3), (0.5, 0.1), (0.05, 0.8)] {
        // Triangle point: x = (1−s−t) P0 + s P1 + t P4.
        let (p0, p1, p4) = ([-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 0.0, 1.0]);
        let p: [Real; 3] = std::array::from_fn(|i| (1.0 - s - t) * p0[i] + s * p1[i] + t * p4[i]);
        let (n, _) = pyramid13(eval_point(CellKind::Pyramid13, p));
        let (nt, _) = tri6([s, t]);
        for a in 0..13 {
            let want = face.iter().position(|&f| f == a).map_or(0.0, |k| nt[k]);
            assert!((n[a] - want).abs() < 1e-14, "node {a}: {} vs {want}", n[a]);
        }
    }
    let base = [0usize, 1, 2, 3, 5, 6, 7, 8];
    for &(u, v) in &[(0.3, -0.4), (-0.9, 0.2)] {
        let (n, _) = pyramid13([u, v, 0.0]);
        let (nq, _) = quad8([u, v]);
        for a in 0..13 {
            let want = base.iter().position(|&f| f == a).map_or(0.0, |k| nq[k]);
            assert!((n[a] - want).abs() < 1e-14, "base node {a}");
        }
    }
}
