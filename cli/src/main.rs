//! The `squeal` command: `squeal <verb> SCENE.toml [--out DIR] [--set key=value ...]`.
//!
//! Argument parsing, progress bars and exit codes over the `squeal-pipeline` library; every
//! verb is one library call.

mod bars;

use anyhow::Result;
use clap::{Args, Parser, Subcommand};
use squeal_pipeline::progress::Progress;
use squeal_pipeline::{stages, RunDir, Scene};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

#[derive(Parser)]
#[command(
    name = "squeal",
    version,
    about = "Disc-brake squeal simulator (BSQL method, open front end)"
)]
struct Cli {
    /// Print no progress.
    #[arg(short, long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    verb: Verb,
}

#[derive(Args)]
struct SceneArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Override a scene value: dotted.key=value (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

#[derive(Args)]
struct RunArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output folder (default: out/<scene file stem>).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// The model cache: `--cache DIR`, else the environment variable `SQUEAL_CACHE`.
#[derive(Args)]
struct CacheArgs {
    /// Read/store reduced models in this cache folder, keyed by the scene values that
    /// determine them (default: $SQUEAL_CACHE; unset = no cache).
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
}

impl CacheArgs {
    fn dir(&self) -> Option<PathBuf> {
        self.cache.clone().or_else(|| {
            std::env::var_os("SQUEAL_CACHE")
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
        })
    }
}

#[derive(Subcommand)]
enum Verb {
    /// Validate a scene and print it resolved (every default filled in).
    Check(SceneArgs),
    /// Mesh every component (gmsh) and write the meshes as .msh and .vtu.
    Mesh(RunArgs),
    /// Modal analysis of one component: modes.json and modes.vtu.
    Modes {
        #[command(flatten)]
        run: RunArgs,
        /// Component to analyse (default: the scene's only component).
        #[arg(long)]
        component: Option<String>,
    },
    /// Reduce the scene's components (Craig–Bampton superelements + gaps + loads) and write
    /// reduced.op4, reduced.pch, dofmap.json, gaps.json, checks.json.
    Reduce(RunArgs),
    /// Nonlinear BSQL transient: history.npy + history_map.json, energy.csv, restart.json,
    /// summary.json with the squeal verdict.
    Transient {
        #[command(flatten)]
        run: RunArgs,
        /// Also write the assembled DAE (M, B, K, G, loads, gap table, solver options) here.
        #[arg(long, value_name = "DIR")]
        export_dae: Option<PathBuf>,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Complex eigenvalue analysis about the steady sliding state (or a restart file's state):
    /// cea.json, stability_map.{png,svg}, cea_modes.vtu, summary.json; with a friction sweep
    /// (`[cea] sweep` or --mu) also cea.sweep.json and root_locus*.{png,svg}.
    Cea {
        #[command(flatten)]
        run: RunArgs,
        /// Friction sweep FIRST:LAST:COUNT (e.g. 0.1:0.9:41), overriding `[cea] sweep`.
        #[arg(long, value_name = "A:B:N")]
        mu: Option<String>,
        /// Also write the eigenproblem's matrices at the state as tangents.op4 and tangents.pch.
        #[arg(long)]
        export_tangents: bool,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Limit cycles by harmonic balance on the band-limited model (`[transient] band_cutoff`),
    /// continued in μ from each unstable in-band root's Hopf point: limit_cycle.json (per
    /// unstable mode the cycle's frequency and the rotor face's normal velocity, peak and RMS).
    LimitCycle {
        #[command(flatten)]
        run: RunArgs,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Design iterations: run CEA and/or the transient for each value of one scene parameter,
    /// rebuilding the reduced model only when the value changes it (model cache): per-value
    /// folders, sweep.json, sweep.md, sweep_indicators.{png,svg}, sweep_frequencies.{png,svg}.
    Sweep {
        #[command(flatten)]
        run: RunArgs,
        /// The parameter: a dotted scene key as --set writes it (e.g. friction.law.mu0,
        /// components.0.geometry.thickness, contact.0.p0, rotor.rpm); several keys separated by
        /// commas are all set to each value (components.1.rotate_deg,components.2.rotate_deg).
        #[arg(long, value_name = "DOTTED.KEY")]
        param: String,
        /// Values, comma-separated (TOML values: 0.4, 32, hex8).
        #[arg(long, value_name = "A,B,...")]
        values: Option<String>,
        /// Evenly spaced values FIRST:LAST:COUNT (after --values when both are given).
        #[arg(long, value_name = "A:B:N")]
        values_range: Option<String>,
        /// What runs for each value.
        #[arg(long, default_value = "cea", value_parser = ["cea", "transient", "both"])]
        analysis: String,
        /// Model cache folder (default: $SQUEAL_CACHE, else .squeal-cache beside the --out folder).
        #[arg(long, value_name = "DIR")]
        cache: Option<PathBuf>,
    },
    /// Squeal propensity under uncertain inputs: a scrambled-Sobol quasi-Monte Carlo design
    /// over --dist inputs, one CEA per sample on one reduced model: propensity.json
    /// (P(unstable) with its interval, per one-third-octave band, the largest Re p's
    /// distribution, Sobol indices), samples.csv, summary.json.
    Propensity {
        #[command(flatten)]
        run: RunArgs,
        /// An uncertain input: dotted scene key = uniform(a, b), normal(mean, sd),
        /// lognormal(mu, sigma) or truncnormal(mean, sd, lo, hi) (repeatable). Also
        /// components.NAME.young_scale / density_scale: a component's moduli or densities
        /// scaled on the one reduced model.
        #[arg(long = "dist", value_name = "KEY=DIST", required = true)]
        dist: Vec<String>,
        /// Correlation of two inputs' normal scores (Gaussian copula): KEY_A:KEY_B=RHO (repeatable).
        #[arg(long = "corr", value_name = "A:B=RHO")]
        corr: Vec<String>,
        /// Budget of CEA evaluations (the design uses R × 2^k × (d + 2) of them, d inputs).
        #[arg(long, default_value_t = 1000)]
        samples: usize,
        /// Independent scramblings (default: the R in 4..8 that uses the most of --samples).
        #[arg(long)]
        replicates: Option<usize>,
        /// Seed of the scrambling.
        #[arg(long, default_value_t = 1)]
        seed: u32,
        /// Rebuild the reduced model for every sample when an input changes it (component
        /// material or geometry); without it such an input is refused.
        #[arg(long)]
        rereduce: bool,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Work–precision study of the scene's transient: BDF at a ladder of RTOL1 × MAXORD and
    /// generalized-α at a ladder of fixed steps against a tight reference run: accuracy.json,
    /// accuracy.md, work_precision.{png,svg}, summary.json (ladders in `[accuracy]`).
    Accuracy(RunArgs),
    /// Extract records of a transient run's time-history database to a CSV table.
    Plotit {
        /// The transient run folder (holds history.npy and history_map.json).
        run_dir: PathBuf,
        /// Records: a column name, or KIND[:grid=G][:comp=x|y|z][:gap=N] (repeatable; default all).
        #[arg(long, num_args = 1.., value_name = "SPEC")]
        records: Vec<String>,
        /// Output CSV file.
        #[arg(long)]
        out: PathBuf,
    },
    /// The paper's sample-brake study: run the cases of a study file (default:
    /// examples/sample-brake/study.toml) and write cases.json, cases.md, figures and report.md.
    Reproduce {
        /// Study file: base scene + table of cases.
        #[arg(default_value = "examples/sample-brake/study.toml")]
        study: PathBuf,
        /// Output folder (default: out/reproduce).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run only these cases, e.g. 1,2,5.
        #[arg(long, value_delimiter = ',')]
        cases: Option<Vec<u32>>,
        /// Override a base-scene value for every case: dotted.key=value (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Cases run at the same time (default: the available cores).
        #[arg(long)]
        jobs: Option<usize>,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Regression of one reduced model or run against another: DOF maps, matrix differences
    /// ‖A−B‖/‖A‖, undamped modes paired by MAC, CEA roots paired by frequency, or two run
    /// folders' summary.json and cea.json: compare.json and compare.md. Exits 4 when a
    /// difference is beyond a tolerance given.
    Compare {
        /// Reference: a scene (.toml), stored matrices (.op4/.pch with dofmap.json beside), a
        /// reduce folder, or a run folder.
        a: PathBuf,
        /// Compared with A (same kind: a model or a run folder).
        b: PathBuf,
        /// Output folder (default: out/compare).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Largest relative frequency difference |f_B − f_A|/f_A of a paired undamped mode.
        #[arg(long, value_name = "REL")]
        tol_freq: Option<f64>,
        /// Smallest MAC of every mode of A with its pair (an unpaired mode fails).
        #[arg(long, value_name = "MIN")]
        tol_mac: Option<f64>,
        /// Largest ‖A − B‖_F/‖A‖_F of KR, MR, BR, PBRAKE.
        #[arg(long, value_name = "REL")]
        tol_matrix: Option<f64>,
        /// Largest |Δf|/f and |Δ Re p|/|p| of a paired CEA root (an unpaired root fails).
        #[arg(long, value_name = "REL")]
        tol_root: Option<f64>,
        /// Run folders: largest relative difference of a summary.json number (timings
        /// excluded); text and booleans (the verdict's state) must be equal.
        #[arg(long, value_name = "REL")]
        tol_summary: Option<f64>,
        /// Compare only the lowest N undamped modes of A.
        #[arg(long, value_name = "N")]
        modes: Option<usize>,
        /// MAC below which two modes are not paired, in [0, 1] and at most --tol-mac (default:
        /// 0.5, or --tol-mac when that is lower).
        #[arg(long, value_name = "MIN")]
        pair_mac: Option<f64>,
        /// Analysis settings (friction, rotor, loads, [cea]) for the CEA of stored matrices.
        #[arg(long, value_name = "SCENE.toml")]
        scene: Option<PathBuf>,
        /// Do not run the CEA of model inputs.
        #[arg(long)]
        no_cea: bool,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// List the matrices of a NASTRAN OP4 or punch (DMIG) file: name, shape, form, precision,
    /// nnz, Frobenius norm, sum, symmetry.
    Inspect {
        /// An .op4 file, or a punch file with DMIG cards.
        file: PathBuf,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
}

fn run_dir(args: &RunArgs) -> Result<RunDir> {
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args
            .scene
            .scene
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "run".into());
        PathBuf::from("out").join(stem)
    });
    Ok(RunDir::create(&out)?)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    bars::handle_ctrl_c();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            let cancelled = e
                .downcast_ref::<squeal_pipeline::PipelineError>()
                .is_some_and(|p| p.is_cancelled());
            if cancelled {
                eprintln!("squeal: {e}");
                return ExitCode::from(bars::EXIT_CANCELLED);
            }
            // Each stage's error already carries its cause's text; print it once.
            eprintln!("squeal: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Prints each warning on stderr (also when it is not a terminal, and with `-q`).
fn print_warnings(ws: &[squeal_pipeline::Warning]) {
    ws.iter().for_each(|w| eprintln!("squeal: {w}"));
}

fn run(cli: Cli) -> Result<ExitCode> {
    let progress = if cli.quiet {
        Progress::new(Arc::new(bars::Quiet)).silenced()
    } else {
        Progress::new(Arc::new(bars::Bars::default()))
    };
    let progress = &progress;
    let mut code = ExitCode::SUCCESS;
    match cli.verb {
        Verb::Check(args) => {
            let scene = Scene::load(&args.scene, &args.set)?;
            print!("{}", scene.resolved_toml());
        }
        Verb::Mesh(args) => {
            let scene = Scene::load(&args.scene.scene, &args.scene.set)?;
            let dir = run_dir(&args)?;
            let reports = stages::mesh::run(&scene, &dir, progress)?;
            for w in reports.iter().flat_map(|r| r.warnings()) {
                eprintln!("squeal: {w}");
            }
        }
        Verb::Modes { run, component } => {
            let scene = Scene::load(&run.scene.scene, &run.scene.set)?;
            let dir = run_dir(&run)?;
            let report = stages::modes::run(&scene, component.as_deref(), &dir, progress)?;
            for w in report.mesh.warnings() {
                eprintln!("squeal: {w}");
            }
            progress.info(report.table());
        }
        Verb::Reduce(args) => {
            let scene = Scene::load(&args.scene.scene, &args.scene.set)?;
            let dir = run_dir(&args)?;
            let report = stages::reduce::run(&scene, &dir, progress)?;
            print_warnings(&report.warnings);
            progress.info(report.table());
        }
        Verb::Transient {
            run,
            export_dae,
            cache,
        } => {
            let scene = Scene::load(&run.scene.scene, &run.scene.set)?;
            let dir = run_dir(&run)?;
            let cache = cache.dir().map(stages::model::ModelCache::new);
            let r = stages::transient::run_cached(
                &scene,
                &dir,
                progress,
                export_dae.as_deref(),
                cache.as_ref(),
            )?;
            let r = r.result;
            print_warnings(&r.warnings);
            progress.info(format!(
                "{} steps, {:.2} s: {}, growth rate {:?} /s, dominant frequency {:?} Hz ({})",
                r.steps,
                r.cpu_s,
                stages::reproduce::report::verdict_text(&r.verdict.state),
                r.growth_rate_per_s,
                r.dominant_frequency_hz,
                r.response
            ));
            if !r.status.is_success() {
                anyhow::bail!(
                    "integration stopped early: {:?} (outputs up to there are written)",
                    r.status
                );
            }
        }
        Verb::LimitCycle { run, cache } => {
            let scene = Scene::load(&run.scene.scene, &run.scene.set)?;
            let dir = run_dir(&run)?;
            let cache = cache.dir().map(stages::model::ModelCache::new);
            let r = stages::limit_cycle::run(&scene, &dir, progress, cache.as_ref())?;
            let mut lines = format!(
                "{} unstable mode(s) in the band; {}",
                r.result.modes.len(),
                r.result.band_model.line()
            );
            for m in &r.result.modes {
                lines.push_str(&format!(
                    "\n  root {:.2} Hz (Re p {:+.2} /s): {} {:.2} Hz, face normal velocity peak \
                     {:.4e}, rms {:.4e}, stable {:?}",
                    m.root_frequency_hz,
                    m.root_real_part,
                    if m.reached {
                        "limit cycle"
                    } else {
                        "NOT reached, last point"
                    },
                    m.frequency_hz,
                    m.peak_normal_velocity,
                    m.rms_normal_velocity,
                    m.stable
                ));
            }
            progress.info(lines);
        }
        Verb::Cea {
            run,
            mu,
            export_tangents,
            cache,
        } => {
            let scene = Scene::load(&run.scene.scene, &run.scene.set)?;
            let mu = mu
                .as_deref()
                .map(squeal_pipeline::scene::cea::parse_mu_range)
                .transpose()?;
            let dir = run_dir(&run)?;
            let args = stages::cea::CeaArgs {
                mu,
                export_tangents,
                cache: cache.dir().map(stages::model::ModelCache::new),
            };
            let r = stages::cea::run(&scene, &dir, progress, &args)?;
            print_warnings(&r.warnings);
            let mut lines = format!(
                "{} modes, {} unstable (max Re p = {:?})",
                r.n_modes_reported, r.n_unstable, r.max_real_part
            );
            for m in &r.unstable_modes {
                lines.push_str(&format!(
                    "\n  unstable: {:.2} Hz, Re p = {:.4e} 1/s, zeta = {:?}",
                    m.frequency_hz, m.real_part, m.damping_ratio
                ));
            }
            if let Some(mu) = r.lowest_critical_mu {
                lines.push_str(&format!("\n  lowest critical mu = {mu:.6}"));
            }
            progress.info(lines);
        }
        Verb::Propensity {
            run,
            dist,
            corr,
            samples,
            replicates,
            seed,
            rereduce,
            cache,
        } => {
            let scene = Scene::load(&run.scene.scene, &run.scene.set)?;
            let args = stages::propensity::PropensityArgs {
                dists: dist
                    .iter()
                    .map(|d| stages::propensity::parse_dist_flag(d))
                    .collect::<Result<_, _>>()?,
                corr: corr
                    .iter()
                    .map(|c| stages::propensity::parse_corr_flag(c))
                    .collect::<Result<_, _>>()?,
                samples,
                replicates,
                seed,
                rereduce,
            };
            let dir = run_dir(&run)?;
            let cache = cache.dir().map(stages::model::ModelCache::new);
            let r = stages::propensity::run(&scene, &dir, progress, &args, cache.as_ref())?;
            let p = &r.p_unstable;
            let mut lines = format!(
                "P(unstable) = {:.4} (95 % interval [{:.4}, {:.4}]) over {} samples ({} failed)",
                p.p, p.interval[0], p.interval[1], r.stats.evaluations, r.stats.failed
            );
            for b in r.bands.iter().filter(|b| b.p > 0.0) {
                lines.push_str(&format!(
                    "\n  {:.0} Hz band: {:.4} [{:.4}, {:.4}]",
                    b.band.center_hz, b.p, b.interval[0], b.interval[1]
                ));
            }
            if let Some(s) = &r.sobol_max_real_part {
                for (k, key) in s.keys.iter().enumerate() {
                    lines.push_str(&format!(
                        "\n  max Re p: S1({key}) = {:.3}, ST = {:.3}",
                        s.indices.first_order[k], s.indices.total[k]
                    ));
                }
            }
            progress.info(lines);
        }
        Verb::Sweep {
            run,
            param,
            values,
            values_range,
            analysis,
            cache,
        } => {
            let values =
                stages::sweep::values::parse_values(values.as_deref(), values_range.as_deref())?;
            let out = run.out.clone().unwrap_or_else(|| {
                let stem = run
                    .scene
                    .scene
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "run".into());
                PathBuf::from("out").join(format!("{stem}-sweep"))
            });
            let dir = RunDir::create(&out)?;
            let base = Scene::load(&run.scene.scene, &run.scene.set)?;
            let args = stages::sweep::SweepArgs {
                param,
                values,
                analysis: stages::sweep::Analysis::parse(&analysis)?,
                cache: CacheArgs { cache }.dir(),
            };
            let name = run.scene.scene.display().to_string();
            let r = stages::sweep::run(&base, &name, &dir, progress, &args)?;
            for p in &r.points {
                for w in &p.warnings {
                    eprintln!("squeal: value {}: {w}", p.label);
                }
            }
            progress.info(format!(
                "{} values in {:.1} s (models built {}, read from the cache {}); table: {}",
                r.points.len(),
                r.wall_s,
                r.n_built,
                r.n_cached,
                dir.path("sweep.md").display()
            ));
            if r.n_failed > 0 {
                eprintln!(
                    "squeal: {} value(s) failed: {}",
                    r.n_failed,
                    r.failed.join(", ")
                );
                code = ExitCode::from(r.exit_code());
            }
        }
        Verb::Accuracy(args) => {
            let scene = Scene::load(&args.scene.scene, &args.scene.set)?;
            let dir = run_dir(&args)?;
            let r = stages::accuracy::run(&scene, &dir, progress)?;
            progress.info(stages::accuracy::markdown(&r.runs));
        }
        Verb::Plotit {
            run_dir,
            records,
            out,
        } => {
            let (rows, cols) = stages::plotit::run(&run_dir, &records, &out)?;
            progress.info(format!("{}: {rows} rows, {cols} columns", out.display()));
        }
        Verb::Reproduce {
            study,
            out,
            cases,
            set,
            jobs,
            cache,
        } => {
            let dir = RunDir::create(&out.unwrap_or_else(|| PathBuf::from("out/reproduce")))?;
            let args = stages::reproduce::ReproduceArgs {
                cases,
                set,
                jobs,
                cache: cache.dir(),
            };
            let r = stages::reproduce::run(&study, &dir, progress, &args)?;
            progress.info(format!(
                "{} cases in {:.1} s; report: {}",
                r.cases.len(),
                r.wall_s,
                dir.path("report.md").display()
            ));
        }
        Verb::Compare {
            a,
            b,
            out,
            tol_freq,
            tol_mac,
            tol_matrix,
            tol_root,
            tol_summary,
            modes,
            pair_mac,
            scene,
            no_cea,
            cache,
        } => {
            let dir = RunDir::create(&out.unwrap_or_else(|| PathBuf::from("out/compare")))?;
            let opts = stages::compare::CompareOptions {
                tol_freq,
                tol_mac,
                tol_matrix,
                tol_root,
                tol_summary,
                modes,
                pair_mac,
                scene,
                cea: !no_cea,
                cache: cache.dir().map(stages::model::ModelCache::new),
            };
            let r = stages::compare::compute(&a, &b, &opts, &dir, progress)?;
            stages::compare::write(&r, &dir)?;
            for c in r.checks.iter().filter(|c| !c.passed) {
                eprintln!(
                    "squeal: beyond tolerance: {} = {:e}: {:e} at {}",
                    c.tolerance_name, c.tolerance, c.worst, c.at
                );
            }
            progress.info(format!(
                "{}; report: {}",
                if r.passed {
                    "within the tolerances"
                } else {
                    "beyond a tolerance"
                },
                dir.path("compare.md").display()
            ));
            if !r.passed {
                code = ExitCode::from(stages::compare::EXIT_BEYOND_TOLERANCE);
            }
        }
        Verb::Inspect { file, json } => {
            let summaries = squeal_reduction::inspect::inspect(&file)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&summaries)?);
            } else {
                print!("{}", squeal_reduction::inspect::SummaryTable(&summaries));
            }
        }
    }
    Ok(code)
}
