//! `propensity.json`: the estimates of a propensity study from its evaluated rows.
//!
//! # Reference
//! - P(unstable) and the per-band probabilities: the mean of the indicator over all design
//!   rows (every row of A, B and A_B^(i) is a draw of the joint input distribution); the 95 %
//!   interval is the union of the Student-t interval of the R independent replicates'
//!   estimates (randomised QMC: Owen 1997, L'Ecuyer & Lemieux 2002) and the binomial Wilson
//!   score interval of all rows (Wilson 1927), which treats the rows as independent draws and
//!   is therefore wide for QMC points (approximate and conservative, not exact).
//! - Sobol indices: Saltelli et al. (2010), S_i by their Table 2 (b), S_Ti by Jansen (1999),
//!   per replicate, mean and Student-t interval over the replicates ([`crate::uq::sobol_indices`]).

use super::evaluate::EvalInfo;
use super::{Input, Plan, Sample};
use crate::error::PipelineError;
use crate::scene::Scene;
use crate::uq::{probability, quantile, sobol_indices, Band, Outcome, Probability, SobolIndices};
use serde::Serialize;

use squeal_solver::Real;

/// The probability of an unstable root in one one-third-octave band.
#[derive(Debug, Clone, Serialize)]
pub struct BandProbability {
    #[serde(flatten)]
    pub band: Band,
    pub p: Real,
    pub interval: [Real; 2],
}

/// The distribution of the largest Re λ over the samples.
#[derive(Debug, Clone, Serialize)]
pub struct MaxRealPart {
    pub mean: Real,
    /// (q, value) for q = 0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99 (type-7 quantiles).
    pub quantiles: Vec<(Real, Real)>,
    pub min: Real,
    pub max: Real,
    /// `bins` equal bins between min and max: edges (bins + 1) and counts.
    pub histogram_edges: Vec<Real>,
    pub histogram_counts: Vec<usize>,
}

/// The Sobol indices of one output per input key.
#[derive(Debug, Clone, Serialize)]
pub struct SobolOut {
    pub keys: Vec<String>,
    #[serde(flatten)]
    pub indices: SobolIndices,
}

/// Statistics of the run.
#[derive(Debug, Clone, Serialize, Default)]
pub struct PropensityStats {
    pub evaluations: usize,
    pub failed: usize,
    /// Building (or reading) the reduced model once (0 with `--rereduce`).
    pub build_s: Real,
    /// All evaluations.
    pub evaluate_s: Real,
    pub wall_s: Real,
    pub threads: usize,
    /// Where the rows' CEAs spent their time (the CLI's run; None from Python's chunks).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phases: Option<super::evaluate::Phases>,
}

/// `propensity.json`.
#[derive(Debug, Clone, Serialize)]
pub struct PropensityOut {
    pub verb: &'static str,
    pub version: &'static str,
    pub inputs: Vec<Input>,
    pub correlation: Option<Vec<Vec<Real>>>,
    pub method: String,
    pub n_base: usize,
    pub replicates: usize,
    pub seed: u32,
    pub budget: usize,
    pub model: EvalInfo,
    /// P(an unstable root in the validity band).
    pub p_unstable: Probability,
    pub interval_note: &'static str,
    /// Per one-third-octave band (bands from 10 Hz to the validity band's top).
    pub bands: Vec<BandProbability>,
    pub max_real_part: Option<MaxRealPart>,
    /// Sobol indices of the largest Re λ (None: a single input, correlated inputs, or failed
    /// rows in every base point; see `sobol_note`).
    pub sobol_max_real_part: Option<SobolOut>,
    /// Sobol indices of the unstable indicator (0/1).
    pub sobol_unstable: Option<SobolOut>,
    pub sobol_note: String,
    /// The first failed rows' errors (at most 10).
    pub errors: Vec<String>,
    pub stats: PropensityStats,
    pub files: Vec<String>,
}

const INTERVAL_NOTE: &str = "95 % interval: the union of the Student-t interval of the \
independent scrambled-Sobol replicates' estimates and the Wilson score interval of all rows; \
the latter treats the QMC rows as independent draws, so the interval is approximate and \
conservative (wider than the QMC error)";

/// Histogram bins of the largest Re λ.
const BINS: usize = 20;

fn outcomes(plan: &Plan, samples: &[Sample]) -> Result<Vec<Option<Outcome>>, PipelineError> {
    let mut out = vec![None; plan.design.rows.len()];
    let mut seen = vec![false; out.len()];
    for s in samples {
        if s.row >= out.len() || seen[s.row] {
            return Err(PipelineError::Model(format!(
                "propensity: sample of row {} is not one design row",
                s.row
            )));
        }
        seen[s.row] = true;
        out[s.row] = s.outcome.clone();
    }
    if let Some(r) = seen.iter().position(|s| !s) {
        return Err(PipelineError::Model(format!(
            "propensity: design row {r} was not evaluated"
        )));
    }
    Ok(out)
}

