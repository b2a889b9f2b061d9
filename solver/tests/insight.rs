//! Verification of `squeal_solver::insight`: the energy identity 2σE = Σ friction power +
//! Σ damping power of every mode of random constrained models (with rigid and compliant
//! gaps, overlapping components), the sign of the friction feed-in on Hoffmann's model, and
//! the eigenvalue derivatives against central finite differences of the exact CEA.

mod common;
use common::random::{random_spd, Rng};
use faer::Mat;
use squeal_solver::cea::{complex_eigen, CeaMatrices, CeaOptions, Cplx};
use squeal_solver::insight::{
    eigen_triplet, eigenvalue_derivative, mode_energy, ComponentPart, EnergyParts, GapPart,
    MatrixDerivative, TripletSolver,
};

/// A random model of `n` DOFs in three overlapping components and `ng` gaps of four DOFs
/// each; every third gap compliant (k_n ~ 50× the stiffness scale).
fn random_parts(n: usize, ng: usize, seed: u64) -> EnergyParts {
    let mut rng = Rng(seed);
    let ranges = [(0, n / 2), (n / 3, 5 * n / 6), (2 * n / 3, n)];
    let components = ranges
        .iter()
        .enumerate()
        .map(|(c, &(a, b))| {
            let r = b - a;
            let m = random_spd(r, &mut rng, r as f64);
            let mut k = random_spd(r, &mut rng, 0.0);
            for i in 0..r {
                k[(i, i)] += r as f64 * (1.0 + 50.0 * (i as f64 / r as f64).powi(2));
            }
            let damp = &k * 2e-4 + &m * 1e-3;
            ComponentPart {
                name: format!("c{c}"),
                dofs: (a..b).collect(),
                m,
                k,
                b: Some(damp),
            }
        })
        .collect();
    let gaps = (0..ng)
        .map(|k| {
            let mut dofs: Vec<usize> = Vec::new();
            while dofs.len() < 4 {
                let d = ((rng.next() + 1.0) * 0.5 * n as f64) as usize % n;
                if !dofs.contains(&d) {
                    dofs.push(d);
                }
            }
            let g: Vec<f64> = (0..4).map(|_| rng.next()).collect();
            let d: Vec<f64> = (0..4).map(|_| 0.4 * rng.next()).collect();
            let c_f = Mat::from_fn(4, 4, |_, _| 0.05 * rng.next() * (n as f64).sqrt());
            GapPart {
                pair: k % 2,
                dofs,
                g,
                d,
                c_f,
                compliance: if k % 3 == 2 {
                    1.0 / (50.0 * n as f64)
                } else {
                    0.0
                },
            }
        })
        .collect();
    EnergyParts { components, gaps }
}

fn exact_modes(sys: &CeaMatrices) -> Vec<Cplx> {
    let opts = CeaOptions::default();
    complex_eigen(sys, &opts)
        .unwrap()
        .modes
        .iter()
        .map(|m| m.eigenvalue)
        .collect()
}

/// 2σE = Σ P_gap + Σ P_component to 1e-8 for every root of three random models (rigid and
/// compliant gaps, overlapping components); the refined root equals the CEA's to 1e-9.
#[test]
fn the_energy_identity_closes_on_random_models() {
    let mut worst: f64 = 0.0;
    let mut n_unstable = 0;
    for seed in [3_u64, 17, 101] {
        let parts = random_parts(30, 9, seed);
        let sys = parts.assemble(30);
        for p in exact_modes(&sys) {
            if p.im == 0.0 {
                continue;
            }
            let t = eigen_triplet(&sys, p).unwrap();
            assert!(
                (t.p - p).norm() <= 1e-9 * p.norm(),
                "refined {} vs CEA {}",
                t.p,
                p
            );
            assert!(t.residual < 1e-12 && t.left_residual < 1e-12, "{t:?}");
            let e = mode_energy(&parts, &t).unwrap();
            worst = worst.max(e.identity_residual);
            assert!(e.identity_residual < 1e-8, "{e:?}");
            // The friction must be what makes a root unstable: the components' damping only
            // takes energy out (B_c positive definite here).
            assert!(e.damping_power.iter().all(|&x| x <= 0.0));
            if e.growth_rate_per_s > 0.0 {
                n_unstable += 1;
                assert!(e.friction_power.iter().sum::<f64>() > 0.0, "{e:?}");
            }
        }
    }
    eprintln!("worst identity residual {worst:.2e}; unstable roots seen {n_unstable}");
    assert!(
        n_unstable > 0,
        "the random models should have unstable roots"
    );
}

