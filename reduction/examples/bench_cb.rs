//! Benchmark of the Craig–Bampton reduction on a hex20 annulus rotor (≈ 100k DOFs).
//!
//! ```text
//! cargo build --release -p squeal-reduction --example bench_cb
//! target/release/examples/bench_cb [n_circ n_rad n_thick n_boundary_nodes n_modes] [--cross-check]
//! ```
//! Defaults: 160 × 10 × 4 hex20 cells (97 920 DOFs), 50 boundary nodes (150 DOFs) on the
//! friction face nearest to the mean radius at angle 0 (a pad-like patch), 50 modes. Prints a
//! JSON document with the time and peak resident memory (VmHWM) of every phase. With
//! `--block=N` sets the Lanczos block size. With `--cross-check`, the fixed-interface problem is also assembled with the boundary DOFs fixed
//! and solved by `squeal_fe::solve_modes`, and the frequencies are compared.

use serde_json::json;
use squeal_fe::{assemble, solve_modes, AssemblyOptions, DofMap, Material, ModalOptions};
use squeal_meshes::structured::annulus_mesh;
use squeal_meshes::CellKind;
use squeal_reduction::cb::{self, peak_rss_kib, CbOptions};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cross_check = args.iter().any(|a| a == "--cross-check");
    let nums: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let get = |i: usize, d: usize| nums.get(i).copied().unwrap_or(d);
    let (n_circ, n_rad, n_thick, n_bnodes, n_modes) =
        (get(0, 160), get(1, 10), get(2, 4), get(3, 50), get(4, 50));
    let (r_in, r_out, t) = (0.08, 0.16, 0.025);

    let t0 = Instant::now();
    let mesh = annulus_mesh(r_in, r_out, t, n_circ, n_rad, n_thick, CellKind::Hex20);
    let mesh_s = t0.elapsed().as_secs_f64();

    // Pad-like patch: friction-face nodes nearest to (r_mid, 0, t).
    let face = mesh
        .node_sets
        .get("friction_top")
        .ok_or("annulus mesh has no friction_top node set")?;
    let centre = [0.5 * (r_in + r_out), 0.0, t];
    let mut by_dist: Vec<(f64, usize)> = face
        .iter()
        .map(|&n| {
            let p = mesh.nodes[n];
            ((0..3).map(|a| (p[a] - centre[a]).powi(2)).sum::<f64>(), n)
        })
        .collect();
    by_dist.sort_by(|a, b| a.0.total_cmp(&b.0));
    let bnodes: Vec<usize> = by_dist.iter().take(n_bnodes).map(|&(_, n)| n).collect();

    let t0 = Instant::now();
    let dofs = DofMap::new(mesh.nodes.len(), &[])?;
    let asm = assemble(
        &mesh,
        &[Material::steel_si()],
        &dofs,
        &AssemblyOptions::default(),
    )?;
    let assembly_s = t0.elapsed().as_secs_f64();
    let rss_after_assembly = peak_rss_kib();
    let boundary: Vec<usize> = bnodes
        .iter()
        .flat_map(|&n| (0..3).map(move |c| (n, c)))
        .map(|(n, c)| dofs.free(n, c).ok_or("boundary DOF is fixed"))
        .collect::<Result<_, _>>()?;

    let mut opts = CbOptions::with_n_modes(n_modes);
    if let Some(b) = args.iter().find_map(|a| a.strip_prefix("--block=")) {
        opts.lanczos_block = b.parse()?;
    }
    let t0 = Instant::now();
    let model = cb::reduce(&asm.k, &asm.m, &boundary, &opts)?;
    let reduce_s = t0.elapsed().as_secs_f64();

    let mut out = json!({
        "mesh": { "kind": "hex20 annulus", "n_circ": n_circ, "n_rad": n_rad, "n_thick": n_thick,
                  "r_in": r_in, "r_out": r_out, "thickness": t, "n_nodes": mesh.nodes.len() },
        "n_dofs": asm.k.nrows(),
        "nnz_k": asm.k.val().len(),
        "n_boundary_dofs": boundary.len(),
        "n_modes": model.n_modes,
        "mesh_s": mesh_s,
        "assembly_s": assembly_s,
        "peak_rss_kib_after_assembly": rss_after_assembly,
        "reduce_s": reduce_s,
        "cb_stats": serde_json::to_value(&model.stats)?,
        "fixed_frequencies_hz": [model.fixed_frequencies_hz.first(), model.fixed_frequencies_hz.last()],
        "peak_rss_kib": peak_rss_kib(),
        "threads": rayon::current_num_threads(),
    });

    if cross_check {
        let fixed: Vec<(usize, usize)> = bnodes
            .iter()
            .flat_map(|&n| (0..3).map(move |c| (n, c)))
            .collect();
        let dofs_i = DofMap::new(mesh.nodes.len(), &fixed)?;
        let asm_i = assemble(
            &mesh,
            &[Material::steel_si()],
            &dofs_i,
            &AssemblyOptions::default(),
        )?;
        let t0 = Instant::now();
        let modes = solve_modes(
            &asm_i.k,
            &asm_i.m,
            &ModalOptions {
                n_modes: Some(n_modes),
                ..ModalOptions::default()
            },
        )?;
        let fe_s = t0.elapsed().as_secs_f64();
        let max_rel = modes
            .frequencies_hz
            .iter()
            .zip(&model.fixed_frequencies_hz)
            .map(|(a, b)| ((a - b) / a).abs())
            .fold(0.0, f64::max);
        out["cross_check"] = json!({
            "fe_solve_modes_s": fe_s,
            "fe_status": format!("{:?}", modes.status),
            "max_rel_freq_diff": max_rel,
            "n_compared": modes.frequencies_hz.len().min(model.fixed_frequencies_hz.len()),
        });
    }
    println!("{}", serde_json::to_string_pretty(&out)?);
    Ok(())
}
