//! `squeal accuracy`: the work–precision study of a scene's transient (issue 7).
//!
//! The scene's transient is run at a ladder of tolerances (BDF, RTOL1 × MAXORD) and of fixed
//! steps (generalized-α), every run sampled on one common time grid (each integrator
//! interpolates its own solution there), and compared with a reference run at a much tighter
//! tolerance: error of the velocities of the chosen DOFs (max and RMS over time, relative),
//! growth rate and frequency of the response and their errors, steps, Newton iterations,
//! factorisations, CPU seconds. Outputs: `accuracy.json` (one object per run),
//! `accuracy.md` (table), `work_precision.{png,svg}` (error against CPU, log–log).
//!
//! - the `[accuracy]` table: [`crate::scene::AccuracySpec`].
//! - [`drive`]: one run with either integrator, sampled on the grid, nothing written.
//! - [`compare`]: errors against the reference.
//! - [`models`]: small stored-matrix models (belt, 2-DOF coupling, pad row).

pub mod compare;
pub mod drive;
pub mod models;

pub use crate::scene::AccuracySpec;
pub use drive::{initial_state, integrate, Method, RunOutcome};

use crate::error::PipelineError;
use crate::model;
use crate::output::RunDir;
use crate::problem::system;
use crate::progress::Progress;
use crate::scene::Scene;
use compare::RunErrors;
use serde::Serialize;

use squeal_solver::Real;

/// One row of `accuracy.json`.
#[derive(Debug, Clone, Serialize)]
pub struct AccuracyRun {
    /// `reference` or `ladder`.
    pub role: &'static str,
    /// `bdf` or `generalized_alpha`.
    pub integrator: &'static str,
    /// RTOL1 (BDF; adaptive generalized-α).
    pub rtol: Option<Real>,
    /// MAXORD (BDF).
    pub max_order: Option<usize>,
    /// Fixed step (generalized-α).
    pub h: Option<Real>,
    /// ρ∞ (generalized-α).
    pub rho_inf: Option<Real>,
    #[serde(flatten)]
    pub errors: RunErrors,
    pub steps: u64,
    pub newton_iterations: u64,
    pub factorisations: u64,
    pub rejected_steps: u64,
    /// Mean seconds inside the integrator per run.
    pub cpu_s: Real,
    /// Repetitions behind `cpu_s`.
    pub repeats: usize,
    pub max_constraint_drift: Real,
    pub status: squeal_solver::bdf::Status,
}

/// `summary.json` of `squeal accuracy`.
#[derive(Debug, Clone, Serialize)]
pub struct AccuracyReport {
    pub verb: &'static str,
    pub version: &'static str,
    pub n_dofs: usize,
    pub n_gaps: usize,
    pub tfinal: Real,
    pub samples: usize,
    /// Reduced DOF indices compared, and the response column's DOF.
    pub dofs: Vec<usize>,
    pub response_dof: usize,
    pub reference_growth_rate: Option<Real>,
    pub reference_frequency_hz: Option<Real>,
    pub runs: Vec<AccuracyRun>,
    pub wall_s: Real,
}

fn row(role: &'static str, r: &RunOutcome, errors: RunErrors, repeats: usize) -> AccuracyRun {
    let (integrator, rtol, max_order, h, rho) = match r.method {
        Method::Bdf { rtol, max_order } => ("bdf", Some(rtol), Some(max_order), None, None),
        Method::GeneralizedAlpha { h, rtol, rho_inf } => (
            "generalized_alpha",
            h.is_none().then_some(rtol),
            None,
            h,
            Some(rho_inf),
        ),
    };
    AccuracyRun {
        role,
        integrator,
        rtol,
        max_order,
        h,
        rho_inf: rho,
        errors,
        steps: r.steps,
        newton_iterations: r.newton_iterations,
        factorisations: r.factorisations,
        rejected_steps: r.rejected_steps,
        cpu_s: r.cpu_s,
        repeats,
        max_constraint_drift: r.max_constraint_drift,
        status: r.status.clone(),
    }
}

/// Runs the study and writes its outputs into `dir`: [`compute`], then [`write`].
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
) -> Result<AccuracyReport, PipelineError> {
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let report = compute(scene, dir, progress)?;
    write(&report, dir, progress)?;
    Ok(report)
}

