//! Cost of one transient step and where it goes (issue 13, item 3, the transient parts).
//!
//! Cases (each a BDF2 run from the steady sliding state, energy balance kept as
//! `squeal transient` keeps it, no files written):
//! - `study_case2_rtol1e-4`: the study brake (`examples/sample-brake/base.toml` = paper case 2 of
//!   `study.toml`: 244 reduced DOFs, 20 gaps, μ = 0.7 − 0.0005 V, TLOAD 5e-4, TF 6e-3) at the
//!   paper's tolerances (RTOL1 = ATOL1 = 1e-4) under the band step bound, as `reproduce` runs it,
//!   with the paper's rigid contact (any `normal_stiffness` of the scene is removed, so that the
//!   run stays the one of `docs/bench/transient_step_before.json`);
//! - `study_case2_compliant_rtol1e-4`: the same with a compliant contact, `normal_stiffness =
//!   1e6` psi/in on both pairs (set here, whatever the scene file says);
//! - `study_case2_rtol1e-8`: the same at RTOL1 = 1e-8 (ATOL1 scaled), no step bound (the
//!   work–precision table's run);
//! - `hex20_case2`: the hex20 brake (`examples/transient/sample-brake-case2.toml`, the
//!   components of `components.toml`: 2153 reduced DOFs, 234 gaps) at the paper's tolerances,
//!   the first `HEX20_STEPS` steps.
//!
//! For each: CPU seconds of the run, all threads of the process (`/proc/self/task/*/schedstat`,
//! so that other load on the machine does not count and the rayon threads of the block
//! factorisation do; wall seconds too), split into the integrator and the per-step
//! bookkeeping (energy terms, in the proportion the driver's wall clocks give), µs per step,
//! steps, Newton iterations, residual evaluations, iteration-matrix set-ups; then the cost of
//! each operation alone on the same system at the start state (a residual, a factorisation of
//! the iteration matrix, a Newton solve, one energy observation), and the time those
//! operations account for (cost × count).
//! Each case runs three times: with the structure used (the default: the Craig–Bampton modal
//! block eliminated before the LU, `BsqlSystem::set_modal_elimination`, and the saddle matrix
//! factorised by component blocks, `BsqlSystem::set_component_blocks`), with the elimination
//! alone (`no_blocks`: the path before the blocks) and with the whole system factorised
//! (`dense`: the path before the elimination), all in the same binary, with the largest
//! relative difference of the final velocities (`moved_vs_no_blocks`, `moved_vs_dense`).
//! The final state is written to `target/bench/transient_step_<case>.final.json`; when such a
//! file exists from an earlier run, the largest relative difference of the final velocities to
//! it is reported (how far a change moved the results).
//!
//! ```text
//! cargo build --release -p squeal-pipeline --example bench_step
//! target/release/examples/bench_step [--quick] [out.json]   # default docs/bench/transient_step.json
//! ```
//! Run from the repository root, with gmsh on PATH (the hex20 model is meshed and reduced once,
//! then read from the model cache `target/bench/cache`). `--quick` skips the hex20 brake (its
//! row in the output file, if there is one, is kept, marked `from_earlier_run`).

use serde::Serialize;
use squeal_pipeline::stages::model::{self, cache::ModelCache};
use squeal_pipeline::stages::transient::driver::{drive, DriveOptions};
use squeal_pipeline::stages::transient::stepper::{IntegratorStats, Stepper};
use squeal_pipeline::stages::transient::{prepare, start_state};
use squeal_pipeline::{progress::Progress, RunDir, Scene};
use squeal_solver::bdf::DaeSystem;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Steps of the hex20 run (about 32 ms of CPU each before the sparse products).
const HEX20_STEPS: usize = 300;

#[derive(Serialize)]
struct OpCosts {
    /// One residual F(t, y, y'), µs.
    residual_us: f64,
    /// One set-up (assembly + factorisation) of the iteration matrix, µs.
    setup_us: f64,
    /// One Newton solve with the factorised matrix, µs.
    solve_us: f64,
    /// One energy observation (`BsqlSystem::observe`), µs.
    observe_us: f64,
    /// For comparison: M v' + B v + K u as three dense matrix–vector products (faer), µs.
    dense_mbk_products_us: f64,
}

