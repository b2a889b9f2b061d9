//! Input distributions of a propensity study, and their correlation (a Gaussian copula).

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, Normal};

/// The distribution of one scene value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Distribution {
    /// Uniform on [a, b].
    Uniform { a: f64, b: f64 },
    /// Normal with mean and standard deviation.
    Normal { mean: f64, sd: f64 },
    /// Log-normal: ln x is normal with mean `mu` and standard deviation `sigma`.
    LogNormal { mu: f64, sigma: f64 },
    /// Normal with mean and standard deviation, truncated to [lo, hi].
    TruncatedNormal {
        mean: f64,
        sd: f64,
        lo: f64,
        hi: f64,
    },
}

fn std_normal() -> Normal {
    Normal::new(0.0, 1.0).expect("standard normal")
}

impl Distribution {
    /// Parses `uniform(a, b)`, `normal(mean, sd)`, `lognormal(mu, sigma)` or
    /// `truncnormal(mean, sd, lo, hi)`; `key` names the scene key in the error.
    pub fn parse(key: &str, text: &str) -> Result<Self, PipelineError> {
        let err = |message: String| PipelineError::Option {
            option: format!("--dist {key}={text}"),
            message,
        };
        let t = text.trim();
        let open = t.find('(').ok_or_else(|| {
            err("expected NAME(ARGS), e.g. uniform(0.35, 0.55), normal(0.45, 0.03), lognormal(0, 0.1) or truncnormal(0.45, 0.05, 0.3, 0.6)".into())
        })?;
        if !t.ends_with(')') {
            return Err(err("missing the closing `)`".into()));
        }
        let name = t[..open].trim().to_ascii_lowercase();
        let args: Vec<f64> = t[open + 1..t.len() - 1]
            .split(',')
            .map(|a| {
                a.trim()
                    .parse::<f64>()
                    .map_err(|_| err(format!("`{}` is not a number", a.trim())))
            })
            .collect::<Result<_, _>>()?;
        let want = |n: usize| {
            if args.len() == n {
                Ok(())
            } else {
                Err(err(format!("{name} takes {n} numbers, got {}", args.len())))
            }
        };
        let d = match name.as_str() {
            "uniform" => {
                want(2)?;
                Distribution::Uniform {
                    a: args[0],
                    b: args[1],
                }
            }
            "normal" => {
                want(2)?;
                Distribution::Normal {
                    mean: args[0],
                    sd: args[1],
                }
            }
            "lognormal" => {
                want(2)?;
                Distribution::LogNormal {
                    mu: args[0],
                    sigma: args[1],
                }
            }
            "truncnormal" | "truncated_normal" => {
                want(4)?;
                Distribution::TruncatedNormal {
                    mean: args[0],
                    sd: args[1],
                    lo: args[2],
                    hi: args[3],
                }
            }
            other => {
                return Err(err(format!(
                    "unknown distribution `{other}` (uniform, normal, lognormal, truncnormal)"
                )))
            }
        };
        d.validate().map_err(err)?;
        Ok(d)
    }

