//! Property tests of the element matrices (proptest): partition of unity, symmetry,
//! rigid-body null space, total mass.

use super::{hex20, hex8, hex8_incompatible, quadrature::hex_rule, shape};
use crate::{Material, Real};
use proptest::prelude::*;

fn steel() -> Material {
    Material::steel_si()
}

/// Unit-cube hex8 scaled to `size` with corner perturbations `d` (fraction of size).
fn hex8_coords(size: [Real; 3], d: &[Real]) -> [[Real; 3]; 8] {
    std::array::from_fn(|a| {
        let p = shape::HEX8_NODES[a];
        std::array::from_fn(|i| size[i] * (0.5 * (p[i] + 1.0) + d[3 * a + i]))
    })
}

/// Hex20 with distorted corners, mid-edge nodes at edge midpoints plus a small offset.
fn hex20_coords(size: [Real; 3], d: &[Real], mid: &[Real]) -> [[Real; 3]; 20] {
    let c = hex8_coords(size, d);
    let edges = [
        [0, 1],
        [1, 2],
        [2, 3],
        [3, 0],
        [4, 5],
        [5, 6],
        [6, 7],
        [7, 4],
        [0, 4],
        [1, 5],
        [2, 6],
        [3, 7],
    ];
    std::array::from_fn(|a| {
        if a < 8 {
            c[a]
        } else {
            let [p, q] = edges[a - 8];
            std::array::from_fn(|i| 0.5 * (c[p][i] + c[q][i]) + size[i] * mid[3 * (a - 8) + i])
        }
    })
}

/// The six rigid-body motions evaluated at the nodes (3 translations, 3 rotations).
fn rigid_modes(x: &[[Real; 3]]) -> Vec<Vec<Real>> {
    let mut out = Vec::new();
    for t in 0..3 {
        out.push(
            x.iter()
                .flat_map(|_| (0..3).map(move |i| if i == t { 1.0 } else { 0.0 }))
                .collect(),
        );
    }
    for axis in 0..3 {
        let mut v = Vec::new();
        for p in x {
            // ω × p with ω = e_axis.
            let w = [0, 1, 2].map(|i| if i == axis { 1.0 } else { 0.0 });
            v.extend([
                w[1] * p[2] - w[2] * p[1],
                w[2] * p[0] - w[0] * p[2],
                w[0] * p[1] - w[1] * p[0],
            ]);
        }
        out.push(v);
    }
    out
}

fn check_k<const D: usize>(
    k: &nalgebra::SMatrix<Real, D, D>,
    x: &[[Real; 3]],
) -> Result<(), TestCaseError> {
    let kmax = k.amax();
    let asym = (k - k.transpose()).amax();
    prop_assert!(asym <= 1e-12 * kmax, "asymmetry {asym:e} of max {kmax:e}");
    for r in rigid_modes(x) {
        let v = nalgebra::SVector::<Real, D>::from_column_slice(&r);
        let kv = k * v;
        prop_assert!(
            kv.amax() <= 1e-9 * kmax * v.amax(),
            "rigid residual {:e}",
            kv.amax() / (kmax * v.amax())
        );
    }
    // Exactly six zero eigenvalues: the seventh smallest is well away from zero.
    let ev = nalgebra::DMatrix::from_column_slice(D, D, k.as_slice()).symmetric_eigenvalues();
    let mut e: Vec<Real> = ev.iter().copied().collect();
    e.sort_by(|a, b| a.total_cmp(b));
    prop_assert!(
        e[6] > 1e-6 * kmax,
        "spurious zero-energy mode: {:e}",
        e[6] / kmax
    );
    Ok(())
}

/// Shape-function evaluator: (N_a, ∂N_a/∂ξ).
type ShapeFn<const N: usize> = fn([Real; 3]) -> ([Real; N], [[Real; 3]; N]);

fn volume<const N: usize>(x: &[[Real; 3]; N], sh: ShapeFn<N>, order: usize) -> Real {
    hex_rule(order)
        .iter()
        .map(|(xi, w)| {
            let (_, dn) = sh(*xi);
            w * super::jacobian(x, &dn, *xi).unwrap().1
        })
        .sum()
}