#[derive(Serialize)]
struct Breakdown {
    residuals_s: f64,
    setups_s: f64,
    solves_s: f64,
    observe_s: f64,
    /// Integrator seconds not accounted for by residuals, set-ups and solves (predictor,
    /// error test, step control, copies).
    integrator_other_s: f64,
}

/// The same case by another path: the whole saddle system factorised (no modal elimination),
/// or the modal elimination without the component blocks.
#[derive(Serialize)]
struct DenseRun {
    steps: u64,
    newton_iterations: u64,
    jacobian_setups: u64,
    run_cpu_s: f64,
    us_per_step: f64,
    integrator_us_per_step: f64,
    setup_us: f64,
    solve_us: f64,
    energy_balance_rel: f64,
}

impl DenseRun {
    /// A run's counts and costs, with the set-up and one solve timed apart.
    fn of(run: &RunOut, setup_us: f64, solve_us: f64) -> Self {
        let steps = run.stats.steps.max(1) as f64;
        DenseRun {
            steps: run.stats.steps,
            newton_iterations: run.stats.newton_iterations,
            jacobian_setups: run.stats.jacobian_setups,
            run_cpu_s: run.run_cpu_s,
            us_per_step: 1e6 * run.run_cpu_s / steps,
            integrator_us_per_step: 1e6 * (run.run_cpu_s - run.bookkeeping_s) / steps,
            setup_us,
            solve_us,
            energy_balance_rel: run.energy_balance_rel,
        }
    }
}

#[derive(Serialize)]
struct Row {
    case: String,
    n_dofs: usize,
    n_gaps: usize,
    /// `normal_stiffness` of both pairs (None: rigid contact).
    normal_stiffness: Option<f64>,
    /// DOFs of the diagonal (modal) block found by pattern on a fresh system (the first
    /// set-up keeps those the friction tangents touch), their coupling groups, and the
    /// multiply–adds of one Schur-complement update.
    eliminated_dofs: usize,
    modal_groups: usize,
    schur_madds: usize,
    /// The run's `BsqlStats::modal_redetections` (friction touched the block: found again).
    modal_redetections: u64,
    /// Factorisations with C_f because a contact was near sticking (`BsqlStats`).
    near_stick_factorisations: u64,
    /// Whether the products with M, B, K (residual, energy forms) and with K (Newton solve)
    /// read the upper triangles only (`BsqlSystem::symmetric_products`: the matrices are
    /// symmetric to round-off).
    symmetric_products: (bool, bool),
    /// Stored entries of M, B, K (union pattern), K, G over n², n², ng·n.
    density_mbk: f64,
    density_k: f64,
    density_g: f64,
    rtol1: f64,
    h_max: Option<f64>,
    t_end: f64,
    status: String,
    steps: u64,
    newton_iterations: u64,
    residual_evals: u64,
    jacobian_setups: u64,
    error_test_failures: u64,
    convergence_failures: u64,
    /// Wall seconds of the whole run (integrator + bookkeeping).
    wall_s: f64,
    /// CPU seconds of the whole run, all threads of the process (the machine's other load
    /// excluded; the block factorisation runs its blocks on rayon's threads).
    run_cpu_s: f64,
    /// The integrator alone: run CPU × (wall − bookkeeping) / wall.
    integrator_s: f64,
    /// Energy bookkeeping: run CPU × (the driver's wall `bookkeeping_s`) / wall.
    bookkeeping_s: f64,
    /// The integrator's own `cpu_s` counter.
    cpu_s: f64,
    us_per_step: f64,
    integrator_us_per_step: f64,
    bookkeeping_us_per_step: f64,
    steps_per_s: f64,
    ops: OpCosts,
    breakdown: Breakdown,
    /// Energy-balance residual / scale at the end.
    energy_balance_rel: f64,
    /// max_i |v_i − v_i,prev| / max_i |v_i,prev| against the previous run's final state (at
    /// TFINAL, or at the last step of a run stopped by its step cap; None: no previous file).
    moved_vs_previous: Option<f64>,
    /// Component blocks of the saddle matrix on a fresh system (`component_block_sizes`: the
    /// blocks' sizes, then the border's; None: one LU of the whole), and the run's set-ups
    /// that fell back to the whole LU (`BsqlStats::block_fallbacks`).
    component_blocks: Option<(Vec<usize>, usize)>,
    block_fallbacks: u64,
    /// The modal elimination without the component blocks (`set_component_blocks(false)`:
    /// the path before the blocks), same binary.
    no_blocks: DenseRun,
    /// max_i |v_i − v_i,no_blocks| / max_i |v_i,no_blocks| of the final states.
    moved_vs_no_blocks: f64,
    /// The whole system factorised, same binary.
    dense: DenseRun,
    /// One Newton solve (δv) at the start state, by the structured path against the whole LU,
    /// max |Δ| / max |δv_dense|.
    one_solve_vs_dense: f64,
    /// max_i |v_i − v_i,dense| / max_i |v_i,dense| of the final states (at TFINAL or the cap).
    moved_vs_dense: f64,
}

