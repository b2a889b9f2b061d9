//! Shared helpers for the verification and system tests, and the fuzz harness ([`fuzz`]).

pub mod fuzz;

use std::path::{Path, PathBuf};

/// The workspace root (the folder holding `examples/`).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ sits in the workspace root")
        .to_path_buf()
}

/// A fresh, empty output folder for one test, under the target directory.
pub fn fresh_out_dir(tmp_root: &str, name: &str) -> PathBuf {
    let dir = Path::new(tmp_root).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create test output folder");
    dir
}

/// Collapses values that repeat within `rel` (degenerate mode pairs) to one.
pub fn distinct(values: &[f64], rel: f64) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for &v in values {
        if out
            .last()
            .is_none_or(|&last| (v - last).abs() > rel * v.abs().max(last.abs()))
        {
            out.push(v);
        }
    }
    out
}