/// The estimates from every design row's sample (in any order).
pub fn estimate(
    _scene: &Scene,
    plan: &Plan,
    samples: &[Sample],
    info: &EvalInfo,
) -> Result<PropensityOut, PipelineError> {
    let out = outcomes(plan, samples)?;
    let design = &plan.design;
    let n_ok = out.iter().filter(|o| o.is_some()).count();
    if n_ok == 0 {
        let first = samples
            .iter()
            .find_map(|s| s.error.clone())
            .unwrap_or_default();
        return Err(PipelineError::Model(format!(
            "every sample of the propensity study failed; first error: {first}"
        )));
    }
    let p_unstable = probability(design, &out, |o| o.unstable());
    let bands = info
        .bands
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let p = probability(design, &out, |o| o.unstable_bands.contains(&k));
            BandProbability {
                band: b.clone(),
                p: p.p,
                interval: p.interval,
            }
        })
        .collect();
    let mut re: Vec<Real> = out.iter().flatten().map(|o| o.max_real_part).collect();
    re.sort_by(Real::total_cmp);
    let max_real_part = (!re.is_empty()).then(|| {
        let (lo, hi) = (re[0], re[re.len() - 1]);
        let w = (hi - lo) / BINS as Real;
        let mut counts = vec![0usize; BINS];
        for &x in &re {
            let k = if w > 0.0 {
                (((x - lo) / w) as usize).min(BINS - 1)
            } else {
                0
            };
            counts[k] += 1;
        }
        MaxRealPart {
            mean: re.iter().sum::<Real>() / re.len() as Real,
            quantiles: [0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99]
                .iter()
                .map(|&q| (q, quantile(&re, q)))
                .collect(),
            min: lo,
            max: hi,
            histogram_edges: (0..=BINS).map(|i| lo + w * i as Real).collect(),
            histogram_counts: counts,
        }
    });
    let d = plan.inputs.len();
    let keys = plan.keys();
    let y_re: Vec<Option<Real>> = out
        .iter()
        .map(|o| o.as_ref().map(|o| o.max_real_part))
        .collect();
    let y_un: Vec<Option<Real>> = out
        .iter()
        .map(|o| o.as_ref().map(|o| if o.unstable() { 1.0 } else { 0.0 }))
        .collect();
    let sob = |y: &[Option<Real>]| {
        sobol_indices(design, y, d).map(|indices| SobolOut {
            keys: keys.clone(),
            indices,
        })
    };
    let (s_re, s_un) = (sob(&y_re), sob(&y_un));
    let sobol_note = if !design.indices {
        if d == 1 {
            "one input: no Sobol indices (S = 1 trivially)".to_string()
        } else {
            "correlated inputs: Sobol indices need independent inputs, none computed".to_string()
        }
    } else if s_un.is_none() {
        "S_i (Saltelli 2010, Table 2 (b)) and S_Ti (Jansen 1999) per replicate, 95 % t interval \
         over the replicates; the unstable indicator has no variance (every sample stable or \
         every one unstable): no indices for it"
            .to_string()
    } else {
        "S_i (Saltelli 2010, Table 2 (b)) and S_Ti (Jansen 1999) per replicate, 95 % t interval \
         over the replicates"
            .to_string()
    };
    Ok(PropensityOut {
        verb: "propensity",
        version: crate::VERSION,
        inputs: plan.inputs.clone(),
        correlation: plan.correlation.clone(),
        method: format!(
            "randomised quasi-Monte Carlo: Saltelli's A, B{} matrices from {} independent \
             Owen-scrambled Sobol sequences (Burley 2020 hash-based scrambling) of {} points \
             each, inputs by inverse CDF{}",
            if design.indices { " and A_B^(i)" } else { "" },
            design.replicates,
            design.n_base,
            if plan.correlation.is_some() {
                " after a Gaussian copula (Cholesky factor of the normal scores' correlation)"
            } else {
                ""
            }
        ),
        n_base: design.n_base,
        replicates: design.replicates,
        seed: plan.seed,
        budget: plan.budget,
        model: info.clone(),
        p_unstable,
        interval_note: INTERVAL_NOTE,
        bands,
        max_real_part,
        sobol_max_real_part: s_re,
        sobol_unstable: s_un,
        sobol_note,
        errors: samples
            .iter()
            .filter_map(|s| s.error.as_ref().map(|e| format!("row {}: {e}", s.row)))
            .take(10)
            .collect(),
        stats: PropensityStats {
            evaluations: design.rows.len(),
            failed: design.rows.len() - n_ok,
            ..Default::default()
        },
        files: Vec::new(),
    })
}

/// `samples.csv`: row, replicate, kind, the inputs, max_real_part, its frequency, unstable,
/// n_unstable, error.
pub fn samples_csv(plan: &Plan, samples: &[Sample]) -> String {
    let mut s = String::from("row,replicate,kind");
    for k in plan.keys() {
        s.push(',');
        s.push_str(&k);
    }
    s.push_str(",max_real_part,max_real_part_frequency_hz,unstable,n_unstable,error\n");
    let mut sorted: Vec<&Sample> = samples.iter().collect();
    sorted.sort_by_key(|x| x.row);
    for x in sorted {
        let row = &plan.design.rows[x.row];
        let kind = match row.kind {
            crate::uq::RowKind::A => "A".to_string(),
            crate::uq::RowKind::B => "B".to_string(),
            crate::uq::RowKind::Ab(j) => format!("AB{j}"),
        };
        s.push_str(&format!("{},{},{kind}", x.row, row.replicate));
        for v in &x.values {
            s.push_str(&format!(",{v:?}"));
        }
        let opt = |v: Option<Real>| v.map_or(String::new(), |v| format!("{v:?}"));
        s.push_str(&format!(
            ",{},{},{},{},{}\n",
            opt(x.outcome.as_ref().map(|o| o.max_real_part)),
            opt(x.max_real_part_frequency_hz),
            x.outcome
                .as_ref()
                .map_or(String::new(), |o| o.unstable().to_string()),
            x.n_unstable,
            x.error
                .as_deref()
                .unwrap_or("")
                .replace([',', '\n', '"'], " ")
        ));
    }
    s
}
