//! Writes the stored model of examples/limit-cycle/hoffmann.toml: Hoffmann's mode-coupling
//! model (Hoffmann, Fischer, Allgaier & Gaul, Mech. Res. Commun. 29 (2002) 197–205) as
//! `pipeline/tests/separation.rs` and the solver's harmonic-balance test build it — DOFs pad y
//! (tangential), pad z, a rotor point z of mass 0.05 on a unit spring with a damper 0.05; pad
//! damping 0.02 — as `hoffmann.op4`, `hoffmann.dofmap.json`, `hoffmann.gaps.csv` (one gap at
//! (1, 0, 0), normal +z, area 1, P0 = 0.2; PBRAKE a unit force on the pad's y).
//!
//! ```text
//! cargo run -p squeal-pipeline --example limit_cycle_model [DIR]   # default examples/limit-cycle
//! ```

use faer::Mat;
use squeal_pipeline::stages::accuracy::models::StoredModel;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("examples/limit-cycle"));
    let k = [[1.0, 0.3, 0.0], [0.3, 0.2, 0.0], [0.0, 0.0, 1.0]];
    let diag = |d: [f64; 3]| Mat::from_fn(3, 3, |i, j| if i == j { d[i] } else { 0.0 });
    StoredModel {
        k: Mat::from_fn(3, 3, |i, j| k[i][j]),
        m: diag([1.0, 1.0, 0.05]),
        b: Some(diag([0.02, 0.02, 0.05])),
        p_brake: vec![1.0, 0.0, 0.0],
        dofs: vec![(1, 2), (1, 3), (100_001, 3)],
        gaps: vec![(1, 100_001, [0.0, 0.0, 1.0], 1.0, 0.2)],
    }
    .write(&dir, "hoffmann")?;
    println!("wrote {}", dir.display());
    Ok(())
}
