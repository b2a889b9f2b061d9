//! The pipeline as a library: scenes built and changed in memory, compute functions that return
//! results in memory equal to what the `squeal` command writes, and the progress/cancel hook.

mod common;
use common::{json, root, run, squeal, tmp};

use squeal_pipeline::history::npy::read_npy;
use squeal_pipeline::progress::{Event, Progress, ProgressSink};
use squeal_pipeline::stages::{model, transient};
use squeal_pipeline::{PipelineError, RunDir, Scene};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

fn tiny_text() -> String {
    std::fs::read_to_string(root().join("examples/transient/tiny-brake.toml")).unwrap()
}

/// `from_toml_str` gives the scene `load` gives; `set` changes one value and re-validates,
/// and a bad key or value leaves the scene as it was with an error naming the key.
#[test]
fn scenes_are_built_and_changed_in_memory() {
    let path = root().join("examples/transient/tiny-brake.toml");
    let loaded = Scene::load(&path, &[]).unwrap();
    let mut s = Scene::from_toml_str(&tiny_text(), path.parent().unwrap(), &[]).unwrap();
    assert_eq!(s, loaded);
    s.set("friction.law.mu0", "0.45").unwrap();
    let law = serde_json::to_value(&s.friction.as_ref().unwrap().law).unwrap();
    assert_eq!(law["mu0"], 0.45, "{law}");
    let before = s.clone();
    let e = s
        .set("friction.law.mu_zero", "0.5")
        .unwrap_err()
        .to_string();
    assert!(e.contains("mu_zero"), "{e}");
    assert_eq!(s, before);
    let e = s.set("transient.rtol1", "-1").unwrap_err().to_string();
    assert!(e.contains("rtol1"), "{e}");
    assert_eq!(s, before);
    let e = Scene::from_toml_str("[transient\n", ".", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("<string>"), "{e}");
}

/// The in-memory transient equals the command's files: every history row (bit for bit: the
/// same driver fills both) and the summary's counters and verdict.
#[test]
fn transient_in_memory_equals_the_command_files() {
    let d = tmp("library-transient");
    let out = d.join("cli");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "transient"])
        .arg(root().join("examples/transient/tiny-brake.toml"))
        .arg("--out")
        .arg(&out)
        .args(["--set", "transient.tfinal=0.03"]));
    assert!(ok, "{stderr}");
    let scene = Scene::from_toml_str(
        &tiny_text(),
        root().join("examples/transient"),
        &["transient.tfinal=0.03".into()],
    )
    .unwrap();
    let work = RunDir::create(&d.join("work")).unwrap();
    let m = model::build(&scene, &work, &Progress::quiet()).unwrap();
    let r = transient::compute(
        &scene,
        &m,
        &Progress::quiet(),
        &transient::TransientOptions {
            keep_history: true,
            ..Default::default()
        },
    )
    .unwrap();
    let h = r.history.as_ref().expect("history kept");
    let (rows, cols, data) = read_npy(&out.join("history.npy")).unwrap();
    assert_eq!((h.rows(), h.columns.len()), (rows, cols));
    assert_eq!(h.values, data);
    let map = json(&out.join("history_map.json"));
    assert_eq!(
        serde_json::to_value(&h.columns).unwrap(),
        map["columns"],
        "columns"
    );
    let energy = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    assert_eq!(energy.lines().count() - 1, h.energy.len());
    let s = json(&out.join("summary.json"));
    assert_eq!(s["steps"].as_u64().unwrap(), r.steps);
    assert_eq!(s["history_rows"].as_u64().unwrap() as usize, rows);
    assert_eq!(s["squeal"].as_bool().unwrap(), r.squeal);
    assert_eq!(
        s["growth_rate_per_s"].as_f64(),
        r.growth_rate_per_s,
        "verdict"
    );
    assert_eq!(s["integrator"], "bdf");
    let t = h.column("t").unwrap();
    assert_eq!(t.len(), rows);
    assert!((t[rows - 1] - 0.03).abs() < 1e-15, "{}", t[rows - 1]);
}

/// A sink that counts events and asks to stop after `stop_after` bar updates.
struct Stopper {
    updates: AtomicUsize,
    stop_after: usize,
}

impl ProgressSink for Stopper {
    fn event(&self, _: u64, e: Event<'_>) {
        if matches!(e, Event::Update { .. }) {
            self.updates.fetch_add(1, Ordering::Relaxed);
        }
    }
    fn cancelled(&self) -> bool {
        self.updates.load(Ordering::Relaxed) >= self.stop_after
    }
}

/// Cancelling through the hook ends the run with `Cancelled` between chunks, and the history
/// written up to there is complete and readable.
#[test]
fn cancelling_stops_between_chunks_and_keeps_the_history() {
    let d = tmp("library-cancel");
    let scene = Scene::load(&root().join("examples/transient/tiny-brake.toml"), &[]).unwrap();
    let dir = RunDir::create(&d.join("run")).unwrap();
    let m = model::build(&scene, &dir, &Progress::quiet()).unwrap();
    let sink = Arc::new(Stopper {
        updates: AtomicUsize::new(0),
        stop_after: 2,
    });
    let e = transient::run_on_model(
        &scene,
        &dir,
        &Progress::new(sink.clone()),
        None,
        &m,
        std::time::Instant::now(),
        &Default::default(),
    )
    .unwrap_err();
    assert!(matches!(e, PipelineError::Cancelled { .. }), "{e}");
    assert_eq!(sink.updates.load(Ordering::Relaxed), 2);
    let (rows, cols, data) = read_npy(&d.join("run/history.npy")).unwrap();
    // Two chunks of 50 steps, every NOUTPT = 2nd recorded, plus the initial point.
    assert_eq!(rows, 1 + 2 * 50 / 2, "{rows}");
    assert_eq!(data.len(), rows * cols);
    assert!(data.iter().all(|x| x.is_finite()));
}
