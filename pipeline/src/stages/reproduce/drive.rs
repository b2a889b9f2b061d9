//! Running one case's transient with a step cap.
//!
//! A squealing response grows until the slip speed of some gap reverses; there the friction
//! force crosses the arctangent zone of width VTOL ([Paper eq. (5)]), the problem becomes very
//! stiff and the BDF step collapses (1e-11 s on the sample brake): the run would never reach TF.
//! The transient stage's `max_steps` counts the steps of one `step_to` call (the stage calls it
//! in chunks), so it cannot bound a run; a case with a cap therefore runs `squeal transient` as a
//! child process that is stopped once its history holds `cap` steps. The verdict is then
//! computed here from the history written so far, as the transient stage computes it.

use super::report::column;
use crate::error::PipelineError;
use crate::history::{HistoryMap, RecordKind};
use crate::output::RunDir;
use crate::stages::transient::verdict;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

type Real = f64;

/// What a capped run produced.
#[derive(Debug, Clone)]
pub struct CappedRun {
    pub steps: u64,
    pub cpu_s: Real,
    pub t_end: Real,
    pub status: String,
    pub squeal: bool,
    pub growth_rate_per_s: Option<Real>,
    pub dominant_frequency_hz: Option<Real>,
    pub response: String,
    pub n_dofs: usize,
    pub n_gaps: usize,
}

fn rows_written(dir: &RunDir, cols: usize) -> usize {
    let len = std::fs::metadata(dir.path("history.npy")).map_or(0, |m| m.len() as usize);
    len.saturating_sub(128) / (8 * cols.max(1))
}

/// Runs `squeal -q transient case.toml --out dir [--cache DIR]` and stops it after `cap`
/// recorded steps.
pub fn run_capped(
    scene_file: &std::path::Path,
    dir: &RunDir,
    cap: usize,
    t_load: Real,
    h_max: Real,
    threshold: (Real, Real),
    cache: Option<&std::path::Path>,
) -> Result<CappedRun, PipelineError> {
    let exe = std::env::current_exe().map_err(|source| PipelineError::Io {
        path: "squeal".into(),
        source,
    })?;
    let start = Instant::now();
    let mut cmd = Command::new(&exe);
    cmd.args(["-q", "transient"])
        .arg(scene_file)
        .arg("--out")
        .arg(dir.path(""));
    if let Some(c) = cache {
        cmd.arg("--cache").arg(c);
    }
    let mut child = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|source| PipelineError::Io {
            path: exe.clone(),
            source,
        })?;
    let mut capped = false;
    let exit = loop {
        if let Some(st) = child.try_wait().map_err(|source| PipelineError::Io {
            path: exe.clone(),
            source,
        })? {
            break Some(st);
        }
        let cols = HistoryMap::read(&dir.path("history_map.json")).map_or(0, |m| m.n_columns);
        if cols > 0 && rows_written(dir, cols) > cap {
            let _ = child.kill();
            let _ = child.wait();
            capped = true;
            break None;
        }
        std::thread::sleep(Duration::from_millis(200));
    };
    let wall = start.elapsed().as_secs_f64();
    let summary = dir.path("summary.json");
    if !capped && summary.is_file() {
        let v: serde_json::Value = std::fs::read_to_string(&summary)
            .ok()
            .and_then(|s| serde_json::from_str(&s).ok())
            .unwrap_or_default();
        let f = |k: &str| v.get(k).and_then(|x| x.as_f64());
        return Ok(CappedRun {
            steps: v.get("steps").and_then(|x| x.as_u64()).unwrap_or(0),
            cpu_s: f("cpu_s").unwrap_or(wall),
            t_end: f("t_end").unwrap_or(0.0),
            status: match v.pointer("/status/status").and_then(|s| s.as_str()) {
                Some("reached") => "reached TF".into(),
                _ => format!("{}", v.get("status").cloned().unwrap_or_default()),
            },
            squeal: v.get("squeal").and_then(|x| x.as_bool()).unwrap_or(false),
            growth_rate_per_s: f("growth_rate_per_s"),
            dominant_frequency_hz: f("dominant_frequency_hz"),
            response: v
                .get("response")
                .and_then(|x| x.as_str())
                .unwrap_or("")
                .to_string(),
            n_dofs: v.get("n_dofs").and_then(|x| x.as_u64()).unwrap_or(0) as usize,
            n_gaps: v.get("n_gaps").and_then(|x| x.as_u64()).unwrap_or(0) as usize,
        });
    }
    if !capped {
        let mut msg = String::new();
        if let Some(mut e) = child.stderr.take() {
            use std::io::Read;
            let _ = e.read_to_string(&mut msg);
        }
        return Err(PipelineError::Output {
            path: dir.path(""),
            message: format!("squeal transient failed ({exit:?}): {}", msg.trim()),
        });
    }
    // Stopped at the cap: the verdict of the history so far (the velocity column with the
    // largest peak after the ramp, as the transient stage picks it).
    let map = HistoryMap::read(&dir.path("history_map.json"))?;
    let mut best: Option<(Real, String, verdict::Verdict, Real, u64)> = None;
    for c in map
        .columns
        .iter()
        .filter(|c| c.kind == RecordKind::Velocity)
    {
        let (t, v) = column(&dir.path(""), &c.name)?;
        let peak = t
            .iter()
            .zip(&v)
            .filter(|(t, _)| **t > t_load)
            .fold(0.0f64, |m, (_, x)| m.max(x.abs()));
        if best.as_ref().is_none_or(|b| peak > b.0) {
            // The growth phase only: up to the first step below h_max/100 after the ramp
            // (the start of stick-slip, where the step collapses).
            let stall = (1..t.len())
                .find(|&i| t[i] > t_load && t[i] - t[i - 1] < 1e-2 * h_max)
                .unwrap_or(t.len());
            let vd = verdict::analyse(&t[..stall], &v[..stall], t_load);
            let t_end = t.last().copied().unwrap_or(0.0);
            best = Some((peak, c.name.clone(), vd, t_end, t.len() as u64));
        }
    }
    let (_, response, vd, t_end, rows) = best.ok_or_else(|| PipelineError::Output {
        path: dir.path("history_map.json"),
        message: "no velocity record".into(),
    })?;
    Ok(CappedRun {
        steps: rows.saturating_sub(1),
        cpu_s: wall,
        t_end,
        status: format!("stopped at the step cap ({cap} steps) at t = {t_end:.4e}"),
        squeal: vd.is_squeal(threshold.0, threshold.1),
        growth_rate_per_s: vd.growth_rate_per_s,
        dominant_frequency_hz: vd.dominant_frequency_hz,
        response,
        n_dofs: 0,
        n_gaps: 0,
    })
}