/// The study in memory: the reference, the ladder of integrators and their errors (gmsh's
/// files, when the model is meshed, go into `work`).
pub fn compute(
    scene: &Scene,
    work: &RunDir,
    progress: &Progress,
) -> Result<AccuracyReport, PipelineError> {
    let wall = std::time::Instant::now();
    let spec = scene.transient.clone().unwrap_or_default();
    let acc = scene.accuracy.clone().unwrap_or_default();
    let model = model::build(scene, work, progress)?;
    let problem = system::problem(scene, &model)?;
    let n = model.n();
    let dofs: Vec<usize> = if acc.dofs.is_empty() {
        (0..n).collect()
    } else {
        if let Some(&d) = acc.dofs.iter().find(|&&d| d >= n) {
            return Err(PipelineError::Scene {
                field: "accuracy.dofs".into(),
                message: format!("DOF {d} is out of range (the model has {n})"),
            });
        }
        acc.dofs.clone()
    };
    let (y0, yp0) = initial_state(&problem, spec.tolint)?;
    let grid: Vec<Real> = (0..acc.samples)
        .map(|k| spec.tfinal * k as Real / (acc.samples - 1) as Real)
        .collect();
    let t_after = problem.load.t_load;
    let go = |m: Method| -> Result<(RunOutcome, usize), PipelineError> {
        let mut reps = 0;
        let mut total = 0.0;
        loop {
            let r = integrate(&problem, &spec, m, &y0, &yp0, &grid, &dofs, false)?;
            reps += 1;
            total += r.cpu_s;
            if total >= acc.min_cpu_s || reps >= 20 {
                let mut r = r;
                r.cpu_s = total / reps as Real;
                return Ok((r, reps));
            }
        }
    };
    progress.info(format!(
        "reference: BDF, RTOL1 = {:e}, MAXORD 2",
        acc.reference_rtol
    ));
    let (reference, ref_reps) = go(Method::Bdf {
        rtol: acc.reference_rtol,
        max_order: 2,
    })?;
    if !reference.reached {
        progress.info(format!(
            "the reference run stopped early: {:?}; errors are not available",
            reference.status
        ));
    }
    let col = compare::response_column(&reference, t_after);
    let (g_ref, f_ref) = compare::growth_and_frequency(&reference, col, t_after);
    let mut runs = vec![row(
        "reference",
        &reference,
        compare::compare(&reference, &reference, col, t_after),
        ref_reps,
    )];
    let mut bdf2_steps = Vec::new();
    for &max_order in &acc.max_orders {
        for &rtol in &acc.rtols {
            let (r, reps) = go(Method::Bdf { rtol, max_order })?;
            progress.info(format!(
                "BDF rtol {rtol:e} maxord {max_order}: {} steps, {:.3e} s, {:?}",
                r.steps, r.cpu_s, r.status
            ));
            if max_order == 2 && r.reached && r.steps > 0 {
                bdf2_steps.push(spec.tfinal / r.steps as Real);
            }
            let e = compare::compare(&r, &reference, col, t_after);
            runs.push(row("ladder", &r, e, reps));
        }
    }
    let steps = acc.galpha_steps.clone().unwrap_or(bdf2_steps);
    for h in steps {
        let (r, reps) = go(Method::GeneralizedAlpha {
            h: Some(h),
            rtol: spec.rtol1,
            rho_inf: acc.rho_inf,
        })?;
        progress.info(format!(
            "generalized-alpha h {h:e}: {} steps, {:.3e} s, {:?}",
            r.steps, r.cpu_s, r.status
        ));
        let e = compare::compare(&r, &reference, col, t_after);
        runs.push(row("ladder", &r, e, reps));
    }
    let report = AccuracyReport {
        verb: "accuracy",
        version: crate::VERSION,
        n_dofs: n,
        n_gaps: model.gap_geometry.len(),
        tfinal: spec.tfinal,
        samples: acc.samples,
        response_dof: dofs.get(col).copied().unwrap_or(0),
        dofs,
        reference_growth_rate: g_ref,
        reference_frequency_hz: f_ref,
        runs,
        wall_s: wall.elapsed().as_secs_f64(),
    };
    Ok(report)
}

/// Writes `accuracy.json`, `accuracy.md`, the work–precision figure and `summary.json`.
pub fn write(
    report: &AccuracyReport,
    dir: &RunDir,
    progress: &Progress,
) -> Result<(), PipelineError> {
    let runs = &report.runs;
    dir.write_json("accuracy.json", runs)?;
    dir.write_bytes("accuracy.md", markdown(runs).as_bytes())?;
    let mut series: Vec<(String, Vec<(Real, Real)>)> = Vec::new();
    for r in runs.iter().filter(|r| r.role == "ladder") {
        let label = match r.max_order {
            Some(o) => format!("BDF, MAXORD {o}"),
            None => format!("generalized-α, ρ∞ = {}", r.rho_inf.unwrap_or(0.0)),
        };
        if let (Some(e), true) = (r.errors.error, r.cpu_s > 0.0) {
            if e > 0.0 {
                match series.iter_mut().find(|s| s.0 == label) {
                    Some(s) => s.1.push((r.cpu_s, e)),
                    None => series.push((label, vec![(r.cpu_s, e)])),
                }
            }
        }
    }
    if !series.is_empty() {
        let fig = crate::figures::work_precision(&series);
        if let Err(e) = crate::figures::write_figure(&fig, &dir.path("work_precision")) {
            progress.info(format!("work–precision figure not written: {e}"));
        }
    }
    dir.write_json("summary.json", report)?;
    Ok(())
}

/// The runs as a Markdown table.
pub fn markdown(runs: &[AccuracyRun]) -> String {
    let o = |x: Option<Real>| x.map_or("–".to_string(), |v| format!("{v:.2e}"));
    let mut s = String::from(
        "| integrator | rtol | maxord | h | error (max) | error (RMS) | σ | σ error | f (Hz) | f error | steps | Newton | factorisations | cpu_s | status |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in runs {
        s.push_str(&format!(
            "| {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3e} | {} |\n",
            r.integrator,
            if r.role == "reference" {
                " (reference)"
            } else {
                ""
            },
            o(r.rtol),
            r.max_order.map_or("–".into(), |m| m.to_string()),
            o(r.h),
            o(r.errors.error),
            o(r.errors.error_rms),
            r.errors
                .growth_rate
                .map_or("–".into(), |v| format!("{v:.5}")),
            o(r.errors.growth_rate_error),
            r.errors
                .frequency_hz
                .map_or("–".into(), |v| format!("{v:.5}")),
            o(r.errors.frequency_error),
            r.steps,
            r.newton_iterations,
            r.factorisations,
            r.cpu_s,
            if r.status.is_success() {
                "reached".to_string()
            } else {
                format!("{:?}", r.status)
            },
        ));
    }
    s
}