/// What one run of a case gives.
struct RunOut {
    stats: squeal_solver::bdf::BdfStats,
    bsql: squeal_solver::bsql::BsqlStats,
    run_cpu_s: f64,
    wall_s: f64,
    bookkeeping_s: f64,
    energy_balance_rel: f64,
    status: String,
    t: f64,
    y: Vec<f64>,
}

/// One BDF run of the prepared case from its start state, with or without the modal
/// elimination.
fn run_once(
    prepared: &squeal_pipeline::stages::transient::Prepared,
    start: &squeal_pipeline::stages::transient::StartState,
    case: &str,
    eliminate: bool,
    blocks: bool,
) -> Result<RunOut, Box<dyn std::error::Error>> {
    let spec = &prepared.spec;
    let method = squeal_pipeline::stages::transient::stepper::Method::Bdf {
        rtol: spec.rtol1,
        max_order: spec.maxord,
    };
    let mut stepper = Stepper::new(
        &prepared.problem,
        spec,
        method,
        0.0,
        &start.y0,
        &start.yp0,
        spec.tfinal,
    )?;
    if let Stepper::Bdf { sys, .. } = &mut stepper {
        sys.set_component_blocks(blocks);
        sys.set_modal_elimination(eliminate);
    }
    let clock = Instant::now();
    let cpu0 = thread_cpu_s(&clock);
    let out = drive(
        &mut stepper,
        &mut [],
        &DriveOptions {
            tfinal: spec.tfinal,
            max_steps: spec.max_steps,
            energy: true,
            label: case.into(),
        },
        &Progress::quiet(),
    )?;
    let wall_s = clock.elapsed().as_secs_f64();
    let run_cpu_s = thread_cpu_s(&clock) - cpu0;
    let (stats, bsql) = match stepper.stats() {
        IntegratorStats::Bdf { bdf, bsql, .. } => (bdf, bsql),
        _ => unreachable!("BDF run"),
    };
    let balance = out.energy.as_ref().expect("energy kept");
    Ok(RunOut {
        stats,
        bsql,
        run_cpu_s,
        wall_s,
        bookkeeping_s: out.bookkeeping_s * run_cpu_s / wall_s.max(f64::MIN_POSITIVE),
        energy_balance_rel: balance.residual() / balance.scale().max(f64::MIN_POSITIVE),
        status: format!("{:?}", out.status),
        t: stepper.t(),
        y: stepper.y().to_vec(),
    })
}

/// max_i |a_i − b_i| / max_i |b_i| over the first n entries (the velocities).
fn moved(a: &[f64], b: &[f64], n: usize) -> f64 {
    let scale = b[..n].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let d = a[..n]
        .iter()
        .zip(&b[..n])
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    d / scale.max(f64::MIN_POSITIVE)
}

/// CPU seconds of all threads of this process (the sum of `/proc/self/task/*/schedstat`,
/// Linux): time the process's threads ran, whatever else loads the machine; the rayon threads
/// of the block factorisation count. Falls back to wall time elsewhere.
fn thread_cpu_s(wall: &Instant) -> f64 {
    let tasks = match std::fs::read_dir("/proc/self/task") {
        Ok(t) => t,
        Err(_) => return wall.elapsed().as_secs_f64(),
    };
    let mut ns = 0u64;
    for task in tasks.flatten() {
        ns += std::fs::read_to_string(task.path().join("schedstat"))
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<u64>().ok())
            .unwrap_or(0);
    }
    1e-9 * ns as f64
}

