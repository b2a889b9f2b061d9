//! Restart as a true resume (`transient.restart`): a run killed (SIGKILL) at any point and
//! resumed until it is done ends with the uninterrupted run's records — `history.npy`,
//! `energy.csv`, `response.npy` byte for byte — and its `summary.json` (every field but the
//! timings and `restarted_from`), on the tiny brake scene with a restart every 20 steps.

mod common;
use common::{json, root, run, squeal, tmp};

use squeal_pipeline::history::npy::{read_npy, write_npy};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn scene() -> PathBuf {
    root().join("examples/transient/tiny-brake.toml")
}

/// A restart every 20 steps (about 60 restart points over the ~1150 steps to TFINAL = 0.05).
const SETS: [&str; 2] = ["transient.nrstrt=20", "transient.tfinal=0.05"];

/// `squeal transient` of the scene into `out` (model from `cache`), resuming `restart` if given.
fn command(out: &Path, cache: &Path, restart: Option<&Path>) -> Command {
    let mut cmd = squeal();
    cmd.args(["-q", "transient"])
        .arg(scene())
        .arg("--out")
        .arg(out)
        .arg("--cache")
        .arg(cache);
    for s in SETS {
        cmd.args(["--set", s]);
    }
    if let Some(r) = restart {
        cmd.args(["--set", &format!("transient.restart=\"{}\"", r.display())]);
    }
    cmd
}

/// Files compared byte for byte.
const RECORDS: [&str; 3] = ["history.npy", "energy.csv", "response.npy"];

/// The summary without what differs between an uninterrupted and a resumed run by nature:
/// wall and CPU seconds, and the restart it was resumed from.
fn summary(dir: &Path) -> serde_json::Value {
    let mut s = json(&dir.join("summary.json"));
    let o = s.as_object_mut().unwrap();
    for k in ["wall_s", "cpu_s", "bookkeeping_s", "restarted_from"] {
        assert!(o.remove(k).is_some(), "summary.json lacks {k}");
    }
    o["bdf_stats"].as_object_mut().unwrap().remove("cpu_s");
    s
}

/// The records and summary of `dir` equal those of the uninterrupted run `reference`.
fn assert_same_run(reference: &Path, dir: &Path, what: &str) {
    for f in RECORDS {
        let (a, b) = (
            std::fs::read(reference.join(f)).unwrap(),
            std::fs::read(dir.join(f)).unwrap(),
        );
        assert!(
            a == b,
            "{what}: {f} differs from the uninterrupted run's ({} vs {} bytes)",
            b.len(),
            a.len()
        );
    }
    let (a, b) = (summary(reference), summary(dir));
    for (k, v) in a.as_object().unwrap() {
        assert_eq!(Some(v), b.get(k), "{what}: summary.json `{k}` differs");
    }
    assert_eq!(a, b, "{what}: summary.json differs");
}

/// SplitMix64: the test's seeded random numbers in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Where a kill landed: before the first restart file, between restarts, after the run ended.
#[derive(Debug, Default)]
struct Landed {
    before_first_restart: usize,
    mid_run: usize,
    after_end: usize,
}

#[test]
fn runs_killed_at_random_points_and_resumed_equal_the_uninterrupted_run() {
    let d = tmp("resume-kill");
    let cache = d.join("cache");
    // The uninterrupted run (it also fills the model cache), then its duration from the cache,
    // the scale of the kill delays (timing only chooses where kills land; nothing asserts it).
    let reference = d.join("reference");
    let (ok, _, stderr) = run(&mut command(&reference, &cache, None));
    assert!(ok, "{stderr}");
    let clock = Instant::now();
    let (ok, _, stderr) = run(&mut command(&d.join("timed"), &cache, None));
    assert!(ok, "{stderr}");
    let span = clock.elapsed().as_secs_f64();
    let steps = json(&reference.join("summary.json"))["steps"]
        .as_u64()
        .unwrap();
    assert!(steps > 500, "{steps} steps: too few restart points");

    let mut rng = Rng(0x5eed_0014);
    let trials = 24;
    let mut landed = Landed::default();
    let mut kills = 0;
    for trial in 0..trials {
        let dir = d.join(format!("trial-{trial:02}"));
        let restart = dir.join("restart.json");
        // 1 to 3 kills: the first one stratified over [0, 1.15 × the run's duration] on a
        // quadratic scale (the first trials kill within milliseconds, before the first restart
        // file; the last ones after the run ended), the others anywhere in the rest.
        let n_kills = 1 + (rng.next() * 3.0) as usize;
        let u = (trial as f64 + rng.next()) / trials as f64;
        let mut delays: Vec<f64> = vec![u * u * 1.15 * span];
        for _ in 1..n_kills {
            delays.push(rng.next() * span);
        }
        for delay in delays {
            let resume = restart.is_file().then_some(restart.as_path());
            let mut child = command(&dir, &cache, resume)
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap();
            std::thread::sleep(Duration::from_secs_f64(delay));
            let finished = child.try_wait().unwrap().is_some_and(|s| s.success());
            let _ = child.kill(); // SIGKILL
            child.wait().unwrap();
            kills += 1;
            let at = match (finished, restart.is_file()) {
                (true, _) => &mut landed.after_end,
                (false, false) => &mut landed.before_first_restart,
                (false, true) => &mut landed.mid_run,
            };
            *at += 1;
            eprintln!(
                "trial {trial}: kill after {delay:.3} s: finished {finished}, restart at {:?}",
                restart
                    .is_file()
                    .then(|| json(&restart)["run"]["steps"].clone())
            );
        }
        // Resume until done (a run that was never restarted starts again).
        let resume = restart.is_file().then_some(restart.as_path());
        let (ok, _, stderr) = run(&mut command(&dir, &cache, resume));
        assert!(ok, "trial {trial}: {stderr}");
        assert!(!stderr.contains("warning"), "trial {trial}: {stderr}");
        assert_same_run(&reference, &dir, &format!("trial {trial}"));
    }
    eprintln!("{kills} kills: {landed:?} (run of {steps} steps, {span:.2} s)");
    // The stratified delays put kills before the first restart file (the run starts again)
    // and mid-run, where the records hold rows past the restart file that the resume drops.
    assert!(
        landed.before_first_restart >= 1 && landed.mid_run >= trials / 4,
        "{landed:?}"
    );
}

