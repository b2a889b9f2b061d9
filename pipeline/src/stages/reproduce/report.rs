//! Outputs of `squeal reproduce`: `cases.json`, `cases.md`, the comparison figures, the spectrum
//! of a squealing response and `report.md` with the paper's findings checked.

use super::{CaseResult, StudySpec};
use crate::error::PipelineError;
use crate::figures::{spectrum, time_history, write_figure, SpectrumOptions};
use crate::output::RunDir;
use crate::scene::Scene;
use crate::stages::cea::sweep::{CouplingOut, SweepReport};
use crate::stages::transient::History;
use crate::verdict::guard::VerdictState;
use crate::verdict::Verdict;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

use squeal_solver::Real;

/// One of the paper's findings and whether this run shows it.
#[derive(Debug, Clone, Serialize)]
pub struct Finding {
    /// (a)..(d).
    pub id: &'static str,
    /// The paper's statement.
    pub paper: &'static str,
    /// `Some(true)`: reproduced; `Some(false)`: not; `None`: not decided (the cases needed were
    /// not run, or a verdict it rests on is `unresolved`: a run that could not see squeal
    /// neither confirms nor contradicts the paper).
    pub reproduced: Option<bool>,
    /// The numbers behind the verdict.
    pub evidence: String,
}

/// The complex eigenvalues of the base scene over constant μ (`cea_sweep/cea.sweep.json`, the
/// fields of [`SweepReport`](crate::stages::cea::sweep::SweepReport) the report uses).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SweepSummary {
    pub mu: Vec<Real>,
    /// Lowest critical μ first.
    pub couplings: Vec<CouplingOut>,
    pub lowest_critical_mu: Option<Real>,
    #[serde(default)]
    pub error: Option<String>,
}

impl SweepSummary {
    /// The fields the report uses of a CEA friction sweep.
    pub fn of(rep: &SweepReport) -> Self {
        Self {
            mu: rep.mu.clone(),
            couplings: rep.couplings.clone(),
            lowest_critical_mu: rep.lowest_critical_mu,
            error: None,
        }
    }

    /// A sweep that did not run.
    pub fn failed(error: String) -> Self {
        Self {
            mu: Vec::new(),
            couplings: Vec::new(),
            lowest_critical_mu: None,
            error: Some(error),
        }
    }

    /// The report's section: the couplings table and the root locus.
    fn markdown(&self) -> String {
        let mut md = String::from(
            "## Complex eigenvalues: which modes couple at which μ

",
        );
        if let Some(e) = &self.error {
            let _ = writeln!(
                md,
                "The sweep failed: {e}
"
            );
            return md;
        }
        let _ = writeln!(
            md,
            "Base scene with a constant μ from {} to {} ({} values), linearised at its steady \
             sliding state (`cea_sweep/`). A pair of modes couples at the critical μ where one \
             of them turns unstable (Re p > 0, its partner more damped); the lowest critical μ \
             is {}: a constant μ below it gives no unstable mode, above it squeal is \
             possible. The pair is the two modes nearest in frequency at the last stable μ \
             (greedy tracking; a partner far away in frequency means the mode turned unstable \
             alone).\n\n| critical μ | frequency at coupling (Hz) | pair before coupling (Hz) | split |\n|---|---|---|---|",
            self.mu.first().map_or("–".into(), |m| format!("{m}")),
            self.mu.last().map_or("–".into(), |m| format!("{m}")),
            self.mu.len(),
            self.lowest_critical_mu
                .map_or("– (none in the range)".into(), |m| format!("{m:.3}"))
        );
        for c in &self.couplings {
            let (pair, split) = match c.pair_frequencies_before_hz {
                [Some(a), Some(b)] => (
                    format!("{a:.1} / {b:.1}"),
                    format!("{:.1} %", 200.0 * (a - b).abs() / (a + b)),
                ),
                [Some(a), None] | [None, Some(a)] => (format!("{a:.1} / –"), "–".into()),
                _ => ("–".into(), "–".into()),
            };
            let _ = writeln!(
                md,
                "| {:.3} | {:.1} | {pair} | {split} |",
                c.mu_critical, c.frequency_hz
            );
        }
        if self.couplings.is_empty() {
            md.push_str("| – | no pair couples in this range | | |\n");
        }
        md.push_str("\n![root locus](cea_sweep/root_locus_mu.png)\n\n");
        md
    }
}