fn total_translational_mass<const D: usize>(m: &nalgebra::SMatrix<Real, D, D>) -> Real {
    // uᵀ M u with u = unit translation in x.
    let u = nalgebra::SVector::<Real, D>::from_fn(|i, _| if i % 3 == 0 { 1.0 } else { 0.0 });
    (u.transpose() * m * u)[(0, 0)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn shape_functions_partition_unity(x in -1.0..1.0f64, y in -1.0..1.0f64, z in -1.0..1.0f64) {
        for (n, d) in [shape::hex8([x, y, z]).0.to_vec(), shape::hex20([x, y, z]).0.to_vec()]
            .into_iter()
            .zip([shape::hex8([x, y, z]).1.to_vec(), shape::hex20([x, y, z]).1.to_vec()])
        {
            prop_assert!((n.iter().sum::<Real>() - 1.0).abs() < 1e-14);
            for j in 0..3 {
                prop_assert!(d.iter().map(|g| g[j]).sum::<Real>().abs() < 1e-14);
            }
        }
        for (n, d) in [(shape::quad4([x, y]).0.to_vec(), shape::quad4([x, y]).1.to_vec()),
                       (shape::quad8([x, y]).0.to_vec(), shape::quad8([x, y]).1.to_vec())] {
            prop_assert!((n.iter().sum::<Real>() - 1.0).abs() < 1e-14);
            for j in 0..2 {
                prop_assert!(d.iter().map(|g| g[j]).sum::<Real>().abs() < 1e-14);
            }
        }
    }

    #[test]
    fn hex8_matrices_symmetric_rigid_free_mass_exact(
        d in proptest::collection::vec(-0.15..0.15f64, 24),
        sx in 0.5..2.0f64, sy in 0.5..2.0f64, sz in 0.05..1.0f64,
    ) {
        let x = hex8_coords([sx, sy, sz], &d);
        let mat = steel();
        check_k(&hex8_incompatible::stiffness(&x, &mat).unwrap(), &x)?;
        check_k(&hex8::stiffness(&x, &mat).unwrap(), &x)?;
        let m = hex8::mass(&x, &mat).unwrap();
        prop_assert!((m - m.transpose()).amax() <= 1e-12 * m.amax());
        let v = volume(&x, shape::hex8, 2);
        prop_assert!((total_translational_mass(&m) - mat.density * v).abs() <= 1e-10 * mat.density * v);
    }

    #[test]
    fn hex20_matrices_symmetric_rigid_free_mass_exact(
        d in proptest::collection::vec(-0.12..0.12f64, 24),
        mid in proptest::collection::vec(-0.05..0.05f64, 36),
        sx in 0.5..2.0f64, sy in 0.5..2.0f64, sz in 0.05..1.0f64,
    ) {
        let x = hex20_coords([sx, sy, sz], &d, &mid);
        let mat = steel();
        let k = hex20::stiffness(&x, &mat).unwrap();
        check_k(&*k, &x)?;
        let m = hex20::mass(&x, &mat).unwrap();
        prop_assert!((*m - m.transpose()).amax() <= 1e-12 * m.amax());
        let v = volume(&x, shape::hex20, 3);
        prop_assert!((total_translational_mass(&*m) - mat.density * v).abs() <= 1e-10 * mat.density * v);
    }
}

#[test]
fn unit_cube_volume_and_mass() {
    // A 2×1×0.5 box: V = 1, total mass ρV = 8000 for both element kinds.
    let x8 = hex8_coords([2.0, 1.0, 0.5], &[0.0; 24]);
    let m8 = hex8::mass(&x8, &steel()).unwrap();
    assert!((total_translational_mass(&m8) - 8000.0).abs() < 1e-9);
    let x20 = hex20_coords([2.0, 1.0, 0.5], &[0.0; 24], &[0.0; 36]);
    let m20 = hex20::mass(&x20, &steel()).unwrap();
    assert!((total_translational_mass(&*m20) - 8000.0).abs() < 1e-9);
}

#[test]
fn inverted_element_is_an_error() {
    let mut x = hex8_coords([1.0, 1.0, 1.0], &[0.0; 24]);
    x.swap(0, 1);
    x.swap(2, 3);
    x.swap(4, 5);
    x.swap(6, 7);
    let e = hex8::stiffness(&x, &steel()).unwrap_err();
    assert!(matches!(e, crate::FeError::ElementJacobian { det, .. } if det < 0.0));
}

#[test]
fn taylor_correction_decouples_constant_strain_from_incompatible_modes() {
    // Element-level patch condition: for a linear displacement field the incompatible DOFs
    // feel no force, K_αu u_lin = 0, on a distorted element — only with Taylor's correction.
    let d: Vec<Real> = (0..24)
        .map(|i| 0.1 * ((i * 7 % 11) as Real / 11.0 - 0.5))
        .collect();
    let x = hex8_coords([1.0, 0.8, 0.6], &d);
    let u: Vec<Real> = x
        .iter()
        .flat_map(|p| {
            [
                0.3 * p[0] + 0.1 * p[1],
                -0.2 * p[1] + 0.4 * p[2],
                0.5 * p[0] - 0.3 * p[2],
            ]
        })
        .collect();
    let u = nalgebra::SVector::<Real, 24>::from_column_slice(&u);
    for (taylor, expect_zero) in [(true, true), (false, false)] {
        let k = hex8_incompatible::full_stiffness(&x, &steel(), taylor).unwrap();
        let kau = k.fixed_view::<9, 24>(24, 0).into_owned();
        let f = (kau * u).amax() / (k.amax() * u.amax());
        assert_eq!(
            f < 1e-12,
            expect_zero,
            "taylor {taylor}: relative force {f:e}"
        );
    }
}