#[test]
fn resume_into_a_new_folder_a_copied_restart_file_and_changed_outputs() {
    let d = tmp("resume-cases");
    let cache = d.join("cache");
    let reference = d.join("reference");
    let (ok, _, stderr) = run(&mut command(&reference, &cache, None));
    assert!(ok, "{stderr}");
    // A run stopped at a restart point: the same scene capped at 300 steps (restarts every
    // 20 steps, so its last restart is at step 300 and it wrote rows up to there).
    let stopped = d.join("stopped");
    let (ok, _, stderr) =
        run(command(&stopped, &cache, None).args(["--set", "transient.max_steps=300"]));
    assert!(!ok && stderr.contains("stopped early"), "{stderr}");
    let restart = stopped.join("restart.json");
    let r = json(&restart);
    assert_eq!(r["run"]["steps"], 300);

    // Resumed into a new folder: it holds the whole run, equal to the uninterrupted one; the
    // stopped run's folder is left as it was.
    let before = std::fs::read(stopped.join("history.npy")).unwrap();
    let new = d.join("new");
    let (ok, _, stderr) = run(&mut command(&new, &cache, Some(&restart)));
    assert!(ok, "{stderr}");
    assert_same_run(&reference, &new, "resumed into a new folder");
    assert_eq!(before, std::fs::read(stopped.join("history.npy")).unwrap());
    assert_eq!(
        json(&new.join("summary.json"))["restarted_from"],
        restart.display().to_string()
    );

    // A restart file away from its run's records: the state alone, with a warning, and a
    // history that starts at the restart time.
    let alone = d.join("copied.restart.json");
    std::fs::copy(&restart, &alone).unwrap();
    let out = d.join("alone");
    let (ok, _, stderr) = run(&mut command(&out, &cache, Some(&alone)));
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("copied.restart.json") && stderr.contains("continues the state alone"),
        "{stderr}"
    );
    let s = json(&out.join("summary.json"));
    assert_eq!(s["warnings"].as_array().unwrap().len(), 1, "{s}");
    assert_eq!(s["t_start"], r["t"]);
    assert_eq!(s["steps"], json(&reference.join("summary.json"))["steps"]);

    // Records beside the restart file with fewer rows than it counts (cut or replaced after
    // it was written): errors naming the restart file, the count and the file.
    for (file, field) in [
        ("history.npy", "history_rows"),
        ("energy.csv", "energy_rows"),
    ] {
        let short = d.join(format!("short-{field}"));
        std::fs::create_dir_all(&short).unwrap();
        for f in [
            "restart.json",
            "history.npy",
            "history_map.json",
            "energy.csv",
            "response.npy",
        ] {
            std::fs::copy(stopped.join(f), short.join(f)).unwrap();
        }
        match file {
            "history.npy" => {
                let (rows, cols, data) = read_npy(&short.join(file)).unwrap();
                write_npy(&short.join(file), &data[..(rows - 2) * cols], cols).unwrap();
            }
            _ => {
                let text = std::fs::read_to_string(short.join(file)).unwrap();
                let keep: Vec<&str> = text.lines().take(10).collect();
                std::fs::write(short.join(file), keep.join("\n") + "\n").unwrap();
            }
        }
        let r = short.join("restart.json");
        let (ok, _, stderr) = run(&mut command(&d.join("short-out"), &cache, Some(&r)));
        assert!(
            !ok && stderr.contains(&format!("{}: field `run.records.{field}`", r.display()))
                && stderr.contains(file),
            "{stderr}"
        );
    }

    // Other history columns or another response than the run resumed: errors naming the key.
    for (set, key) in [
        ("output.grids=[200017]", "output.grids"),
        ("output.response={grid=200017,dof=\"z\"}", "output.response"),
        ("output.history=false", ""),
    ] {
        let out = d.join("changed");
        let (ok, _, stderr) = run(command(&out, &cache, Some(&restart)).args(["--set", set]));
        match key {
            // Without a history the run goes on (nothing to continue but the response).
            "" => assert!(ok, "{set}: {stderr}"),
            _ => assert!(
                !ok && stderr.contains(key) && stderr.contains("restart.json"),
                "{set}: {stderr}"
            ),
        }
    }
}