/// What the report uses of a case besides its `cases.json` row, kept in memory from the
/// case's runs (nothing is read back from its files).
#[derive(Debug, Clone)]
pub struct CaseData {
    pub case: u32,
    /// The transient's sampled history (the rows of `history.npy`; None with
    /// `output.history = false`).
    pub history: Option<History>,
    /// The steady-state μ range (min, max) of the case's CEA (None: no CEA, or not finite).
    pub cea_mu_range: Option<(Real, Real)>,
}

impl CaseData {
    /// One column of the case's history: (t, values), t strictly increasing.
    pub fn column(&self, name: &str) -> Result<(Vec<Real>, Vec<Real>), PipelineError> {
        let h = self.history.as_ref().ok_or_else(|| PipelineError::Scene {
            field: "output.history".into(),
            message: format!(
                "case {} recorded no history: the report's figures need output.history = true",
                self.case
            ),
        })?;
        let (Some(ts), Some(ys)) = (h.column("t"), h.column(name)) else {
            return Err(PipelineError::Scene {
                field: "output.grids".into(),
                message: format!("case {}: the history has no column `{name}`", self.case),
            });
        };
        Ok(increasing(&ts, &ys))
    }
}

/// (t, y) with the rows whose t does not exceed the previous one left out (the final row may
/// repeat the last step's time).
fn increasing(ts: &[Real], ys: &[Real]) -> (Vec<Real>, Vec<Real>) {
    let mut t = Vec::with_capacity(ts.len());
    let mut y = Vec::with_capacity(ts.len());
    for (&tr, &yr) in ts.iter().zip(ys) {
        if t.last().is_some_and(|&l: &Real| tr <= l) {
            continue;
        }
        t.push(tr);
        y.push(yr);
    }
    (t, y)
}

/// Onset of squeal: the time the squealing root's fitted amplitude reaches `level`.
///
/// The squealing root is the verdict's deciding root ([`PencilFit::deciding`](crate::verdict::roots::PencilFit::deciding),
/// the fastest-growing significant root); its amplitude (norm over the output DOFs)
/// is `amplitude`·e^{σ(t − t0)} over the fitted window [t0, t1]. The onset is where that
/// reaches `level`: t0 when it starts above, None when σ ≤ 0 or the level is not reached
/// within the window (no extrapolation beyond the run). One DOF's velocity crossing a level
/// (the earlier definition) mixes the squealing mode with the strongly damped modes the
/// load ramp rings: on the compliant study brake case 2's pad velocity stays at 0.6–0.9 in/s
/// for 6 ms while its 2.1 kHz root doubles.
pub fn onset_time(verdict: &Verdict, level: Real) -> Option<Real> {
    let fit = verdict.estimator.as_ref()?;
    let [t0, t1] = fit.window;
    let root = fit.deciding()?;
    let sigma = root.growth_rate_per_s;
    if !(sigma > 0.0 && root.amplitude > 0.0) {
        return None;
    }
    if root.amplitude >= level {
        return Some(t0);
    }
    let t = t0 + (level / root.amplitude).ln() / sigma;
    (t <= t1).then_some(t)
}

/// Displacement column of the grid DOF a velocity column reads (`v_G_z` → `u_G_z`).
fn displacement_of(response: &str) -> String {
    response
        .strip_prefix("v_")
        .map_or_else(|| response.to_string(), |r| format!("u_{r}"))
}

fn opt(x: Option<Real>, prec: usize) -> String {
    x.map_or_else(|| "–".into(), |v| format!("{v:.prec$e}"))
}

/// The paper's NS (accepted steps) of cases 1–8 (its table, section 3).
pub const PAPER_NS: [u64; 8] = [2504, 2300, 1748, 2246, 1086, 3520, 3306, 68];

