//! Verification of the complex eigenvalue analysis (`squeal_solver::cea`) against analytic
//! references: Hoffmann's 2-DOF mode-coupling model (undamped, equally damped, unequally
//! damped), the same model with an extra constrained DOF, a constraint with friction
//! tangent D, proportional damping, and real roots; and the subspace-projection method
//! against the exact one (Hoffmann models and a random constrained model).

mod common;
use common::random::{random_spd, RandomConstrained, Rng};
use faer::{Mat, Side};
use squeal_solver::cea::{
    complex_eigen, mac, sweep, CeaError, CeaMatrices, CeaMethod, CeaOptions, Cplx, ModalBasis,
    ProjectionOptions, SweepOptions,
};

/// Hoffmann et al. (2002) 2-DOF model: M = I, K = [[k11, k12 − μ k3], [k21, k22]] with
/// k11 = 1, k12 = k21 = 0.3, k22 = 1.2, k3 = 1, and B = diag(c1, c2).
fn hoffmann(mu: f64, c1: f64, c2: f64) -> CeaMatrices {
    let k = Mat::from_fn(2, 2, |i, j| [[1.0, 0.3 - mu], [0.3, 1.2]][i][j]);
    let mut s = CeaMatrices::new(Mat::identity(2, 2), k);
    if c1 != 0.0 || c2 != 0.0 {
        s.b = Some(Mat::from_fn(
            2,
            2,
            |i, j| if i == j { [c1, c2][i] } else { 0.0 },
        ));
    }
    s
}

