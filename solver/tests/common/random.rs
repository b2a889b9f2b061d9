//! Random test models for the CEA tests (deterministic: a seeded xorshift64* generator).

use faer::Mat;
use squeal_solver::cea::CeaMatrices;

/// Small deterministic generator (xorshift64*), uniform in [−1, 1).
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A Aᵀ + shift·I with A uniform in [−1, 1)ⁿˣⁿ.
pub fn random_spd(n: usize, rng: &mut Rng, shift: f64) -> Mat<f64> {
    let a = Mat::from_fn(n, n, |_, _| rng.next());
    let mut s = &a * a.transpose();
    for i in 0..n {
        s[(i, i)] += shift;
    }
    s
}

/// A random constrained model: n DOFs, ng random constraints, unsymmetric friction stiffness
/// μ K1, friction tangent μ D1, damping B = 1e-4 K0 + 1e-3 M. Built once, evaluated at any μ.
pub struct RandomConstrained {
    m: Mat<f64>,
    k0: Mat<f64>,
    k1: Mat<f64>,
    g: Mat<f64>,
    d1: Mat<f64>,
    b: Mat<f64>,
}

impl RandomConstrained {
    pub fn new(n: usize, ng: usize, seed: u64) -> Self {
        let mut rng = Rng(seed);
        let m = random_spd(n, &mut rng, n as f64);
        let mut k0 = random_spd(n, &mut rng, 0.0);
        for i in 0..n {
            // Spread the spectrum: ω² from ~n to ~100 n.
            k0[(i, i)] += n as f64 * (1.0 + 100.0 * (i as f64 / n as f64).powi(2));
        }
        let k1 = Mat::from_fn(n, n, |_, _| 0.5 * rng.next() * (n as f64).sqrt());
        let g = Mat::from_fn(ng, n, |_, _| rng.next());
        let d1 = Mat::from_fn(n, ng, |_, _| 0.3 * rng.next());
        let b = &k0 * 1e-4 + &m * 1e-3;
        Self {
            m,
            k0,
            k1,
            g,
            d1,
            b,
        }
    }

    /// The model at friction coefficient μ.
    pub fn at(&self, mu: f64) -> CeaMatrices {
        let mut s = CeaMatrices::new(self.m.clone(), &self.k0 + &self.k1 * mu);
        s.b = Some(self.b.clone());
        s.g = Some(self.g.clone());
        s.d = Some(&self.d1 * mu);
        s
    }
}