/// The table of the paper with our columns, Markdown.
pub fn table(cases: &[CaseResult]) -> String {
    let mut s = String::from(
        "| Case | RTOL1 | TLOAD | μ | G | W3 | P0 | TF | NS | paper NS | CPU s | t reached | verdict | deciding root σ (1/s) at f (Hz) | largest root f (Hz) | largest root vs CEA (Δσ/σ, Δf/f) | unstable CEA modes (Hz: Re) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for c in cases {
        let cea = match (&c.cea_unstable_modes, &c.cea_error) {
            (Some(m), _) if m.is_empty() => "none".to_string(),
            (Some(m), _) => m
                .iter()
                .take(4)
                .map(|m| format!("{:.0}: {:+.1}", m.frequency_hz, m.real_part))
                .collect::<Vec<_>>()
                .join("; "),
            (None, Some(_)) => "failed".into(),
            (None, None) => "not run".into(),
        };
        let vs = c
            .transient_vs_cea
            .as_ref()
            .and_then(|p| p.first())
            .map_or("–".into(), |p| {
                format!(
                    "{:.1} Hz {:+.1} /s vs {:.1} Hz {:+.1} /s ({:+.2} %, {:+.3} %)",
                    p.transient_frequency_hz,
                    p.transient_growth_rate_per_s,
                    p.cea_frequency_hz,
                    p.cea_real_part,
                    100.0 * p.rel_diff_growth,
                    100.0 * p.rel_diff_frequency
                )
            });
        // The deciding root (the fastest-growing significant one, which the verdict and the
        // growth column use) and the largest one (which the CEA pairing lists first) can differ.
        let deciding = c.growth_rate_per_s.map_or("–".into(), |g| {
            match c.roots.iter().find(|r| r.growth_rate_per_s == g) {
                Some(r) => format!("{g:.3e} at {:.0}", r.frequency_hz),
                None => format!("{g:.3e}"),
            }
        });
        let paper_ns = PAPER_NS
            .get((c.case as usize).wrapping_sub(1))
            .map_or("–".into(), |n| n.to_string());
        let _ = writeln!(
            s,
            "| {} | {:e} | {} | {} | {} | {} | {} | {} | {} | {paper_ns} | {:.1} | {:.4e} | {} | {} | {} | {vs} | {} |",
            c.case,
            c.rtol1,
            c.tload,
            c.mu,
            c.g,
            c.w3,
            c.p0,
            c.tf,
            c.steps,
            c.cpu_s,
            c.t_end,
            c.verdict.label(),
            deciding,
            c.dominant_frequency_hz
                .map_or("–".into(), |f| format!("{f:.0}")),
            cea
        );
    }
    s
}