fn mus(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

fn critical_mu(
    build: impl FnMut(f64) -> Result<CeaMatrices, CeaError>,
    lo: f64,
    hi: f64,
) -> (f64, f64, squeal_solver::cea::Sweep) {
    let s = sweep(build, &mus(lo, hi, 26), &SweepOptions::default()).unwrap();
    let (_, c) = s
        .lowest_critical()
        .expect("an onset of instability inside the sweep");
    eprintln!(
        "critical mu = {:.8} (interpolated {:.8}), {} locate solves, omega = {:.8}",
        c.mu,
        c.mu_interpolated,
        c.locate_solves,
        2.0 * std::f64::consts::PI * c.frequency_hz
    );
    (c.mu, c.frequency_hz, s)
}

/// Undamped: eigenvalues ω² of K coalesce when (k11 − k22)² + 4 k21 (k12 − μ k3) = 0, i.e.
/// 0.04 + 1.2 (0.3 − μ) = 0 → μc = 0.3 + 0.04/1.2 = 1/3, at ω² = (k11 + k22)/2 = 1.1,
/// ω = 1.048809 rad/s (lock-in frequency).
#[test]
fn hoffmann_undamped_critical_mu_and_lock_in() {
    let (mu_c, f_c, s) = critical_mu(|mu| Ok(hoffmann(mu, 0.0, 0.0)), 0.2, 0.45);
    assert!((mu_c - 1.0 / 3.0).abs() < 1e-4, "mu_c = {mu_c}");
    let omega = 2.0 * std::f64::consts::PI * f_c;
    assert!(
        (omega - 1.1f64.sqrt()).abs() < 1e-4,
        "lock-in omega = {omega}"
    );
    assert!((1.1f64.sqrt() - 1.048809).abs() < 1e-6);
    // The two modes that merge: partner found, and their frequencies before the onset
    // bracket the lock-in frequency.
    let (_, c) = s.lowest_critical().unwrap();
    let fp = c.partner_frequency_before_hz.expect("a partner");
    let (f1, f2) = (c.frequency_before_hz.min(fp), c.frequency_before_hz.max(fp));
    let f_lock = 1.1f64.sqrt() / (2.0 * std::f64::consts::PI);
    assert!(f1 < f_lock && f_lock < f2, "{f1} < {f_lock} < {f2}");
    // Below μc the eigenvalues are ±iω with ω² = 1.1 ± sqrt(0.01 + 0.3 (0.3 − μ)).
    let mu = 0.25;
    let r = complex_eigen(&hoffmann(mu, 0.0, 0.0), &CeaOptions::default()).unwrap();
    assert_eq!(r.modes.len(), 2);
    let d = (0.01f64 + 0.3 * (0.3 - mu)).sqrt();
    for (m, w2) in r.modes.iter().zip([1.1 - d, 1.1 + d]) {
        assert!(
            (m.eigenvalue.im - w2.sqrt()).abs() < 1e-12 && m.real_part.abs() < 1e-12,
            "{:?}",
            m.eigenvalue
        );
        assert!(!m.unstable);
    }
}

/// Equal damping c on both DOFs: with p = iΩ on the boundary, Ω² = 1.1 and the imaginary
/// part of ω² equals c Ω: 0.3 (μ − 0.3) − 0.01 = 1.1 c², μc = 0.3 + (0.01 + 1.1 c²)/0.3
/// = 0.3425 for c = 0.05 (damping raises μc).
#[test]
fn hoffmann_equal_damping_raises_critical_mu() {
    let (mu_c, _, _) = critical_mu(|mu| Ok(hoffmann(mu, 0.05, 0.05)), 0.2, 0.45);
    assert!((mu_c - 0.3425).abs() < 1e-4, "mu_c = {mu_c}");
}

/// c1 = 0.1, c2 = 0: det(p²I + pC + K) at p = iΩ: the imaginary part c1 Ω (1.2 − Ω²) = 0
/// gives Ω² = 1.2, the real part then −0.09 + 0.3 μ = 0: μc = 0.3 < 1/3 — damping on one DOF
/// only *lowers* the threshold (the destabilisation paradox).
#[test]
fn hoffmann_unequal_damping_destabilises() {
    let (mu_c, f_c, _) = critical_mu(|mu| Ok(hoffmann(mu, 0.1, 0.0)), 0.2, 0.45);
    assert!((mu_c - 0.3).abs() < 1e-4, "mu_c = {mu_c}");
    let omega = 2.0 * std::f64::consts::PI * f_c;
    assert!((omega - 1.2f64.sqrt()).abs() < 1e-3, "omega = {omega}");
}

/// The same model with DOF y split into two halves y_a, y_b (mass 1/2 each, the y-row
/// stiffness split in halves) tied by G = [0, −1, 1]: summing the two y rows gives back
/// Hoffmann's y equation, so the eigenvalues are identical, and the constraint adds no
/// (spurious zero) root.
fn split_hoffmann(mu: f64, c1: f64, c2: f64) -> CeaMatrices {
    let a = 0.3 - mu;
    let k = [[1.0, a / 2.0, a / 2.0], [0.15, 0.6, 0.0], [0.15, 0.0, 0.6]];
    let mut s = CeaMatrices::new(
        Mat::from_fn(3, 3, |i, j| {
            [[1.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.5]][i][j]
        }),
        Mat::from_fn(3, 3, |i, j| k[i][j]),
    );
    s.b = Some(Mat::from_fn(3, 3, |i, j| {
        if i == j {
            [c1, c2 / 2.0, c2 / 2.0][i]
        } else {
            0.0
        }
    }));
    s.g = Some(Mat::from_fn(1, 3, |_, j| [0.0, -1.0, 1.0][j]));
    s
}

#[test]
fn constrained_model_has_same_eigenvalues_and_no_spurious_roots() {
    for &(mu, c1, c2) in &[
        (0.1, 0.0, 0.0),
        (0.36, 0.0, 0.0),
        (0.32, 0.05, 0.05),
        (0.31, 0.1, 0.0),
    ] {
        let a = complex_eigen(&hoffmann(mu, c1, c2), &CeaOptions::default()).unwrap();
        let b = complex_eigen(&split_hoffmann(mu, c1, c2), &CeaOptions::default()).unwrap();
        assert_eq!(b.stats.n_reduced, 2);
        assert_eq!(b.modes.len(), a.modes.len(), "mu = {mu}");
        for y in &b.modes {
            // Compare with the nearest root (coalesced pairs share a frequency to round-off).
            let x = a
                .modes
                .iter()
                .min_by(|p, q| {
                    (p.eigenvalue - y.eigenvalue)
                        .norm()
                        .total_cmp(&(q.eigenvalue - y.eigenvalue).norm())
                })
                .unwrap();
            assert!(
                (x.eigenvalue - y.eigenvalue).norm() < 1e-10,
                "mu = {mu}: {} vs {}",
                x.eigenvalue,
                y.eigenvalue
            );
            assert!(y.eigenvalue.norm() > 0.5, "spurious root {}", y.eigenvalue);
            // Shapes satisfy G u = 0.
            assert!((y.shape[2] - y.shape[1]).norm() < 1e-12);
        }
    }
    let (mu_c, _, _) = critical_mu(|mu| Ok(split_hoffmann(mu, 0.05, 0.05)), 0.2, 0.45);
    assert!((mu_c - 0.3425).abs() < 1e-4, "mu_c = {mu_c}");
}

/// Hoffmann's model with the normal spring k3 = 1 carried by a third DOF z_r of mass m_r,
/// constrained to follow z (G = [0, −1, 1]), the friction force depending on the constraint
/// force N through D (∂F_x/∂N = −μ, the tangent of F_x = μ·(−N)). Eliminating N from the
/// z_r row (N = −k3 z − m_r z̈) gives the 2-DOF problem with the unsymmetric mass
/// [[1, −μ m_r], [0, 1 + m_r]] and K = [[1, 0.3 − μ], [0.3, 1.2]] whose characteristic
/// polynomial in s = p² is
/// (1 + m_r) s² + (1.2 + (1 + m_r) + 0.3 μ m_r) s + 1.2 − 0.3 (0.3 − μ) = 0.
#[test]
fn friction_tangent_d_is_projected_exactly() {
    let m_r = 0.5;
    for &mu in &[0.2, 0.33, 0.5] {
        let mut s = CeaMatrices::new(
            Mat::from_fn(3, 3, |i, j| if i == j { [1.0, 1.0, m_r][i] } else { 0.0 }),
            Mat::from_fn(3, 3, |i, j| {
                [[1.0, 0.3, 0.0], [0.3, 0.2, 0.0], [0.0, 0.0, 1.0]][i][j]
            }),
        );
        s.g = Some(Mat::from_fn(1, 3, |_, j| [0.0, -1.0, 1.0][j]));
        s.d = Some(Mat::from_fn(3, 1, |i, _| [-mu, 0.0, 0.0][i]));
        let r = complex_eigen(&s, &CeaOptions::default()).unwrap();
        let (a, b, c) = (
            1.0 + m_r,
            1.2 + (1.0 + m_r) + 0.3 * mu * m_r,
            1.2 - 0.3 * (0.3 - mu),
        );
        let disc = Cplx::new(b * b - 4.0 * a * c, 0.0).sqrt();
        let mut expect: Vec<Cplx> = [(-b + disc) / (2.0 * a), (-b - disc) / (2.0 * a)]
            .iter()
            .flat_map(|s| [s.sqrt(), -s.sqrt()])
            .filter(|p| p.im >= 0.0)
            .collect();
        expect.sort_by(|x, y| x.im.total_cmp(&y.im).then(x.re.total_cmp(&y.re)));
        assert_eq!(r.modes.len(), expect.len(), "mu = {mu}");
        for (m, e) in r.modes.iter().zip(&expect) {
            assert!(
                (m.eigenvalue - e).norm() < 1e-10,
                "mu = {mu}: {} vs {e}",
                m.eigenvalue
            );
        }
    }
}

/// Proportional damping C = αM + βK on a random symmetric positive system: the modes are the
/// undamped ones (ω_i² from the symmetric eigenproblem of L⁻¹KL⁻ᵀ, a different algorithm) with
/// ζ_i = (α/ω_i + β ω_i)/2 and p = −ζω ± iω√(1 − ζ²).
#[test]
fn proportional_damping_matches_modal_solution() {
    let n = 12;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let m = random_spd(n, &mut rng, 1.0);
    let k = random_spd(n, &mut rng, 0.5);
    let (alpha, beta) = (0.02, 0.01);
    let mut s = CeaMatrices::new(m.clone(), k.clone());
    s.b = Some(&m * alpha + &k * beta);
    let r = complex_eigen(&s, &CeaOptions::default()).unwrap();
    let llt = m.llt(Side::Lower).unwrap();
    let l = llt.L();
    let mut y = k.clone();
    l.solve_lower_triangular_in_place(&mut y);
    let mut z = y.transpose().to_owned();
    l.solve_lower_triangular_in_place(&mut z);
    let w2 = z.self_adjoint_eigenvalues(Side::Lower).unwrap();
    assert_eq!(r.modes.len(), n);
    for (mode, &w2) in r.modes.iter().zip(&w2) {
        let w = w2.sqrt();
        let zeta = 0.5 * (alpha / w + beta * w);
        let p = Cplx::new(-zeta * w, w * (1.0 - zeta * zeta).sqrt());
        assert!(
            (mode.eigenvalue - p).norm() < 1e-9 * w,
            "{} vs {p}",
            mode.eigenvalue
        );
        // ζ here is the critical-damping ratio; DESIGN.md's damping_ratio = −2 Re/|Im|.
        let g = mode.damping_ratio.unwrap();
        assert!((g - 2.0 * zeta / (1.0 - zeta * zeta).sqrt()).abs() < 1e-8);
        // The shape solves the quadratic problem: |(p²M + pC + K) u| small.
        let res: f64 = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        (mode.eigenvalue * mode.eigenvalue * m[(i, j)]
                            + mode.eigenvalue * s.b.as_ref().unwrap()[(i, j)]
                            + k[(i, j)])
                            * mode.shape[j]
                    })
                    .sum::<Cplx>()
                    .norm_sqr()
            })
            .sum::<f64>()
            .sqrt();
        assert!(res < 1e-9 * (1.0 + w2), "residual {res}");
    }
}

