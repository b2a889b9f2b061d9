//! Writes the stored-matrix models of the work–precision scenes into `examples/accuracy/`:
//! `belt.*` (mass on a belt, falling μ(v)) and `coupling.*` (Hoffmann's 2-DOF mode coupling),
//! each as `.op4` (ASCII), `.dofmap.json`, `.gaps.csv`. See
//! `squeal_pipeline::stages::accuracy::models` for the models and their analytic roots.
//!
//! ```text
//! cargo run -p squeal-pipeline --example accuracy_models [DIR]   # default examples/accuracy
//! ```

use squeal_pipeline::stages::accuracy::models;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("examples/accuracy"));
    models::belt().write(&dir, "belt")?;
    models::coupling().write(&dir, "coupling")?;
    let (s, f) = models::belt_reference();
    println!("belt: sigma = {s} 1/s, f = {f} Hz");
    let (s, f) = models::coupling_reference(0.8);
    println!("coupling (mu = 0.8): sigma = {s} 1/s, f = {f} Hz");
    println!("wrote {}", dir.display());
    Ok(())
}
