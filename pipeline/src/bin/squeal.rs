//! The `squeal` command: `squeal <verb> SCENE.toml [--out DIR] [--set key=value ...]`.

use anyhow::Result;
use clap::{Args, Parser, Subcommand};
use squeal_pipeline::progress::Progress;
use squeal_pipeline::{stages, RunDir, Scene};
use std::path::PathBuf;
use std::process::ExitCode;

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
    },
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
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Each stage's error already carries its cause's text; print it once.
            eprintln!("squeal: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    let progress = Progress { quiet: cli.quiet };
    match cli.verb {
        Verb::Check(args) => {
            let scene = Scene::load(&args.scene, &args.set)?;
            print!("{}", scene.resolved_toml());
        }
        Verb::Mesh(args) => {
            let scene = Scene::load(&args.scene.scene, &args.scene.set)?;
            let dir = run_dir(&args)?;
            stages::mesh::run(&scene, &dir, progress)?;
        }
        Verb::Modes { run, component } => {
            let scene = Scene::load(&run.scene.scene, &run.scene.set)?;
            let dir = run_dir(&run)?;
            let report = stages::modes::run(&scene, component.as_deref(), &dir, progress)?;
            progress.info(report.table());
        }
        Verb::Reduce(args) => {
            let scene = Scene::load(&args.scene.scene, &args.scene.set)?;
            let dir = run_dir(&args)?;
            let report = stages::reduce::run(&scene, &dir, progress)?;
            progress.info(report.table());
        }
        Verb::Transient { run, export_dae } => {
            let scene = Scene::load(&run.scene.scene, &run.scene.set)?;
            let dir = run_dir(&run)?;
            let r = stages::transient::run(&scene, &dir, progress, export_dae.as_deref())?;
            progress.info(format!(
                "{} steps, {:.2} s: squeal = {}, growth rate {:?} /s, dominant frequency {:?} Hz ({})",
                r.steps, r.cpu_s, r.squeal, r.growth_rate_per_s, r.dominant_frequency_hz, r.response
            ));
            if !r.status.is_success() {
                anyhow::bail!(
                    "integration stopped early: {:?} (outputs up to there are written)",
                    r.status
                );
            }
        }
        Verb::Plotit {
            run_dir,
            records,
            out,
        } => {
            let (rows, cols) = stages::plotit::run(&run_dir, &records, &out)?;
            progress.info(format!("{}: {rows} rows, {cols} columns", out.display()));
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
    Ok(())
}