/// One overdamped DOF, m = 1, c = 3, k = 1: two real roots p = (−3 ± √5)/2, no damping ratio.
#[test]
fn real_roots_are_kept_without_damping_ratio() {
    let mut s = CeaMatrices::new(Mat::identity(1, 1), Mat::identity(1, 1));
    s.b = Some(Mat::from_fn(1, 1, |_, _| 3.0));
    let r = complex_eigen(&s, &CeaOptions::default()).unwrap();
    assert_eq!(r.modes.len(), 2);
    assert_eq!(r.stats.n_real_roots, 2);
    let mut re: Vec<f64> = r.modes.iter().map(|m| m.real_part).collect();
    re.sort_by(f64::total_cmp);
    assert!((re[0] - (-3.0 - 5f64.sqrt()) / 2.0).abs() < 1e-12);
    assert!((re[1] - (-3.0 + 5f64.sqrt()) / 2.0).abs() < 1e-12);
    assert!(r
        .modes
        .iter()
        .all(|m| m.damping_ratio.is_none() && m.frequency_hz == 0.0 && !m.unstable));
}

#[test]
fn bad_inputs_are_errors_with_numbers() {
    // Redundant constraints.
    let mut s = split_hoffmann(0.2, 0.0, 0.0);
    s.g = Some(Mat::from_fn(2, 3, |_, j| [0.0, -1.0, 1.0][j]));
    let e = complex_eigen(&s, &CeaOptions::default()).unwrap_err();
    assert!(
        matches!(e, CeaError::RankDeficientConstraints { ng: 2, n: 3, .. }),
        "{e}"
    );
    // Indefinite mass.
    let mut s = hoffmann(0.2, 0.0, 0.0);
    s.m[(1, 1)] = -1.0;
    let e = complex_eigen(&s, &CeaOptions::default()).unwrap_err();
    assert!(
        matches!(e, CeaError::NotPositiveDefinite { pivot: 1, .. }),
        "{e}"
    );
    // Shape and NaN.
    let mut s = hoffmann(0.2, 0.0, 0.0);
    s.b = Some(Mat::zeros(3, 3));
    assert!(matches!(
        complex_eigen(&s, &CeaOptions::default()),
        Err(CeaError::Shape { what: "B", .. })
    ));
    let mut s = hoffmann(0.2, 0.0, 0.0);
    s.k[(0, 1)] = f64::NAN;
    assert!(matches!(
        complex_eigen(&s, &CeaOptions::default()),
        Err(CeaError::NonFinite {
            what: "K",
            row: 0,
            col: 1,
            ..
        })
    ));
    // Non-increasing sweep.
    let e = sweep(
        |mu| Ok::<_, CeaError>(hoffmann(mu, 0.0, 0.0)),
        &[0.1, 0.1],
        &SweepOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("mus[0] = 0.1"), "{e}");
    let o = CeaOptions {
        unstable_tol: -1.0,
        ..CeaOptions::default()
    };
    assert!(complex_eigen(&hoffmann(0.2, 0.0, 0.0), &o).is_err());
}

