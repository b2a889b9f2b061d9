use super::*;
use std::f64::consts::PI;

fn eval(design: &Design, f: impl Fn(&[f64]) -> f64) -> Vec<Option<f64>> {
    design.rows.iter().map(|r| Some(f(&r.values))).collect()
}

/// The Ishigami function on U(−π, π)³ with a = 7, b = 0.1 has closed-form indices
/// (Ishigami & Homma 1990; Saltelli et al. 2010 use it to test these estimators):
/// V = a²/8 + bπ⁴/5 + b²π⁸/18 + 1/2, V1 = (1 + bπ⁴/5)²/2, V2 = a²/8, V13 = b²π⁸(1/18 − 1/50),
/// so S1 = V1/V, S2 = V2/V, S3 = 0, ST1 = (V1 + V13)/V, ST2 = S2, ST3 = V13/V. The estimates
/// from 8 replicates of 2¹¹ base points are within 0.02 of them and their intervals hold
/// them.
#[test]
fn saltelli_estimators_reproduce_the_ishigami_indices() {
    let (a, b) = (7.0, 0.1);
    let u = Distribution::Uniform { a: -PI, b: PI };
    let design = Design::new(&[u.clone(), u.clone(), u], None, 8 * 2048 * 5, 8, 7).unwrap();
    assert_eq!(design.n_base, 2048);
    let y = eval(&design, |x| {
        x[0].sin() + a * x[1].sin().powi(2) + b * x[2].powi(4) * x[0].sin()
    });
    let s = sobol_indices(&design, &y, 3).unwrap();
    let pi4 = PI.powi(4);
    let v = a * a / 8.0 + b * pi4 / 5.0 + b * b * pi4 * pi4 / 18.0 + 0.5;
    let v1 = (1.0 + b * pi4 / 5.0).powi(2) / 2.0;
    let v2 = a * a / 8.0;
    let v13 = b * b * pi4 * pi4 * (1.0 / 18.0 - 1.0 / 50.0);
    let s1 = [v1 / v, v2 / v, 0.0];
    let st = [(v1 + v13) / v, v2 / v, v13 / v];
    eprintln!(
        "S1 {:?} vs {s1:?}\nST {:?} vs {st:?}",
        s.first_order, s.total
    );
    for i in 0..3 {
        assert!((s.first_order[i] - s1[i]).abs() < 0.02, "S1[{i}]");
        assert!((s.total[i] - st[i]).abs() < 0.02, "ST[{i}]");
        let (lo, hi) = (s.total_interval[i][0], s.total_interval[i][1]);
        assert!(lo <= st[i] && st[i] <= hi, "ST[{i}] interval [{lo}, {hi}]");
    }
    assert!((s.variance - v).abs() < 0.02 * v);
}

/// P(μ > μc) for μ ~ U(a, b) is (b − μc)/(b − a) exactly: with Hoffmann's μc = 1/3 and
/// U(0.2, 0.5), 5/9. The estimate is within 2e-3 and its interval holds the exact value.
#[test]
fn probability_of_an_exceedance_is_the_uniform_fraction() {
    let mu = Distribution::Uniform { a: 0.2, b: 0.5 };
    let design = Design::new(&[mu], None, 4096, 4, 1).unwrap();
    assert!(!design.indices, "one input: no A_B rows");
    let out: Vec<Option<Outcome>> = design
        .rows
        .iter()
        .map(|r| {
            Some(Outcome {
                max_real_part: r.values[0] - 1.0 / 3.0,
                unstable_bands: if r.values[0] > 1.0 / 3.0 {
                    vec![0]
                } else {
                    vec![]
                },
                unstable: r.values[0] > 1.0 / 3.0,
            })
        })
        .collect();
    let p = probability(&design, &out, |o| o.unstable());
    let exact = 5.0 / 9.0;
    eprintln!("P = {} in {:?} (exact {exact})", p.p, p.interval);
    assert!((p.p - exact).abs() < 2e-3);
    assert!(p.interval[0] <= exact && exact <= p.interval[1]);
    assert!(p.interval[1] - p.interval[0] < 0.05);
}

