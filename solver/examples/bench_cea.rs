//! Benchmark of the complex eigenvalue analysis: one CEA and a 50-point friction sweep on a
//! random ~500-DOF reduced model with 20 contact constraints. Prints JSON on stdout.
//!
//! `cargo build --release -p squeal-solver --example bench_cea && target/release/examples/bench_cea [n] [ng] [steps]`

use faer::Mat;
use squeal_solver::cea::{complex_eigen, sweep, CeaError, CeaMatrices, CeaOptions, SweepOptions};
use std::time::Instant;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A random model: M = I + small SPD, K = SPD with spread eigenvalues, B = 1e-4 K,
/// G: ng rows u_q − u_p on disjoint DOF pairs (p, q), a tangential DOF t per pair coupled
/// to it, friction −μ K1 (t row) and D = μ D1 (friction ∝ contact force on t).
struct Model {
    m: Mat<f64>,
    k0: Mat<f64>,
    k1: Mat<f64>,
    b: Mat<f64>,
    g: Mat<f64>,
    d1: Mat<f64>,
}

fn model(n: usize, ng: usize) -> Model {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let a = Mat::from_fn(n, n, |_, _| rng.next() / (n as f64).sqrt());
    let mut m = &a * a.transpose() * 0.1;
    let c = Mat::from_fn(n, n, |_, _| rng.next() / (n as f64).sqrt());
    let mut k0 = &c * c.transpose();
    for i in 0..n {
        m[(i, i)] += 1.0;
        k0[(i, i)] += 1.0 + 100.0 * i as f64 / n as f64;
    }
    let mut g = Mat::zeros(ng, n);
    let mut d1 = Mat::zeros(n, ng);
    let mut k1 = Mat::zeros(n, n);
    for r in 0..ng {
        let (p, q) = (2 * r, 2 * r + 1);
        g[(r, q)] = 1.0;
        g[(r, p)] = -1.0;
        // Friction on a tangential DOF of the pad driven by the normal force.
        let t = 2 * ng + r;
        // Bring the tangential DOF near the frequency of the constrained pair and couple
        // them symmetrically, so that friction can merge the two modes (Hoffmann-like).
        k0[(t, t)] = 0.5 * (k0[(p, p)] + k0[(q, q)]) + 0.5;
        for x in [p, q] {
            k0[(t, x)] += 0.5;
            k0[(x, t)] += 0.5;
        }
        d1[(t, r)] = -1.0;
        k1[(t, p)] = 5.0 * rng.next();
        k1[(t, q)] = 5.0 * rng.next();
    }
    let b = &k0 * 1e-4;
    Model {
        m,
        k0,
        k1,
        b,
        g,
        d1,
    }
}

fn build(md: &Model, mu: f64) -> CeaMatrices {
    let mut s = CeaMatrices::new(md.m.clone(), &md.k0 - &md.k1 * mu);
    s.b = Some(md.b.clone());
    s.g = Some(md.g.clone());
    s.d = Some(&md.d1 * mu);
    s
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let n = args.first().copied().unwrap_or(500);
    let ng = args.get(1).copied().unwrap_or(20);
    let steps = args.get(2).copied().unwrap_or(50);
    let md = model(n, ng);
    let t = Instant::now();
    let r = complex_eigen(&build(&md, 0.5), &CeaOptions::default()).expect("CEA");
    let t_cea = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let r2 = complex_eigen(
        &build(&md, 0.5),
        &CeaOptions {
            compute_shapes: false,
            ..CeaOptions::default()
        },
    )
    .expect("CEA");
    let t_cea_values = t.elapsed().as_secs_f64();
    assert_eq!(r.modes.len(), r2.modes.len());
    let mus: Vec<f64> = (0..steps)
        .map(|i| 2.0 * i as f64 / (steps - 1).max(1) as f64)
        .collect();
    let t = Instant::now();
    let opts = SweepOptions {
        bisection: false,
        ..SweepOptions::default()
    };
    let s = sweep(|mu| Ok::<_, CeaError>(build(&md, mu)), &mus, &opts).expect("sweep");
    let t_sweep = t.elapsed().as_secs_f64();
    let low = s
        .lowest_critical()
        .map(|(id, c)| (id, c.mu, c.frequency_hz));
    println!("{{");
    println!(
        "  \"n\": {n}, \"n_constraints\": {ng}, \"n_reduced\": {}, \"first_order_size\": {},",
        r.stats.n_reduced,
        2 * r.stats.n_reduced
    );
    println!(
        "  \"cea_with_shapes_s\": {t_cea:.4}, \"cea_reduce_s\": {:.4}, \"cea_eigen_s\": {:.4},",
        r.stats.time_reduce_s, r.stats.time_eigen_s
    );
    println!("  \"cea_eigenvalues_only_s\": {t_cea_values:.4},");
    println!(
        "  \"cea_modes\": {}, \"cea_unstable_at_mu_0_5\": {},",
        r.stats.n_modes, r.stats.n_unstable
    );
    println!("  \"sweep_steps\": {}, \"sweep_solves\": {}, \"sweep_s\": {t_sweep:.4}, \"sweep_eigen_s\": {:.4}, \"sweep_per_step_s\": {:.4},", s.stats.n_steps, s.stats.n_solves, s.stats.time_eigen_s, t_sweep / s.stats.n_solves as f64);
    println!(
        "  \"sweep_tracks\": {}, \"sweep_critical\": {},",
        s.stats.n_tracks, s.stats.n_critical
    );
    match low {
        Some((id, mu, f)) => println!(
            "  \"lowest_critical\": {{\"track\": {id}, \"mu\": {mu:.6}, \"frequency_hz\": {f:.6}}}"
        ),
        None => println!("  \"lowest_critical\": null"),
    }
    println!("}}");
}