// ---------------------------------------------------------------------------------------
// Subspace projection (method = "projection") against the exact method.
// ---------------------------------------------------------------------------------------

fn projection(opts: ProjectionOptions) -> CeaOptions {
    CeaOptions {
        method: CeaMethod::Projection,
        projection: opts,
        ..CeaOptions::default()
    }
}

/// Largest relative distance from each exact eigenvalue (frequency ≤ band) to the nearest
/// projected one, computed here independently of `compare_eigenvalues`.
fn max_rel_error(
    proj: &[squeal_solver::cea::Mode],
    exact: &[squeal_solver::cea::Mode],
    band: f64,
) -> f64 {
    exact
        .iter()
        .filter(|e| e.frequency_hz <= band)
        .map(|e| {
            let d = proj
                .iter()
                .map(|p| (p.eigenvalue - e.eigenvalue).norm())
                .fold(f64::INFINITY, f64::min);
            d / e.eigenvalue.norm()
        })
        .fold(0.0, f64::max)
}

/// With the full basis the projected problem is a congruence of the reduced one (Φ is
/// invertible), so every eigenvalue equals the exact one to round-off — checked on the
/// Hoffmann models (plain, with a constraint, with a friction tangent D) below and above μc.
#[test]
fn projection_with_full_basis_is_exact_on_hoffmann_models() {
    let full = projection(ProjectionOptions::default());
    for &(mu, c1, c2) in &[
        (0.1, 0.0, 0.0),
        (0.36, 0.0, 0.0),
        (0.32, 0.05, 0.05),
        (0.31, 0.1, 0.0),
    ] {
        for sys in [hoffmann(mu, c1, c2), split_hoffmann(mu, c1, c2)] {
            let e = complex_eigen(&sys, &CeaOptions::default()).unwrap();
            let p = complex_eigen(&sys, &full).unwrap();
            assert_eq!(p.stats.method, CeaMethod::Projection);
            assert_eq!(e.stats.method, CeaMethod::Exact);
            assert_eq!(p.stats.n_basis, 2);
            assert_eq!(p.modes.len(), e.modes.len());
            let err = max_rel_error(&p.modes, &e.modes, f64::INFINITY);
            assert!(err < 1e-10, "mu = {mu}: {err:e}");
            // Shapes still satisfy the constraint and match the exact ones of the nearest
            // eigenvalue (MAC = 1; above μc the two roots share a frequency).
            for a in &p.modes {
                if sys.g.is_some() {
                    assert!((a.shape[2] - a.shape[1]).norm() < 1e-12);
                }
                let b = e
                    .modes
                    .iter()
                    .min_by(|x, y| {
                        (x.eigenvalue - a.eigenvalue)
                            .norm()
                            .total_cmp(&(y.eigenvalue - a.eigenvalue).norm())
                    })
                    .unwrap();
                let x = mac(&a.shape, &b.shape);
                assert!(x > 1.0 - 1e-10, "mu = {mu}: MAC {x} at {}", a.eigenvalue);
            }
        }
    }
}