#[test]
fn quantiles_of_the_distributions() {
    let n = Distribution::Normal { mean: 2.0, sd: 0.5 };
    assert!((n.quantile(0.5) - 2.0).abs() < 1e-12);
    assert!((n.quantile(0.975) - (2.0 + 0.5 * 1.959963984540054)).abs() < 1e-9);
    let l = Distribution::LogNormal {
        mu: 0.0,
        sigma: 0.2,
    };
    assert!((l.quantile(0.5) - 1.0).abs() < 1e-12);
    let t = Distribution::TruncatedNormal {
        mean: 0.45,
        sd: 0.1,
        lo: 0.4,
        hi: 0.5,
    };
    for u in [1e-9, 0.3, 0.5, 0.9999999] {
        let x = t.quantile(u);
        assert!((0.4..=0.5).contains(&x), "{x}");
    }
    assert!(
        (t.quantile(0.5) - 0.45).abs() < 1e-12,
        "symmetric truncation keeps the median"
    );
    assert!((t.mean() - 0.45).abs() < 1e-12);
}

#[test]
fn bad_distributions_name_the_key_and_the_text() {
    for (text, frag) in [
        ("uniform(0.5, 0.3)", "a < b"),
        ("normal(1, -2)", "sd > 0"),
        ("gamma(1, 2)", "unknown distribution `gamma`"),
        ("uniform(0.1)", "takes 2 numbers"),
        ("uniform(0.1, x)", "`x` is not a number"),
        ("uniform 0.1 0.2", "expected NAME(ARGS)"),
        ("truncnormal(0, 1, 50, 60)", "too far from the mean"),
    ] {
        let e = Distribution::parse("friction.mu", text)
            .unwrap_err()
            .to_string();
        assert!(e.contains("friction.mu") && e.contains(frag), "{text}: {e}");
    }
}

/// The Gaussian copula gives the normal scores the asked correlation: 0.7 between two
/// uniforms, measured on 2¹⁴ points to within 0.01; an inconsistent matrix is refused.
#[test]
fn copula_correlates_the_normal_scores() {
    use statrs::distribution::{ContinuousCDF, Normal};
    let c = Copula::new(&[vec![1.0, 0.7], vec![0.7, 1.0]]).unwrap();
    let u = Distribution::Uniform { a: 0.0, b: 1.0 };
    let design = Design::new(&[u.clone(), u], Some(&c), 2 * 2 * 8192, 2, 3).unwrap();
    let n = Normal::new(0.0, 1.0).unwrap();
    let z: Vec<(f64, f64)> = design
        .rows
        .iter()
        .map(|r| (n.inverse_cdf(r.values[0]), n.inverse_cdf(r.values[1])))
        .collect();
    let m = z.len() as f64;
    let (sx, sy) = (
        z.iter().map(|p| p.0).sum::<f64>() / m,
        z.iter().map(|p| p.1).sum::<f64>() / m,
    );
    let cov = z.iter().map(|p| (p.0 - sx) * (p.1 - sy)).sum::<f64>() / m;
    let vx = z.iter().map(|p| (p.0 - sx).powi(2)).sum::<f64>() / m;
    let vy = z.iter().map(|p| (p.1 - sy).powi(2)).sum::<f64>() / m;
    let rho = cov / (vx * vy).sqrt();
    assert!((rho - 0.7).abs() < 0.01, "{rho}");
    let e = Copula::new(&[
        vec![1.0, 0.9, -0.9],
        vec![0.9, 1.0, 0.9],
        vec![-0.9, 0.9, 1.0],
    ])
    .unwrap_err()
    .to_string();
    assert!(e.contains("not positive definite"), "{e}");
}

/// IEC 61260-1 base-10 bands: mid-bands 1000·10^(k/10) (nominal 1000, 1250, …, 5000 is
/// 5011.9 Hz), each 10^(1/10) wide; a frequency falls in exactly one band.
#[test]
fn one_third_octave_bands() {
    let b = third_octave_bands(100.0, 20000.0);
    assert_eq!(b.len(), 24);
    assert!((b[0].center_hz - 100.0).abs() < 1e-9);
    assert!((b[b.len() - 1].center_hz - 19952.62).abs() < 0.01);
    let k = band_of(&b, 5423.4).unwrap();
    assert!((b[k].center_hz - 5011.87).abs() < 0.01);
    for w in b.windows(2) {
        assert!((w[0].upper_hz - w[1].lower_hz).abs() < 1e-9 * w[1].lower_hz);
    }
}