/// The friction power summed over the gaps equals ½ Re vᴴ(C_f v + D ν) with the assembled C_f
/// and D (rigid gaps only), i.e. the split per gap loses nothing.
#[test]
fn the_gap_powers_sum_to_the_assembled_friction_power() {
    let mut parts = random_parts(24, 6, 5);
    for g in &mut parts.gaps {
        g.compliance = 0.0;
    }
    let sys = parts.assemble(24);
    let p = exact_modes(&sys)
        .into_iter()
        .max_by(|a, b| a.re.total_cmp(&b.re))
        .unwrap();
    let t = eigen_triplet(&sys, p).unwrap();
    let e = mode_energy(&parts, &t).unwrap();
    let v: Vec<Cplx> = t.phi.iter().map(|z| t.p * z).collect();
    let (cf, d) = (sys.c_f.as_ref().unwrap(), sys.d.as_ref().unwrap());
    let mut s = Cplx::new(0.0, 0.0);
    for i in 0..24 {
        let mut r = Cplx::new(0.0, 0.0);
        for j in 0..24 {
            r += cf[(i, j)] * v[j];
        }
        for k in 0..t.nu.len() {
            r += d[(i, k)] * t.nu[k];
        }
        s += v[i].conj() * r;
    }
    let total: f64 = e.friction_power.iter().sum();
    assert!(
        (total - 0.5 * s.re).abs() <= 1e-12 * total.abs().max(1e-300),
        "{total} vs {}",
        0.5 * s.re
    );
}

/// Hoffmann et al. (2002) 2-DOF model as energy parts: two unit masses, K = [[1, 0.3 − μ],
/// [0.3, 1.2]]. The circulatory coupling −μ at (0, 1) is a friction force μ·N on DOF 0
/// driven by the normal force N = k_n u₁ of a compliant gap (g = e₁, d = μ e₀, k_n = 1): the
/// gap folds (gᵀ − d) k_n g into K, and the structural part is [[1, 0.3], [0.3, 1.2 − k_n]].
/// Undamped, the roots are on the imaginary axis below μc = 1/3 (no feed-in) and split
/// above it: the growing root's friction power is positive, its decaying partner's
/// negative, and both equal 2σE.
#[test]
fn hoffmann_feed_in_changes_sign_at_lock_in() {
    let kn = 1.0;
    for (mu, unstable) in [(0.30_f64, false), (0.40, true)] {
        // K = [[1, 0.3], [0.3, 1.2 − kn]] + (gᵀ − d) kn g with g = e₁, d = μ e₀:
        // adds kn at (1,1) and −μ kn at (0,1) → K = [[1, 0.3 − μ], [0.3, 1.2]].
        let parts = EnergyParts {
            components: vec![ComponentPart {
                name: "blocks".into(),
                dofs: vec![0, 1],
                m: Mat::identity(2, 2),
                k: Mat::from_fn(2, 2, |i, j| [[1.0, 0.3], [0.3, 1.2 - kn]][i][j]),
                b: None,
            }],
            gaps: vec![GapPart {
                pair: 0,
                dofs: vec![0, 1],
                g: vec![0.0, 1.0],
                d: vec![mu, 0.0],
                c_f: Mat::zeros(2, 2),
                compliance: 1.0 / kn,
            }],
        };
        let sys = parts.assemble(2);
        let want = Mat::from_fn(2, 2, |i, j| [[1.0, 0.3 - mu], [0.3, 1.2]][i][j]);
        assert!((&sys.k - &want).norm_max() < 1e-15);
        for p in exact_modes(&sys) {
            let t = eigen_triplet(&sys, p).unwrap();
            let e = mode_energy(&parts, &t).unwrap();
            assert!(e.identity_residual < 1e-12, "{e:?}");
            if unstable {
                let sign = e.friction_power[0].signum();
                assert_eq!(sign, p.re.signum(), "{e:?}");
                assert!(p.re.abs() > 1e-3);
            } else {
                assert!(
                    p.re.abs() < 1e-12 && e.friction_power[0].abs() < 1e-12,
                    "{e:?}"
                );
            }
        }
    }
}