/// The critical μ of the projected sweep (basis from the first μ, full basis as the model
/// has 2 DOFs) reproduces the analytic references of the exact tests to 1e-4.
#[test]
fn projected_sweep_reproduces_hoffmann_critical_mu() {
    let opts = SweepOptions {
        cea: projection(ProjectionOptions::default()),
        ..SweepOptions::default()
    };
    // (c1, c2, analytic μc) as derived in the exact tests above.
    for &(c1, c2, mu_ref) in &[(0.0, 0.0, 1.0 / 3.0), (0.05, 0.05, 0.3425), (0.1, 0.0, 0.3)] {
        for split in [false, true] {
            let build = |mu| -> Result<CeaMatrices, CeaError> {
                Ok(if split {
                    split_hoffmann(mu, c1, c2)
                } else {
                    hoffmann(mu, c1, c2)
                })
            };
            let s = sweep(build, &mus(0.2, 0.45, 26), &opts).unwrap();
            assert_eq!(s.stats.method, CeaMethod::Projection);
            let (_, c) = s.lowest_critical().expect("an onset");
            assert!(
                (c.mu - mu_ref).abs() < 1e-4,
                "c = ({c1}, {c2}): {} vs {mu_ref}",
                c.mu
            );
            // Exact checks ran at both ends and agree to round-off.
            assert_eq!(s.stats.exact_checks.len(), 2);
            assert!(s.stats.max_rel_eigenvalue_error.unwrap() < 1e-10);
        }
    }
}

