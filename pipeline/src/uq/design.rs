//! The sample design of a propensity study: Saltelli's A, B and A_B^(i) matrices from
//! randomised (Owen-scrambled) Sobol points, in independent replicates.

use super::dist::{Copula, Distribution};
use crate::error::PipelineError;
use serde::{Deserialize, Serialize};

/// What a design row is (for the estimators).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RowKind {
    /// Row of A.
    A,
    /// Row of B.
    B,
    /// Row of A_B^(i): A with column i taken from B.
    Ab(usize),
}

/// One point of the design: its replicate, base index, kind and the input values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignRow {
    pub replicate: usize,
    pub index: usize,
    pub kind: RowKind,
    /// The values of the inputs, in the order of the study's keys.
    pub values: Vec<f64>,
}

/// The design: `replicates` independent scramblings of `n_base` Sobol points in 2d
/// dimensions (A from the first d, B from the last d), each giving n_base rows of A and B
/// and, with `indices`, n_base rows of every A_B^(i).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Design {
    pub n_base: usize,
    pub replicates: usize,
    /// Whether the A_B^(i) rows (for the Sobol indices) are in the design.
    pub indices: bool,
    pub rows: Vec<DesignRow>,
}

/// Largest power of two ≤ x (x ≥ 1).
fn pow2_floor(x: usize) -> usize {
    1usize << (usize::BITS - 1 - x.leading_zeros())
}

impl Design {
    /// A design of at most `budget` model evaluations over `dists` (with an optional
    /// copula). The base sample size is the largest power of two (the balanced size of a
    /// scrambled Sobol set) with `replicates × n_base × (d + 2)` ≤ budget (× 2 without
    /// indices). Sobol indices need independent inputs: with a copula, or a single input,
    /// the A_B rows are left out. `seed` selects the scrambling.
    pub fn new(
        dists: &[Distribution],
        copula: Option<&Copula>,
        budget: usize,
        replicates: usize,
        seed: u32,
    ) -> Result<Design, PipelineError> {
        let d = dists.len();
        let err = |message: String| PipelineError::Option {
            option: "--samples".into(),
            message,
        };
        if d == 0 {
            return Err(PipelineError::Option {
                option: "--dist".into(),
                message: "a propensity study needs at least one distribution".into(),
            });
        }
        if 2 * d > sobol_burley::NUM_DIMENSIONS as usize {
            return Err(PipelineError::Option {
                option: "--dist".into(),
                message: format!(
                    "{d} distributions: at most {} are supported",
                    sobol_burley::NUM_DIMENSIONS / 2
                ),
            });
        }
        if replicates < 2 {
            return Err(PipelineError::Option {
                option: "--replicates".into(),
                message: format!("{replicates}: at least 2 replicates give an interval"),
            });
        }
        let indices = copula.is_none() && d > 1;
        let per_base = if indices { d + 2 } else { 2 };
        let per_rep = budget / replicates / per_base;
        if per_rep < 2 {
            return Err(err(format!(
                "{budget} evaluations are too few: {replicates} replicates × {per_base} rows per base point need at least {}",
                2 * replicates * per_base
            )));
        }
        let n_base = pow2_floor(per_rep).min(1 << 16);
        let mut rows = Vec::with_capacity(replicates * n_base * per_base);
        for r in 0..replicates {
            let rseed = seed.wrapping_add(0x9e37_79b9u32.wrapping_mul(r as u32 + 1));
            for i in 0..n_base {
                // Sobol values lie in [0, 1 − 2⁻²⁴]; shift by half a step so no quantile is
                // evaluated at 0.
                let u: Vec<f64> = (0..2 * d)
                    .map(|k| {
                        sobol_burley::sample(i as u32, k as u32, rseed) as f64 + 2f64.powi(-25)
                    })
                    .collect();
                let map = |uu: &[f64]| -> Vec<f64> {
                    let uu = match copula {
                        Some(c) => c.correlate(uu),
                        None => uu.to_vec(),
                    };
                    dists
                        .iter()
                        .zip(&uu)
                        .map(|(dd, &x)| dd.quantile(x))
                        .collect()
                };
                let (ua, ub) = u.split_at(d);
                rows.push(DesignRow {
                    replicate: r,
                    index: i,
                    kind: RowKind::A,
                    values: map(ua),
                });
                rows.push(DesignRow {
                    replicate: r,
                    index: i,
                    kind: RowKind::B,
                    values: map(ub),
                });
                if indices {
                    for j in 0..d {
                        let mut uab = ua.to_vec();
                        uab[j] = ub[j];
                        rows.push(DesignRow {
                            replicate: r,
                            index: i,
                            kind: RowKind::Ab(j),
                            values: map(&uab),
                        });
                    }
                }
            }
        }
        Ok(Design {
            n_base,
            replicates,
            indices,
            rows,
        })
    }
}
