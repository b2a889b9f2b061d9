//! Benchmark: 50 modes of a free-free hex20 brake-rotor-like annulus (~100k DOFs).
//!
//! Build and run (not under `cargo test`):
//!   cargo build --release -p squeal-fe --example bench_modal
//!   target/release/examples/bench_modal [OUT.json] [--clamped] [--block B] [--basis M] [--tol T]
//! Writes n_dofs, nnz, timings, peak RSS (VmHWM) and the frequencies as JSON
//! (default `target/bench/modal.json`).

use squeal_fe::*;
use squeal_meshes::structured::annulus_mesh;
use squeal_meshes::CellKind;
use std::time::Instant;

fn peak_rss_mb() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let clamped = args.iter().any(|a| a == "--clamped");
    let out = args
        .iter()
        .enumerate()
        .find(|(i, a)| {
            !a.starts_with("--")
                && (*i == 0 || !args[i - 1].starts_with("--b") && !args[i - 1].starts_with("--t"))
        })
        .map(|(_, a)| a)
        .cloned()
        .unwrap_or_else(|| "target/bench/modal.json".to_string());
    let t0 = Instant::now();
    // Solid rotor: r 0.07..0.15 m, 25 mm thick, 144 x 12 x 4 hex20.
    let (r_in, r_out, h, nc, nr, nt) = (0.07, 0.15, 0.025, 144, 12, 4);
    let mesh = annulus_mesh(r_in, r_out, h, nc, nr, nt, CellKind::Hex20);
    let mesh_s = t0.elapsed().as_secs_f64();
    let dofs = if clamped {
        DofMap::from_node_sets(&mesh, &[("hub", [true, true, true])])?
    } else {
        DofMap::new(mesh.nodes.len(), &[])?
    };
    let mat = Material::steel_si();
    let asm = assemble(&mesh, &[mat], &dofs, &AssemblyOptions::default())?;
    let flag = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse::<f64>().ok())
    };
    let mut opts = ModalOptions {
        n_modes: Some(50),
        ..Default::default()
    };
    if let Some(b) = flag("--block") {
        opts.block_size = b as usize;
    }
    if let Some(m) = flag("--basis") {
        opts.max_basis = m as usize;
    }
    if let Some(t) = flag("--tol") {
        opts.tol = t;
    }
    let modes = solve_modes(&asm.k, &asm.m, &opts)?;
    let total_s = t0.elapsed().as_secs_f64();
    let report = serde_json::json!({
        "case": format!("annulus hex20 r {r_in}..{r_out} m, h {h} m, {nc}x{nr}x{nt}, steel, {}",
                        if clamped { "hub clamped" } else { "free-free" }),
        "n_nodes": mesh.nodes.len(),
        "n_elements": asm.stats.n_elements,
        "n_dofs": dofs.n_free(),
        "nnz_k": asm.stats.nnz_k,
        "nnz_m": asm.stats.nnz_m,
        "mesh_s": mesh_s,
        "assembly_s": asm.stats.total_s,
        "assembly": asm.stats,
        "factor_s": modes.stats.factor_s,
        "lanczos_s": modes.stats.lanczos_s,
        "modal": modes.stats,
        "status": modes.status,
        "total_s": total_s,
        "peak_rss_mb": peak_rss_mb(),
        "threads": rayon::current_num_threads(),
        "frequencies_hz": modes.frequencies_hz,
    });
    if let Some(dir) = std::path::Path::new(&out).parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(&out, serde_json::to_string_pretty(&report)?)?;
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}