/// Microseconds of process CPU time per call of `f` (repeated for at least `min_s`).
fn per_call_us(min_s: f64, mut f: impl FnMut()) -> f64 {
    f();
    let wall = Instant::now();
    let start = thread_cpu_s(&wall);
    let mut reps = 0u64;
    while wall.elapsed().as_secs_f64() < min_s {
        f();
        reps += 1;
    }
    1e6 * (thread_cpu_s(&wall) - start) / reps.max(1) as f64
}

#[derive(Serialize, serde::Deserialize)]
struct FinalState {
    t: f64,
    steps: u64,
    y: Vec<f64>,
}

fn run_case(
    case: &str,
    scene_path: &Path,
    sets: &[&str],
    normal_stiffness: Option<f64>,
    cache: &ModelCache,
    work: &Path,
) -> Result<Row, Box<dyn std::error::Error>> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let mut scene = Scene::load(scene_path, &sets)?;
    for pair in &mut scene.contact {
        pair.normal_stiffness = normal_stiffness;
    }
    scene.validate()?;
    let run_dir = RunDir::create(&work.join(case))?;
    let (model, _) = model::build_cached(&scene, &run_dir, &Progress::quiet(), Some(cache))?;
    let prepared = prepare(&scene, &model)?;
    let spec = prepared.spec.clone();
    let problem = &prepared.problem;
    let start = start_state(problem, spec.tolint)?;
    let (n, ng) = (model.n(), model.gap_geometry.len());
    let run = run_once(&prepared, &start, case, true, true)?;
    let no_blocks_run = run_once(&prepared, &start, case, true, false)?;
    let dense_run = run_once(&prepared, &start, case, false, false)?;
    let (wall_s, run_cpu_s) = (run.wall_s, run.run_cpu_s);
    let bdf = run.stats.clone();
    // Cost of each operation alone, on a fresh system at the start state (with the
    // elimination, then without).
    let mut sys = problem.system(problem.gaps.clone())?;
    let (eliminated_dofs, modal_groups, schur_madds) = sys.modal_elimination();
    let component_blocks = sys.component_block_sizes();
    let (y, yp) = (start.y0.clone(), start.yp0.clone());
    let mut res = vec![0.0; y.len()];
    let t = 0.5 * spec.tfinal;
    let min_s = if n > 1000 { 1.0 } else { 0.3 };
    let residual_us = per_call_us(min_s, || sys.residual(t, &y, &yp, &mut res).unwrap());
    let cj = 2.0 / spec.h_max.unwrap_or(1e-6).max(1e-7) * 0.75;
    let mut b = vec![0.0; y.len()];
    let mut setup_solve = |sys: &mut squeal_solver::bsql::BsqlSystem<_>| {
        let setup_us = per_call_us(min_s, || sys.setup_jacobian(t, &y, &yp, cj).unwrap());
        let solve_us = per_call_us(min_s, || {
            b.copy_from_slice(&res);
            sys.solve_jacobian(&mut b).unwrap()
        });
        (setup_us, solve_us, b.clone())
    };
    let (setup_us, solve_us, x_struct) = setup_solve(&mut sys);
    sys.set_component_blocks(false);
    let (no_blocks_setup_us, no_blocks_solve_us, _) = setup_solve(&mut sys);
    sys.set_modal_elimination(false);
    let (dense_setup_us, dense_solve_us, x_dense) = setup_solve(&mut sys);
    // One Newton solve at the start state, the structured path against the whole LU: the
    // round-off of the two factorisations of the same matrix.
    let one_solve_vs_dense = moved(&x_struct, &x_dense, n);
    sys.set_component_blocks(true);
    sys.set_modal_elimination(true);
    let observe_us = per_call_us(min_s, || {
        sys.observe(t, &y, &yp).unwrap();
    });
    let dense_mbk_products_us = {
        use faer::linalg::matmul::matmul;
        use faer::{Accum, MatMut, MatRef, Par};
        let col = |x: &[f64]| MatRef::from_column_major_slice(x, x.len(), 1).to_owned();
        let (v, vp, u) = (col(&y[..n]), col(&yp[..n]), col(&y[n + ng..]));
        let mut r = vec![0.0; n];
        per_call_us(min_s, || {
            let mut rr = MatMut::from_column_major_slice_mut(&mut r, n, 1);
            matmul(
                rr.as_mut(),
                Accum::Replace,
                problem.m.as_ref(),
                vp.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(
                rr.as_mut(),
                Accum::Add,
                problem.b.as_ref(),
                v.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(
                rr.as_mut(),
                Accum::Add,
                problem.k.as_ref(),
                u.as_ref(),
                1.0,
                Par::Seq,
            );
        })
    };
    let (nnz_mbk, nnz_k, nnz_g) = sys.product_nnz();
    let mut runs = 0usize;
    for i in 0..n {
        let mut prev = false;
        for j in 0..n {
            let nz =
                problem.m[(i, j)] != 0.0 || problem.b[(i, j)] != 0.0 || problem.k[(i, j)] != 0.0;
            if nz && !prev {
                runs += 1;
            }
            prev = nz;
        }
    }
    println!(
        "  union pattern: {nnz_mbk} entries in {runs} contiguous runs (mean {:.1})",
        nnz_mbk as f64 / runs.max(1) as f64
    );
    let steps = bdf.steps;
    let bookkeeping_s = run.bookkeeping_s;
    let integrator_s = run_cpu_s - bookkeeping_s;
    let residuals_s = 1e-6 * residual_us * bdf.residual_evals as f64;
    let setups_s = 1e-6 * setup_us * bdf.jacobian_setups as f64;
    let solves_s = 1e-6 * solve_us * bdf.newton_iterations as f64;
    let energy_balance_rel = run.energy_balance_rel;
    // How far the results moved against the previous run of this benchmark.
    let final_path = PathBuf::from(format!("target/bench/transient_step_{case}.final.json"));
    let now = FinalState {
        t: run.t,
        steps,
        y: run.y.clone(),
    };
    let moved_vs_previous = std::fs::read_to_string(&final_path)
        .ok()
        .and_then(|s| serde_json::from_str::<FinalState>(&s).ok())
        .filter(|p| p.y.len() == now.y.len())
        .map(|p| moved(&now.y, &p.y, n));
    if let Some(dir) = final_path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(&final_path, serde_json::to_string(&now)?)?;
    let row = Row {
        case: case.into(),
        n_dofs: n,
        n_gaps: ng,
        normal_stiffness,
        eliminated_dofs,
        modal_groups,
        schur_madds,
        modal_redetections: run.bsql.modal_redetections,
        near_stick_factorisations: run.bsql.near_stick_factorisations,
        symmetric_products: sys.symmetric_products(),
        density_mbk: nnz_mbk as f64 / (n * n) as f64,
        density_k: nnz_k as f64 / (n * n) as f64,
        density_g: nnz_g as f64 / (n * ng).max(1) as f64,
        rtol1: spec.rtol1,
        h_max: spec.h_max,
        t_end: run.t,
        status: run.status.clone(),
        steps,
        newton_iterations: bdf.newton_iterations,
        residual_evals: bdf.residual_evals,
        jacobian_setups: bdf.jacobian_setups,
        error_test_failures: bdf.error_test_failures,
        convergence_failures: bdf.convergence_failures,
        wall_s,
        run_cpu_s,
        integrator_s,
        bookkeeping_s,
        cpu_s: bdf.cpu_s,
        us_per_step: 1e6 * run_cpu_s / steps.max(1) as f64,
        integrator_us_per_step: 1e6 * integrator_s / steps.max(1) as f64,
        bookkeeping_us_per_step: 1e6 * bookkeeping_s / steps.max(1) as f64,
        steps_per_s: steps as f64 / run_cpu_s,
        ops: OpCosts {
            residual_us,
            setup_us,
            solve_us,
            observe_us,
            dense_mbk_products_us,
        },
        breakdown: Breakdown {
            residuals_s,
            setups_s,
            solves_s,
            observe_s: 1e-6 * observe_us * (steps + 1) as f64,
            integrator_other_s: integrator_s - residuals_s - setups_s - solves_s,
        },
        energy_balance_rel,
        moved_vs_previous,
        component_blocks: component_blocks.clone(),
        block_fallbacks: run.bsql.block_fallbacks,
        no_blocks: DenseRun::of(&no_blocks_run, no_blocks_setup_us, no_blocks_solve_us),
        moved_vs_no_blocks: moved(&run.y, &no_blocks_run.y, n),
        dense: DenseRun::of(&dense_run, dense_setup_us, dense_solve_us),
        moved_vs_dense: moved(&run.y, &dense_run.y, n),
        one_solve_vs_dense,
    };
    println!(
        "{case:<22} n = {n}, ng = {ng}: {steps} steps, {} Newton, {} set-ups, {:.1} us/step \
         (integrator {:.1}, bookkeeping {:.1}); residual {:.1} us, set-up {:.1} us, solve {:.1} \
         us, observe {:.1} us (dense M,B,K products {:.1} us; density {:.3}); moved {:?}\n  \
         eliminated {eliminated_dofs} DOFs in {modal_groups} groups ({} re-detections, {} near-stick \
         set-ups); component blocks {:?} ({} fall-backs); without the blocks: {} steps, {:.1} \
         us/step, set-up {:.1} us, solve {:.1} us, moved {:.2e}; whole system factorised: \
         {} steps, {} set-ups, {:.1} us/step, set-up {:.1} us, solve {:.1} us; moved vs dense {:.2e} (one solve {:.2e})",
        row.newton_iterations,
        row.jacobian_setups,
        row.us_per_step,
        row.integrator_us_per_step,
        row.bookkeeping_us_per_step,
        residual_us,
        setup_us,
        solve_us,
        observe_us,
        dense_mbk_products_us,
        row.density_mbk,
        row.moved_vs_previous,
        row.modal_redetections,
        row.near_stick_factorisations,
        component_blocks,
        row.block_fallbacks,
        row.no_blocks.steps,
        row.no_blocks.us_per_step,
        no_blocks_setup_us,
        no_blocks_solve_us,
        row.moved_vs_no_blocks,
        row.dense.steps,
        row.dense.jacobian_setups,
        row.dense.us_per_step,
        dense_setup_us,
        dense_solve_us,
        row.moved_vs_dense,
        row.one_solve_vs_dense
    );
    Ok(row)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let out = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .cloned()
        .unwrap_or_else(|| "docs/bench/transient_step.json".into());
    let work = std::env::temp_dir().join(format!("squeal-bench-step-{}", std::process::id()));
    let cache = ModelCache::new("target/bench/cache");
    let study = Path::new("examples/sample-brake/base.toml");
    let mut rows = vec![
        run_case(
            "study_case2_rtol1e-4",
            study,
            &["transient.tfinal=0.006", "transient.nrstrt=0"],
            None,
            &cache,
            &work,
        )?,
        run_case(
            "study_case2_compliant_rtol1e-4",
            study,
            &["transient.tfinal=0.006", "transient.nrstrt=0"],
            Some(1.0e6),
            &cache,
            &work,
        )?,
        run_case(
            "study_case2_rtol1e-8",
            study,
            &[
                "transient.tfinal=0.006",
                "transient.nrstrt=0",
                "transient.rtol1=1e-8",
                "transient.atol1=1e-8",
                "transient.band_step_bound=false",
            ],
            None,
            &cache,
            &work,
        )?,
    ];
    if !quick {
        let steps = format!("transient.max_steps={HEX20_STEPS}");
        rows.push(run_case(
            "hex20_case2",
            Path::new("examples/transient/sample-brake-case2.toml"),
            &["transient.nrstrt=0", &steps],
            None,
            &cache,
            &work,
        )?);
    }
    let _ = std::fs::remove_dir_all(&work);
    let out = PathBuf::from(out);
    if let Some(p) = out.parent() {
        std::fs::create_dir_all(p)?;
    }
    let mut json: Vec<serde_json::Value> = rows
        .iter()
        .map(serde_json::to_value)
        .collect::<Result<_, _>>()?;
    if quick {
        // The rows of the cases `--quick` skips (the hex20 brake) stay from the file it
        // overwrites, marked `from_earlier_run`.
        let old = std::fs::read_to_string(&out)
            .ok()
            .and_then(|s| serde_json::from_str::<Vec<serde_json::Value>>(&s).ok())
            .unwrap_or_default();
        for mut r in old {
            let case = r.get("case").cloned();
            if r.is_object() && !json.iter().any(|n| n.get("case") == case.as_ref()) {
                r["from_earlier_run"] = true.into();
                json.push(r);
            }
        }
    }
    std::fs::write(&out, serde_json::to_string_pretty(&json)?)?;
    println!("wrote {}", out.display());
    Ok(())
}