    /// Checks the parameters (finite, ordered bounds, positive spreads).
    pub fn validate(&self) -> Result<(), String> {
        let finite = |xs: &[f64]| xs.iter().all(|x| x.is_finite());
        match *self {
            Distribution::Uniform { a, b } if !(finite(&[a, b]) && a < b) => {
                Err(format!("uniform needs finite a < b, got a = {a}, b = {b}"))
            }
            Distribution::Normal { mean, sd } if !(finite(&[mean, sd]) && sd > 0.0) => Err(
                format!("normal needs a finite mean and sd > 0, got sd = {sd}"),
            ),
            Distribution::LogNormal { mu, sigma } if !(finite(&[mu, sigma]) && sigma > 0.0) => Err(
                format!("lognormal needs a finite mu and sigma > 0, got sigma = {sigma}"),
            ),
            Distribution::TruncatedNormal { mean, sd, lo, hi } => {
                if !(finite(&[mean, sd, lo, hi]) && sd > 0.0 && lo < hi) {
                    return Err(format!(
                        "truncnormal needs sd > 0 and lo < hi, got sd = {sd}, lo = {lo}, hi = {hi}"
                    ));
                }
                let n = std_normal();
                let mass = n.cdf((hi - mean) / sd) - n.cdf((lo - mean) / sd);
                if mass < 1e-12 {
                    return Err(format!(
                        "truncnormal keeps a probability of {mass:.1e} of its normal: [lo, hi] = [{lo}, {hi}] is too far from the mean {mean}"
                    ));
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// The quantile x = F⁻¹(u) for u in (0, 1).
    pub fn quantile(&self, u: f64) -> f64 {
        let n = std_normal();
        match *self {
            Distribution::Uniform { a, b } => a + (b - a) * u,
            Distribution::Normal { mean, sd } => mean + sd * n.inverse_cdf(u),
            Distribution::LogNormal { mu, sigma } => (mu + sigma * n.inverse_cdf(u)).exp(),
            Distribution::TruncatedNormal { mean, sd, lo, hi } => {
                let (a, b) = (n.cdf((lo - mean) / sd), n.cdf((hi - mean) / sd));
                (mean + sd * n.inverse_cdf(a + u * (b - a))).clamp(lo, hi)
            }
        }
    }

    /// The mean (for the report).
    pub fn mean(&self) -> f64 {
        match *self {
            Distribution::Uniform { a, b } => 0.5 * (a + b),
            Distribution::Normal { mean, .. } => mean,
            Distribution::LogNormal { mu, sigma } => (mu + 0.5 * sigma * sigma).exp(),
            Distribution::TruncatedNormal { mean, sd, lo, hi } => {
                let n = std_normal();
                let (al, be) = ((lo - mean) / sd, (hi - mean) / sd);
                let z = n.cdf(be) - n.cdf(al);
                let pdf = |x: f64| (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt();
                mean + sd * (pdf(al) - pdf(be)) / z
            }
        }
    }
}

/// A Gaussian copula: the inputs' normal scores have the correlation matrix R = L Lᵀ.
#[derive(Debug, Clone, PartialEq)]
pub struct Copula {
    /// Lower Cholesky factor of R (d × d, row-major).
    l: Vec<f64>,
    d: usize,
}

impl Copula {
    /// From a correlation matrix (symmetric, unit diagonal, positive definite); the error
    /// names the entry or the failing pivot.
    pub fn new(r: &[Vec<f64>]) -> Result<Self, PipelineError> {
        let d = r.len();
        let err = |message: String| PipelineError::Option {
            option: "--corr".into(),
            message,
        };
        for (i, row) in r.iter().enumerate() {
            if row.len() != d {
                return Err(err(format!(
                    "row {i} has {} entries, expected {d}",
                    row.len()
                )));
            }
            if (row[i] - 1.0).abs() > 1e-12 {
                return Err(err(format!("R[{i}][{i}] = {} must be 1", row[i])));
            }
            for j in 0..d {
                let x = row[j];
                if !x.is_finite() || x.abs() > 1.0 || (x - r[j][i]).abs() > 1e-12 {
                    return Err(err(format!(
                        "R[{i}][{j}] = {x}: a correlation matrix is symmetric with entries in [-1, 1]"
                    )));
                }
            }
        }
        let mut l = vec![0.0; d * d];
        for j in 0..d {
            let mut s = r[j][j];
            for k in 0..j {
                s -= l[j * d + k] * l[j * d + k];
            }
            if s <= 1e-12 {
                return Err(err(format!(
                    "not positive definite (pivot {j} = {s:.3e}): the correlations are inconsistent"
                )));
            }
            l[j * d + j] = s.sqrt();
            for i in j + 1..d {
                let mut s = r[i][j];
                for k in 0..j {
                    s -= l[i * d + k] * l[j * d + k];
                }
                l[i * d + j] = s / l[j * d + j];
            }
        }
        Ok(Copula { l, d })
    }

    /// Maps independent uniforms u (length d) to correlated uniforms: z = L Φ⁻¹(u), Φ(z).
    pub fn correlate(&self, u: &[f64]) -> Vec<f64> {
        let n = std_normal();
        let z: Vec<f64> = u.iter().map(|&x| n.inverse_cdf(x)).collect();
        (0..self.d)
            .map(|i| {
                let zi: f64 = (0..=i).map(|k| self.l[i * self.d + k] * z[k]).sum();
                n.cdf(zi)
            })
            .collect()
    }
}