/// An affine model sys(θ) = sys0 + θ sys1 in every matrix (M, B − C_f, K, G, D).
struct Affine {
    base: CeaMatrices,
    slope: CeaMatrices,
}

impl Affine {
    fn new(n: usize, ng: usize, seed: u64) -> Self {
        let mut rng = Rng(seed);
        let m0 = random_spd(n, &mut rng, n as f64);
        let mut k0 = random_spd(n, &mut rng, 0.0);
        for i in 0..n {
            k0[(i, i)] += n as f64 * (1.0 + 30.0 * (i as f64 / n as f64).powi(2));
        }
        let mut r = || Mat::from_fn(n, n, |_, _| rng.next());
        let (m1, k1, c1, cf0) = (r(), r(), r(), r());
        let mut rng = Rng(seed ^ 0x9e37);
        let g0 = Mat::from_fn(ng, n, |_, _| rng.next());
        let g1 = Mat::from_fn(ng, n, |_, _| 0.2 * rng.next());
        let d0 = Mat::from_fn(n, ng, |_, _| 0.3 * rng.next());
        let d1 = Mat::from_fn(n, ng, |_, _| 0.3 * rng.next());
        let sym = |a: Mat<f64>| (&a + a.transpose()) * 0.5;
        let base = CeaMatrices {
            m: m0,
            k: k0.clone(),
            b: Some(&k0 * 1e-3),
            g: Some(g0),
            d: Some(d0),
            c_f: Some(&cf0 * 0.2),
        };
        let slope = CeaMatrices {
            m: sym(m1) * 0.3,
            k: &k1 * (n as f64),
            b: Some(&c1 * 0.05),
            g: Some(g1),
            d: Some(d1),
            c_f: None,
        };
        Affine { base, slope }
    }
    fn at(&self, th: f64) -> CeaMatrices {
        let (b, s) = (&self.base, &self.slope);
        CeaMatrices {
            m: &b.m + &s.m * th,
            k: &b.k + &s.k * th,
            b: Some(b.b.as_ref().unwrap() + s.b.as_ref().unwrap() * th),
            g: Some(b.g.as_ref().unwrap() + s.g.as_ref().unwrap() * th),
            d: Some(b.d.as_ref().unwrap() + s.d.as_ref().unwrap() * th),
            c_f: b.c_f.clone(),
        }
    }
}