/// A random constrained model (`common::random`), built once and evaluated at any μ.
fn random_constrained(n: usize, ng: usize, seed: u64) -> impl Fn(f64) -> CeaMatrices {
    let model = RandomConstrained::new(n, ng, seed);
    move |mu| model.at(mu)
}

/// Random 150-DOF model with 12 constraints: the full basis reproduces all 138 roots to
/// 1e-10 (round-off); truncated bases give an error in the band of interest (lowest quarter
/// of the spectrum) that decreases as the cutoff grows, and the sweep's exact checks report
/// exactly that error. Measured: 2.2e-4, 1.6e-4, 1.4e-4 relative for cutoffs 1.5×, 2×, 3×
/// the band (48, 69, 104 basis modes) — slow, because the random friction stiffness μK1 is
/// dense and couples every band mode to every truncated one; the 1e-3 bound only guards
/// against a wrong projection (which gives O(1) errors), not the truncation error itself.
#[test]
fn projection_on_random_constrained_model() {
    let build = random_constrained(150, 12, 0x5eed_1234_abcd_0001);
    let sys = build(0.3);
    let e = complex_eigen(&sys, &CeaOptions::default()).unwrap();
    let p = complex_eigen(&sys, &projection(ProjectionOptions::default())).unwrap();
    assert_eq!((p.stats.n_basis, p.modes.len()), (138, e.modes.len()));
    let err_full = max_rel_error(&p.modes, &e.modes, f64::INFINITY);
    assert!(err_full < 1e-10, "full basis: {err_full:e}");
    // Band of interest: the lowest quarter of the spectrum.
    let f_top = e.modes.last().unwrap().frequency_hz;
    let band = 0.25 * f_top;
    let mut errs = Vec::new();
    for factor in [1.5, 2.0, 3.0] {
        let o = ProjectionOptions {
            frequency_max_hz: Some(band),
            cutoff_factor: factor,
            basis_mu: Some(0.0),
            ..ProjectionOptions::default()
        };
        // A sweep over two μ with exact checks at both ends, basis at μ = 0.
        let s = sweep(
            |mu| Ok::<_, CeaError>(build(mu)),
            &[0.0, 0.3],
            &SweepOptions {
                cea: projection(o),
                ..SweepOptions::default()
            },
        )
        .unwrap();
        let nb = s.stats.n_basis;
        let reported = s.stats.max_rel_eigenvalue_error.unwrap();
        let err = max_rel_error(&s.steps[1].modes, &e.modes, band);
        eprintln!("cutoff {factor} x band: nb = {nb}, error {err:e}, reported {reported:e}");
        assert!(nb < 138 && s.stats.check_band_hz == Some(band));
        // The reported error is the independent one (μ = 0.3 dominates; μ = 0 is the
        // basis' own state where only the damping is not diagonal).
        assert!(
            (reported - err.max(s.stats.exact_checks[0].comparison.max_rel_error)).abs()
                <= 1e-12 * (1.0 + reported)
        );
        assert_eq!(
            s.stats.exact_checks[1].comparison.n_exact_in_band,
            s.stats.exact_checks[1].comparison.n_projected_in_band
        );
        errs.push(err);
    }
    assert!(errs[1] < errs[0] && errs[2] < errs[1], "{errs:?}");
    assert!(errs[2] < 1e-3, "{errs:?}");
}