/// The verdict with its reasons, for the report's evidence.
pub fn verdict_text(v: &VerdictState) -> String {
    match v {
        VerdictState::Unresolved { reasons } => format!(
            "unresolved ({})",
            reasons
                .iter()
                .map(|r| r.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        ),
        other => other.label().to_string(),
    }
}

fn by_case(cases: &[CaseResult], n: u32) -> Option<&CaseResult> {
    cases.iter().find(|c| c.case == n)
}

fn data_of(data: &[CaseData], n: u32) -> Option<&CaseData> {
    data.iter().find(|d| d.case == n)
}

/// Column `name` of case `n`'s history.
fn column_of(
    data: &[CaseData],
    n: u32,
    name: &str,
) -> Result<(Vec<Real>, Vec<Real>), PipelineError> {
    data_of(data, n)
        .ok_or_else(|| PipelineError::Model(format!("case {n} has no data in memory")))?
        .column(name)
}

/// Largest |a(t) − b(t)| over max |b| on the common time span (a interpolated linearly).
fn relative_difference(a: &(Vec<Real>, Vec<Real>), b: &(Vec<Real>, Vec<Real>)) -> Option<Real> {
    let t_end = a.0.last()?.min(*b.0.last()?);
    let (mut num, mut den) = (0.0f64, 0.0f64);
    let mut j = 0;
    for (&t, &yb) in b.0.iter().zip(&b.1) {
        if t > t_end {
            break;
        }
        while j + 1 < a.0.len() && a.0[j + 1] < t {
            j += 1;
        }
        if j + 1 >= a.0.len() {
            break;
        }
        let w = ((t - a.0[j]) / (a.0[j + 1] - a.0[j])).clamp(0.0, 1.0);
        let ya = a.1[j] + w * (a.1[j + 1] - a.1[j]);
        num = num.max((ya - yb).abs());
        den = den.max(yb.abs());
    }
    (den > 0.0).then(|| num / den)
}

/// The most unstable CEA mode of a case as `f Hz: Re p /s`, and its steady-state μ range.
fn cea_evidence(c: &CaseResult, data: &[CaseData]) -> String {
    let top = c.cea_unstable_modes.as_ref().and_then(|m| {
        m.iter()
            .max_by(|a, b| a.real_part.total_cmp(&b.real_part))
            .map(|m| format!("{:.0} Hz, Re p = {:+.1} /s", m.frequency_hz, m.real_part))
    });
    let mu = data_of(data, c.case).and_then(|d| d.cea_mu_range);
    format!(
        "CEA of case {}: most unstable {}{}",
        c.case,
        top.unwrap_or_else(|| "none".into()),
        mu.map_or(String::new(), |(a, b)| format!(
            ", steady-state μ {a:.3}..{b:.3}"
        ))
    )
}

fn findings(
    cases: &[CaseResult],
    data: &[CaseData],
    resp_u: &str,
    sweep: Option<&SweepSummary>,
) -> Vec<Finding> {
    let mut out = Vec::new();
    let g = |c: &CaseResult| c.growth_rate_per_s.unwrap_or(Real::NAN);
    // (a)
    let (c2, c4) = (by_case(cases, 2), by_case(cases, 4));
    out.push(Finding {
        id: "a",
        paper: "μ = 0.7 − 0.0005V (case 2) and μ = 0.7 (case 4) squeal; the former grows faster",
        reproduced: match (c2, c4) {
            (Some(a), Some(b)) => match (&a.verdict, &b.verdict) {
                (VerdictState::Squeal, VerdictState::Squeal) => Some(g(a) > g(b)),
                (VerdictState::NoSqueal, _) | (_, VerdictState::NoSqueal) => Some(false),
                _ => None,
            },
            _ => None,
        },
        evidence: match (c2, c4) {
            (Some(a), Some(b)) => format!(
                "case 2: {}, growth {:.4e} /s; case 4: {}, growth {:.4e} /s (the former {} faster). {}; {}",
                verdict_text(&a.verdict),
                g(a),
                verdict_text(&b.verdict),
                g(b),
                if g(a) > g(b) { "grows" } else { "does not grow" },
                cea_evidence(a, data),
                cea_evidence(b, data)
            ),
            _ => "cases 2 and 4 not both run".into(),
        },
    });
    // (b)
    let c6 = by_case(cases, 6);
    out.push(Finding {
        id: "b",
        paper: "μ = 0.3 does not squeal to 0.025 s (case 6)",
        // A negative counts only when the run could have seen squeal (`no_squeal`); an
        // `unresolved` run decides nothing.
        reproduced: c6.and_then(|c| match &c.verdict {
            VerdictState::NoSqueal => Some(c.t_end >= c.tf * (1.0 - 1e-9)),
            VerdictState::Squeal => Some(false),
            VerdictState::Unresolved { .. } => None,
        }),
        evidence: c6.map_or("case 6 not run".into(), |c| {
            format!(
                "case 6: verdict {}, growth {:.4e} /s, t reached {:.4e} of {}. {}{}",
                verdict_text(&c.verdict),
                g(c),
                c.t_end,
                c.tf,
                cea_evidence(c, data),
                sweep
                    .and_then(|s| s.lowest_critical_mu)
                    .map_or(String::new(), |m| format!(
                        "; lowest critical μ of the base scene {m:.3}"
                    ))
            )
        }),
    });
    // (c)
    let c7 = by_case(cases, 7);
    out.push(Finding {
        id: "c",
        paper: "a longer TLOAD (case 7, 0.002 s) delays the onset of squeal against case 2 (0.0005 s)",
        reproduced: match (c2, c7) {
            (Some(a), Some(b)) => match (a.onset_s, b.onset_s) {
                (Some(x), Some(y)) => Some(y > x),
                (Some(_), None) => Some(b.squeal),
                _ if matches!(a.verdict, VerdictState::Unresolved { .. }) => None,
                _ => Some(false),
            },
            _ => None,
        },
        evidence: match (c2, c7) {
            (Some(a), Some(b)) => format!(
                "onset (the squealing root's fitted amplitude first above the study's level): case 2 {}, case 7 {} s; squeal {} / {}",
                opt(a.onset_s, 4),
                opt(b.onset_s, 4),
                a.squeal,
                b.squeal
            ),
            _ => "cases 2 and 7 not both run".into(),
        },
    });
    // (d)
    let (c1, c3) = (by_case(cases, 1), by_case(cases, 3));
    let d = match (c1, c2, c3) {
        (Some(a), Some(b), Some(c)) => {
            let read = |n: u32| column_of(data, n, resp_u).ok();
            let (ya, yb, yc) = (read(a.case), read(b.case), read(c.case));
            match (ya, yb, yc) {
                (Some(ya), Some(yb), Some(yc)) => {
                    let d1 = relative_difference(&ya, &yb);
                    let d3 = relative_difference(&yc, &yb);
                    Some((
                        d1.zip(d3).map(|(x, y)| x.max(y) < 0.1),
                        format!(
                            "max |u − u(case 2)| / max |u(case 2)| over the common span: case 1 {}, case 3 {}; NS {} / {} / {}",
                            opt(d1, 2),
                            opt(d3, 2),
                            a.steps,
                            b.steps,
                            c.steps
                        ),
                    ))
                }
                _ => Some((None, "histories unreadable".into())),
            }
        }
        _ => None,
    };
    out.push(Finding {
        id: "d",
        paper: "RTOL1 from 1e-5 to 1e-3 (cases 1–3) changes the response little (< 10 % here)",
        reproduced: d.as_ref().and_then(|x| x.0),
        evidence: d.map_or("cases 1–3 not all run".into(), |x| x.1),
    });
    out
}

/// Writes every output from the cases' rows and their in-memory `data` (any order); returns
/// the findings and the files written.
pub fn write(
    study: &StudySpec,
    cases: &[CaseResult],
    data: &[CaseData],
    dir: &RunDir,
    base: &Scene,
    sweep: Option<&SweepSummary>,
) -> Result<(Vec<Finding>, Vec<String>), PipelineError> {
    let mut files = vec!["cases.json".to_string(), "cases.md".into()];
    dir.write_json("cases.json", &cases)?;
    let tab = table(cases);
    dir.write_bytes("cases.md", tab.as_bytes())?;
    let fig_err = |path: &Path| {
        let path = path.to_path_buf();
        move |e: crate::figures::FigureError| PipelineError::Output {
            path,
            message: e.to_string(),
        }
    };
    // One pad DOF for every figure: the response of the first case run.
    let resp_v = cases
        .first()
        .map(|c| c.response.clone())
        .unwrap_or_default();
    let resp_u = displacement_of(&resp_v);
    let mut figs_md = String::new();
    for f in &study.figures {
        let present: Vec<&CaseResult> = f.cases.iter().filter_map(|n| by_case(cases, *n)).collect();
        if present.is_empty() {
            continue;
        }
        let mut fig = crate::figures::Figure::new(&f.title, "time (s)", format!("{resp_u} (in)"));
        let mut t_min_end = Real::INFINITY;
        for c in &present {
            let (t, y) = column_of(data, c.case, &resp_u)?;
            t_min_end = t_min_end.min(*t.last().unwrap_or(&0.0));
            let part = time_history(
                "",
                &t,
                &[(
                    format!(
                        "case {} (μ = {}, RTOL1 {:e}, TLOAD {})",
                        c.case, c.mu, c.rtol1, c.tload
                    ),
                    y,
                )],
                None,
            );
            fig.series.extend(part.series);
        }
        if let Some(last) = f.last {
            fig.x_range = Some(((t_min_end - last).max(0.0), t_min_end));
        }
        let stem = dir.path(&f.name);
        if write_figure(&fig, &stem).map_err(fig_err(&stem))?.is_none() {
            continue;
        }
        files.push(format!("{}.png", f.name));
        files.push(format!("{}.svg", f.name));
        let _ = writeln!(
            figs_md,
            "### {}\n\n![{}]({}.png)\n",
            f.title, f.name, f.name
        );
    }
    // Spectrum of the fastest-growing squealing response, after the load ramp.
    let mut spec_md = String::new();
    if let Some(c) = cases.iter().filter(|c| c.squeal).max_by(|a, b| {
        a.growth_rate_per_s
            .unwrap_or(0.0)
            .total_cmp(&b.growth_rate_per_s.unwrap_or(0.0))
    }) {
        let (t, v) = column_of(data, c.case, &c.response)?;
        let start = t.iter().position(|&s| s > c.tload).unwrap_or(0);
        let opts = SpectrumOptions {
            f_max_hz: Some(40_000.0),
            n_peaks: 6,
            ..Default::default()
        };
        let stem = dir.path("spectrum");
        let (mut fig, s) = spectrum(&t[start..], &v[start..], &opts).map_err(fig_err(&stem))?;
        fig.title = format!("Spectrum of {} (case {}), t > TLOAD", c.response, c.case);
        if write_figure(&fig, &stem).map_err(fig_err(&stem))?.is_some() {
            files.push("spectrum.png".into());
            files.push("spectrum.svg".into());
        }
        let f0 = s
            .peaks
            .iter()
            .map(|p| p.freq_hz)
            .fold(Real::INFINITY, Real::min);
        let _ = writeln!(
            spec_md,
            "### Spectrum of the squealing response (case {})\n\n![spectrum](spectrum.png)\n\n| peak (Hz) | amplitude | ratio to the lowest peak |\n|---|---|---|",
            c.case
        );
        for p in &s.peaks {
            let _ = writeln!(
                spec_md,
                "| {:.0} | {:.3e} | {:.2} |",
                p.freq_hz,
                p.amplitude,
                p.freq_hz / f0
            );
        }
        spec_md.push_str(
            "\nThe paper notes spectral peaks at multiples of the fundamental (a non-sinusoidal, \
             nonlinear response): ratios near integers above show them; peaks at non-integer \
             ratios are other modes.\n",
        );
    }
    let fnd = findings(cases, data, &resp_u, sweep);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# squeal reproduce: the paper's sample-brake study\n\nBase scene: {} ({}){}. Response DOF of the figures: `{resp_u}` (a pad grid; the verdict's response of case {}).\n\n{}## Table\n\n{tab}\nNS = accepted BDF steps; CPU = seconds in the integrator; a run that stops before TF ends at a step cap or a step-size collapse (see `status` in cases.json); its verdict uses the response up to there.\n\n## Findings of the paper\n",
        study.base.display(),
        base.title,
        if study.set.is_empty() {
            String::new()
        } else {
            format!(
                ", with {}",
                study
                    .set
                    .iter()
                    .map(|s| format!("`{s}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        },
        cases.first().map_or(0, |c| c.case),
        study
            .notes
            .as_ref()
            .map_or(String::new(), |n| format!("## The model\n\n{}\n\n", n.trim()))
    );
    for f in &fnd {
        let v = match f.reproduced {
            Some(true) => "**reproduced**",
            Some(false) => "**not reproduced**",
            None => "**not decided**",
        };
        let _ = writeln!(md, "- ({}) {} — {v}. {}", f.id, f.paper, f.evidence);
    }
    if let Some(s) = sweep {
        let _ = writeln!(md, "\n{}", s.markdown());
        if s.error.is_none() {
            files.push("cea_sweep/".into());
        }
    }
    let _ = writeln!(md, "\n## Figures\n\n{figs_md}{spec_md}");
    dir.write_bytes("report.md", md.as_bytes())?;
    files.push("report.md".into());
    Ok((fnd, files))
}