/// ∂p/∂θ from the left and right eigenvectors equals the central difference of the exact
/// CEA's roots (h = 1e-5: truncation ~h² |p'''| and round-off ~ε|p|/h, both below 1e-8
/// relative here) to 1e-6 relative, for every complex root of a random model whose M, C, K,
/// G and D all depend on θ; the analytic matrix derivative and the central difference of the
/// matrices give the same ∂p/∂θ.
#[test]
fn eigenvalue_derivatives_match_central_differences() {
    let model = Affine::new(16, 4, 11);
    let th = 0.2;
    let h = 1e-5;
    let sys = model.at(th);
    let (plus, minus) = (
        exact_modes(&model.at(th + h)),
        exact_modes(&model.at(th - h)),
    );
    let analytic = MatrixDerivative {
        m: Some(model.slope.m.clone()),
        c: model.slope.b.clone(),
        k: Some(model.slope.k.clone()),
        g: model.slope.g.clone(),
        d: model.slope.d.clone(),
    };
    let fd_mats =
        MatrixDerivative::central_difference(&model.at(th + h), &model.at(th - h), h).unwrap();
    let nearest = |set: &[Cplx], p: Cplx| {
        *set.iter()
            .min_by(|a, b| (**a - p).norm().total_cmp(&(**b - p).norm()))
            .unwrap()
    };
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for p in exact_modes(&sys) {
        if p.im == 0.0 {
            continue;
        }
        let t = eigen_triplet(&sys, p).unwrap();
        let s = eigenvalue_derivative(&sys, &t, &analytic);
        let s2 = eigenvalue_derivative(&sys, &t, &fd_mats);
        let fd = (nearest(&plus, p) - nearest(&minus, p)) / (2.0 * h);
        let rel = (s.dp - fd).norm() / fd.norm().max(1e-3 * p.norm());
        worst = worst.max(rel);
        assert!(
            rel < 1e-6,
            "p = {p}: dp {} vs FD {} (rel {rel:.2e})",
            s.dp,
            fd
        );
        assert!((s.dp - s2.dp).norm() <= 1e-7 * s.dp.norm().max(1e-3 * p.norm()));
        checked += 1;
    }
    eprintln!("{checked} roots, worst relative error of dp/dtheta {worst:.2e}");
    assert!(checked >= 8);
}

/// The null-space route (complex LU of size n − ng) and the bordered one (n + ng) give the
/// same refined roots (1e-10 relative), the same mode shapes and multipliers (1e-8), the same
/// ∂p/∂θ (1e-8) for a derivative in every matrix, and residuals below 1e-12, on every complex
/// root of the random model of the central-difference test.
#[test]
fn the_null_space_triplets_equal_the_bordered_ones() {
    let model = Affine::new(16, 4, 11);
    let sys = model.at(0.2);
    let dq = MatrixDerivative {
        m: Some(model.slope.m.clone()),
        c: model.slope.b.clone(),
        k: Some(model.slope.k.clone()),
        g: model.slope.g.clone(),
        d: model.slope.d.clone(),
    };
    let fast = TripletSolver::new(&sys).unwrap();
    let slow = TripletSolver::bordered(&sys).unwrap();
    assert_eq!(fast.factorisation(), "null_space");
    assert_eq!(slow.factorisation(), "bordered");
    let diff = |a: &[Cplx], b: &[Cplx]| {
        let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).norm_sqr()).sum();
        let s: f64 = b.iter().map(|y| y.norm_sqr()).sum();
        (d / s).sqrt()
    };
    let mut checked = 0;
    for p in exact_modes(&sys) {
        if p.im == 0.0 {
            continue;
        }
        let (a, b) = (fast.triplet(p).unwrap(), slow.triplet(p).unwrap());
        assert!((a.p - b.p).norm() <= 1e-10 * p.norm(), "{} vs {}", a.p, b.p);
        assert!(a.residual < 1e-12 && a.left_residual < 1e-12, "{a:?}");
        assert!(diff(&a.phi, &b.phi) < 1e-8, "phi differs at {p}");
        assert!(diff(&a.nu, &b.nu) < 1e-8, "nu differs at {p}");
        let (da, db) = (
            eigenvalue_derivative(&sys, &a, &dq).dp,
            eigenvalue_derivative(&sys, &b, &dq).dp,
        );
        assert!(
            (da - db).norm() <= 1e-8 * db.norm().max(1e-3 * p.norm()),
            "{da} vs {db}"
        );
        checked += 1;
    }
    assert!(checked >= 8);
}

fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// Hoffmann's undamped model (M = I, K = [[1, 0.3 − μ], [0.3, 1.2]]): the two branches
/// coalesce at μc = 1/3 (the discriminant 0.01 + 0.3 (0.3 − μ) of K's eigenvalues vanishes)
/// at ω² = 1.1; the sweep reports one coalescence there, between the two tracks that carry
/// the onset and its partner, and no veering.
#[test]
fn hoffmann_branches_coalesce_at_the_critical_mu() {
    use squeal_solver::cea::{sweep, ModeEvent, SweepOptions};
    let build = |mu: f64| -> Result<CeaMatrices, String> {
        let k = Mat::from_fn(2, 2, |i, j| [[1.0, 0.3 - mu], [0.3, 1.2]][i][j]);
        Ok(CeaMatrices::new(Mat::identity(2, 2), k))
    };
    let s = sweep(build, &grid(0.0, 0.6, 31), &SweepOptions::default()).unwrap();
    let coal: Vec<&ModeEvent> = s
        .events
        .iter()
        .filter(|e| matches!(e, ModeEvent::Coalescence { .. }))
        .collect();
    assert_eq!(coal.len(), 1, "{:?}", s.events);
    assert_eq!(s.events.len(), 1, "no veering: {:?}", s.events);
    let ModeEvent::Coalescence {
        tracks,
        mu,
        frequency_hz,
        last_step,
        ..
    } = coal[0]
    else {
        unreachable!()
    };
    let f_c = 1.1_f64.sqrt() / (2.0 * std::f64::consts::PI);
    eprintln!("coalescence at mu = {mu:.6} (exact 1/3), f = {frequency_hz:.6} Hz (exact {f_c:.6})");
    assert!((mu - 1.0 / 3.0).abs() < 2e-3, "mu {mu}");
    assert!((frequency_hz - f_c).abs() < 2e-3 * f_c);
    assert_eq!(*last_step, 30, "locked to the end of the sweep");
    let (id, c) = s.lowest_critical().unwrap();
    let mut pair = [id, c.partner.unwrap()];
    pair.sort();
    let mut t = *tracks;
    t.sort();
    assert_eq!(t, pair);
}

/// Two undamped DOFs K = [[1 + μ, ε], [ε, 2 − μ]], ε = 0.02: the branches approach at μ = 0.5
/// to a gap of 2ε in ω² and part again with their shapes exchanged (the classic veering of
/// weakly coupled modes); the sweep reports a veering at μ = 0.5 and no coalescence.
#[test]
fn a_weakly_coupled_pair_veers() {
    use squeal_solver::cea::{sweep, ModeEvent, SweepOptions};
    let eps = 0.02;
    let build = move |mu: f64| -> Result<CeaMatrices, String> {
        let k = Mat::from_fn(2, 2, |i, j| [[1.0 + mu, eps], [eps, 2.0 - mu]][i][j]);
        Ok(CeaMatrices::new(Mat::identity(2, 2), k))
    };
    let s = sweep(build, &grid(0.0, 1.0, 41), &SweepOptions::default()).unwrap();
    assert_eq!(s.events.len(), 1, "{:?}", s.events);
    let ModeEvent::Veering {
        mu,
        min_gap_hz,
        mac_exchange,
        ..
    } = &s.events[0]
    else {
        panic!("{:?}", s.events)
    };
    let gap = ((1.5 + eps).sqrt() - (1.5 - eps).sqrt()) / (2.0 * std::f64::consts::PI);
    eprintln!("veering at mu = {mu}, gap {min_gap_hz:.6} Hz (exact {gap:.6}), exchange MAC {mac_exchange:.3}");
    assert!((mu - 0.5).abs() < 1e-12);
    assert!((min_gap_hz - gap).abs() < 1e-9);
    // At μ = 0.5 ∓ 0.025 the diagonal differs by ∓0.05: the shapes are turned by ±θ off the
    // axes with tan 2θ = 2ε/0.05, so the lower shape before and the upper one after are 2θ
    // apart: MAC = cos² 2θ = 1/(1 + (2ε/0.05)²).
    let want = 1.0 / (1.0 + (2.0 * eps / 0.05_f64).powi(2));
    assert!(
        (mac_exchange - want).abs() < 1e-9,
        "{mac_exchange} vs {want}"
    );
    assert_eq!(
        s.tracks.len(),
        2,
        "the branches are followed through the veering"
    );
}