#[test]
fn auto_method_and_basis_mismatch() {
    // Small problem: auto stays exact even with a truncation.
    let opts = SweepOptions {
        cea: CeaOptions {
            projection: ProjectionOptions {
                n_basis: Some(1),
                ..ProjectionOptions::default()
            },
            ..CeaOptions::default()
        },
        ..SweepOptions::default()
    };
    let s = sweep(
        |mu| Ok::<_, CeaError>(hoffmann(mu, 0.0, 0.0)),
        &[0.1, 0.2],
        &opts,
    )
    .unwrap();
    assert_eq!((s.stats.method, s.stats.n_basis), (CeaMethod::Exact, 0));
    assert!(s.stats.exact_checks.is_empty() && s.stats.max_rel_eigenvalue_error.is_none());
    // A basis built for one G refuses a problem with another G.
    let sys = split_hoffmann(0.2, 0.0, 0.0);
    let basis = ModalBasis::new(&sys, &CeaOptions::default()).unwrap();
    let mut other = sys.clone();
    other.g = Some(Mat::from_fn(1, 3, |_, j| [0.0, -1.0, 2.0][j]));
    let e = basis.solve(&other, &CeaOptions::default()).unwrap_err();
    assert!(
        matches!(
            e,
            CeaError::BasisMismatch {
                what: "G",
                row: 0,
                col: 2,
                ..
            }
        ),
        "{e}"
    );
    // A cutoff below the lowest mode is an error naming the field.
    let o = projection(ProjectionOptions {
        basis_cutoff_hz: Some(1e-6),
        ..ProjectionOptions::default()
    });
    let e = complex_eigen(&sys, &o).unwrap_err();
    assert!(e.to_string().contains("basis_cutoff_hz"), "{e}");
}

/// The caller's interrupt stops a friction sweep at its next point (issue 26): after the
/// third solve on the Hoffmann model the sweep returns `Interrupted`, having built no more
/// than the points it solved; without it the same sweep finishes all 26 points.
#[test]
fn interrupt_stops_a_sweep_between_points() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;
    let built = Arc::new(AtomicUsize::new(0));
    let b = built.clone();
    let build = move |mu: f64| -> Result<CeaMatrices, CeaError> {
        b.fetch_add(1, Ordering::SeqCst);
        Ok(hoffmann(mu, 0.0, 0.0))
    };
    let seen = built.clone();
    let opts = SweepOptions {
        cea: CeaOptions {
            interrupt: squeal_solver::Interrupt::new(move || seen.load(Ordering::SeqCst) >= 3),
            ..CeaOptions::default()
        },
        ..SweepOptions::default()
    };
    let e = sweep(build, &mus(0.0, 0.5, 26), &opts).unwrap_err();
    assert!(matches!(e, CeaError::Interrupted { .. }), "{e}");
    assert!(built.load(Ordering::SeqCst) <= 4, "{built:?}");
    let all = sweep(
        |mu| Ok::<_, CeaError>(hoffmann(mu, 0.0, 0.0)),
        &mus(0.0, 0.5, 26),
        &SweepOptions::default(),
    )
    .unwrap();
    assert_eq!(all.steps.len(), 26);
}
