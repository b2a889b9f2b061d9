use super::*;

fn ortho() -> Orthotropic {
    // A friction-lining-like orthotropic set (GPa): stiff in plane, soft through thickness.
    Orthotropic {
        e1: 8.0,
        e2: 6.0,
        e3: 2.0,
        nu12: 0.25,
        nu13: 0.35,
        nu23: 0.3,
        g12: 2.5,
        g13: 1.0,
        g23: 0.9,
    }
}

/// The orthotropic D inverts the compliance: uniaxial stress σ1 gives ε1 = σ1/E1,
/// ε2 = −ν12 σ1/E1, ε3 = −ν13 σ1/E1, and shear γ12 = τ12/G12 (Jones §2.4).
#[test]
fn orthotropic_matrix_reproduces_engineering_constants() {
    let o = ortho();
    o.validate("lining").unwrap();
    let d = o.matrix();
    let s = d.try_inverse().unwrap();
    assert!((s[(0, 0)] * o.e1 - 1.0).abs() < 1e-12);
    assert!((-s[(1, 0)] * o.e1 - o.nu12).abs() < 1e-12);
    assert!((-s[(2, 0)] * o.e1 - o.nu13).abs() < 1e-12);
    assert!((-s[(2, 1)] * o.e2 - o.nu23).abs() < 1e-12);
    assert!((s[(5, 5)] * o.g12 - 1.0).abs() < 1e-12);
    assert!((s[(3, 3)] * o.g23 - 1.0).abs() < 1e-12);
}

/// Equal constants give the isotropic matrix (the isotropic limit).
#[test]
fn isotropic_limit() {
    let (e, nu) = (200.0, 0.3);
    let g = e / (2.0 * (1.0 + nu));
    let o = Orthotropic {
        e1: e,
        e2: e,
        e3: e,
        nu12: nu,
        nu13: nu,
        nu23: nu,
        g12: g,
        g13: g,
        g23: g,
    };
    let iso = Elasticity::Isotropic {
        young: e,
        poisson: nu,
    }
    .matrix();
    assert!((o.matrix() - iso).amax() < 1e-12 * iso.amax());
    let t = TransverselyIsotropic {
        e_plane: e,
        e_axis: e,
        nu_plane: nu,
        nu_plane_axis: nu,
        g_axis: g,
    };
    assert!((t.orthotropic().matrix() - iso).amax() < 1e-12 * iso.amax());
}

/// Rotation preserves the strain energy: ε_materialᵀ D ε_material = ε_globalᵀ D_g ε_global,
/// with the strain tensor rotated as ε_m = Qᵀ ε_g Q.
#[test]
fn rotation_preserves_strain_energy() {
    let d = ortho().matrix();
    let frame = frame_from([1.0, 2.0, 0.5], [-0.3, 0.4, 1.0]).unwrap();
    let dg = rotate(&d, &frame);
    let eg = [[1.0, 0.2, -0.3], [0.2, -0.5, 0.7], [-0.3, 0.7, 0.4]];
    // ε_m[a][b] = Σ e_a,i ε_g[i][j] e_b,j.
    let em: [[Real; 3]; 3] = std::array::from_fn(|a| {
        std::array::from_fn(|b| {
            let mut v = 0.0;
            for i in 0..3 {
                for j in 0..3 {
                    v += frame[a][i] * eg[i][j] * frame[b][j];
                }
            }
            v
        })
    });
    let voigt = |e: &[[Real; 3]; 3]| {
        nalgebra::SVector::<Real, 6>::from([
            e[0][0],
            e[1][1],
            e[2][2],
            2.0 * e[1][2],
            2.0 * e[0][2],
            2.0 * e[0][1],
        ])
    };
    let (vg, vm) = (voigt(&eg), voigt(&em));
    let wg = (vg.transpose() * dg * vg)[(0, 0)];
    let wm = (vm.transpose() * d * vm)[(0, 0)];
    assert!((wg - wm).abs() < 1e-12 * wm.abs(), "{wg} vs {wm}");
    // An isotropic D is invariant.
    let iso = isotropic_matrix(1.0, 0.7);
    assert!((rotate(&iso, &frame) - iso).amax() < 1e-14);
}

/// Positive definiteness: each failing condition is named with its value.
#[test]
fn not_positive_definite_names_material_and_value() {
    let bad = Orthotropic {
        nu12: 1.5,
        ..ortho()
    };
    let e = bad.validate("pad.lining").unwrap_err().to_string();
    assert!(e.contains("pad.lining.nu12") && e.contains("1.5"), "{e}");
    // Each |ν| admissible, the determinant not: ν12 = ν13 = ν23 = 0.7 on equal moduli.
    let bad = Orthotropic {
        e1: 1.0,
        e2: 1.0,
        e3: 1.0,
        nu12: 0.7,
        nu13: 0.7,
        nu23: 0.7,
        ..ortho()
    };
    let det = bad.normal_determinant();
    assert!(det < 0.0);
    let e = Elasticity::Orthotropic(bad)
        .validate("lining")
        .unwrap_err()
        .to_string();
    assert!(e.contains("lining") && e.contains(&format!("{det}")), "{e}");
    let mut c = [[0.0; 6]; 6];
    for i in 0..6 {
        c[i][i] = 1.0;
    }
    c[0][1] = 2.0;
    c[1][0] = 2.0;
    let e = Elasticity::Anisotropic { stiffness: c }
        .validate("m9")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("m9") && e.contains("smallest eigenvalue") && e.contains("-1"),
        "{e}"
    );
    let e = Elasticity::Isotropic {
        young: 1.0,
        poisson: 0.5,
    }
    .validate("rotor")
    .unwrap_err()
    .to_string();
    assert!(e.contains("rotor.poisson") && e.contains("0.5"), "{e}");
}

#[test]
fn cylindrical_frame_is_radial_circumferential_axial() {
    let f = cylindrical_frame([0.0; 3], [0.0, 0.0, 2.0], [0.0, 3.0, 5.0]).unwrap();
    let close = |a: [Real; 3], b: [Real; 3]| (0..3).all(|i| (a[i] - b[i]).abs() < 1e-15);
    assert!(close(f[0], [0.0, 1.0, 0.0]));
    assert!(close(f[1], [-1.0, 0.0, 0.0]));
    assert!(close(f[2], [0.0, 0.0, 1.0]));
    assert!(cylindrical_frame([0.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 4.0]).is_none());
}
