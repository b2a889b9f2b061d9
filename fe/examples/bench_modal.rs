//! Benchmark: 50 modes of a free-free hex20 brake-rotor-like annulus (~100k DOFs), with the
//! AMD and the nested-dissection orderings of the factorisation, in the same run.
//!
//! Build and run (not under `cargo test`):
//!   cargo build --release -p squeal-fe --example bench_modal
//!   target/release/examples/bench_modal [OUT.json] [--clamped] [--block B] [--basis M]
//!       [--tol T] [--leaf L] [--repeat R] [--only amd|nd] [--modes N] [--export DIR] [--no-split]
//! `--export DIR` also writes K and M (CSC: `k_indptr.npy`, `k_indices.npy`, `k_data.npy`, the
//! same for `m_`) and `meta.json` (the shift σ, the frequencies) for a peer solver on the same
//! matrices (`docs/bench/modal_peer.py`).
//! Each repeat solves once per ordering (alternating which goes first, since the machine is
//! shared) and records nnz(L), ordering/factor/Lanczos/solve/total seconds and the peak RSS of
//! that solve (VmHWM, reset before each solve). Writes JSON (default `target/bench/modal.json`)
//! with every run, the per-ordering medians and the AMD/ND ratios.

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

/// User + system CPU seconds of the process so far (all threads), from /proc/self/stat
/// (assumes 100 clock ticks per second).
fn cpu_s() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = &s[s.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Resets VmHWM to the current RSS (Linux ≥ 4.0); false if not possible.
fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    if v.is_empty() {
        return f64::NAN;
    }
    let k = v.len() / 2;
    if v.len() % 2 == 1 {
        v[k]
    } else {
        0.5 * (v[k - 1] + v[k])
    }
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let clamped = args.iter().any(|a| a == "--clamped");
    let valued = [
        "--block", "--basis", "--tol", "--leaf", "--repeat", "--only", "--modes", "--export",
    ];
    let out = args
        .iter()
        .enumerate()
        .find(|(i, a)| !a.starts_with("--") && (*i == 0 || !valued.contains(&args[i - 1].as_str())))
        .map(|(_, a)| a)
        .cloned()
        .unwrap_or_else(|| "target/bench/modal.json".to_string());
    let flag = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let num = |name: &str| flag(name).and_then(|v| v.parse::<f64>().ok());
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
    let coords = dof_coordinates(&mesh, &dofs);
    let mut base = ModalOptions {
        n_modes: Some(num("--modes").map_or(50, |m| m as usize)),
        ..Default::default()
    };
    if let Some(b) = num("--block") {
        base.block_size = b as usize;
    }
    if let Some(m) = num("--basis") {
        base.max_basis = m as usize;
    }
    if let Some(t) = num("--tol") {
        base.tol = t;
    }
    if args.iter().any(|a| a == "--no-split") {
        base.split_factor = false;
    }
    if let Some(l) = num("--leaf") {
        base.nested_dissection.leaf_nodes = l as usize;
    }
    let repeat = num("--repeat").map_or(1, |r| r.max(1.0) as usize);
    let orderings: Vec<(&str, FillOrdering)> = match flag("--only").as_deref() {
        Some("amd") => vec![("amd", FillOrdering::Amd)],
        Some("nd") => vec![("nested_dissection", FillOrdering::NestedDissection)],
        _ => vec![
            ("nested_dissection", FillOrdering::NestedDissection),
            ("amd", FillOrdering::Amd),
        ],
    };

    if args.iter().any(|a| a == "--fill-only") {
        // Symbolic factorisations only: fill and flops of AMD and of ND per leaf size.
        let t = Instant::now();
        let amd = squeal_fe::ordering::cholesky_fill(asm.k.symbolic(), None)?;
        let mut rows = vec![serde_json::json!({"ordering": "amd", "fill": amd,
                                               "symbolic_s": t.elapsed().as_secs_f64()})];
        for leaf in [16, 32, 64, 96, 128, 192, 256, 384] {
            let o = NestedDissectionOptions {
                leaf_nodes: leaf,
                ..base.nested_dissection
            };
            let (p, nd) = nested_dissection(asm.k.symbolic(), &coords, &o)?;
            let fill = squeal_fe::ordering::cholesky_fill(asm.k.symbolic(), Some(&p))?;
            rows.push(
                serde_json::json!({"ordering": "nested_dissection", "leaf_nodes": leaf,
                                         "fill": fill, "nd": nd}),
            );
        }
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    let mut runs = Vec::new();
    let mut freqs: Vec<(String, Vec<f64>)> = Vec::new();
    for r in 0..repeat {
        let mut order = orderings.clone();
        if r % 2 == 1 {
            order.reverse();
        }
        for (name, ord) in order {
            let opts = ModalOptions {
                ordering: ord,
                ..base.clone()
            };
            let rss_reset = reset_peak_rss();
            let (t, c0) = (Instant::now(), cpu_s());
            let modes = solve_modes_with(&asm.k, &asm.m, &opts, Some(&coords))?;
            let solve_total = t.elapsed().as_secs_f64();
            let cpu = c0.zip(cpu_s()).map(|(a, b)| b - a);
            let s = &modes.stats;
            eprintln!(
                "repeat {r} {name}: nnz(L) {} factor {:.2} s lanczos {:.2} s (solves {:.2} s) \
                 total {:.2} s (cpu {:.2} s), residual {:.1e}",
                s.factor_nnz,
                s.factor_s,
                s.lanczos_s,
                s.solve_s,
                solve_total,
                cpu.unwrap_or(f64::NAN),
                s.max_residual
            );
            runs.push(serde_json::json!({
                "repeat": r,
                "ordering": name,
                "factor_nnz": s.factor_nnz,
                "ordering_s": s.ordering_s,
                "factor_s": s.factor_s,
                "lanczos_s": s.lanczos_s,
                "solve_s": s.solve_s,
                "total_s": solve_total,
                "cpu_s": cpu,
                "peak_rss_mb": if rss_reset { peak_rss_mb() } else { None },
                "status": modes.status,
                "modal": modes.stats,
            }));
            if r == 0 {
                freqs.push((name.to_string(), modes.frequencies_hz.clone()));
            }
        }
    }
    let mut summary = serde_json::Map::new();
    let pick = |name: &str, key: &str| -> Vec<f64> {
        runs.iter()
            .filter(|x| x["ordering"] == name)
            .filter_map(|x| x[key].as_f64())
            .collect()
    };
    let keys = [
        "factor_nnz",
        "ordering_s",
        "factor_s",
        "lanczos_s",
        "solve_s",
        "total_s",
        "cpu_s",
        "peak_rss_mb",
    ];
    for (name, _) in &orderings {
        let mut m = serde_json::Map::new();
        for key in keys {
            m.insert(key.to_string(), serde_json::json!(median(pick(name, key))));
        }
        summary.insert(format!("median_{name}"), m.into());
    }
    if orderings.len() == 2 {
        let mut ratio = serde_json::Map::new();
        for key in keys {
            let a = median(pick("amd", key));
            let n = median(pick("nested_dissection", key));
            ratio.insert(key.to_string(), serde_json::json!(a / n));
        }
        summary.insert("ratio_amd_over_nd".to_string(), ratio.into());
        let (fa, fb) = (&freqs[0].1, &freqs[1].1);
        let max_rel = fa
            .iter()
            .zip(fb)
            .filter(|(a, _)| a.abs() > 1.0)
            .map(|(a, b)| ((a - b) / a).abs())
            .fold(0.0, f64::max);
        summary.insert(
            "max_rel_frequency_difference_elastic".to_string(),
            serde_json::json!(max_rel),
        );
    }
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
        "options": base,
        "threads": rayon::current_num_threads(),
        "summary": summary,
        "runs": runs,
        "frequencies_hz": freqs[0].1,
        "frequencies_ordering": freqs[0].0,
        "wall_s": t0.elapsed().as_secs_f64(),
    });
    if let Some(dir) = std::path::Path::new(&out).parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(&out, serde_json::to_string_pretty(&report)?)?;
    if let Some(dir) = flag("--export") {
        let dir = std::path::Path::new(&dir);
        std::fs::create_dir_all(dir)?;
        for (name, a) in [("k", &asm.k), ("m", &asm.m)] {
            let s = a.symbolic();
            let ptr: Vec<i64> = s.col_ptr().iter().map(|&p| p as i64).collect();
            let idx: Vec<i64> = s.row_idx().iter().map(|&i| i as i64).collect();
            npy::write_i64(&dir.join(format!("{name}_indptr.npy")), &ptr)?;
            npy::write_i64(&dir.join(format!("{name}_indices.npy")), &idx)?;
            npy::write_f64(&dir.join(format!("{name}_data.npy")), a.val())?;
        }
        let shift = runs[0]["modal"]["shift"].clone();
        let meta = serde_json::json!({
            "n": dofs.n_free(),
            "shift": shift,
            "n_modes": base.n_modes,
            "tol": base.tol,
            "report": report,
        });
        std::fs::write(dir.join("meta.json"), serde_json::to_string_pretty(&meta)?)?;
    }
    println!("{}", serde_json::to_string_pretty(&report["summary"])?);
    Ok(())
}

/// Minimal `.npy` (format 1.0) writers for one-dimensional little-endian arrays.
mod npy {
    use std::io::Write;
    fn write(path: &std::path::Path, descr: &str, n: usize, bytes: &[u8]) -> std::io::Result<()> {
        let mut header =
            format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({n},), }}");
        // Magic (6) + version (2) + header length (2) + header, padded to 64 bytes with '\n'.
        let total = (10 + header.len() + 1).div_ceil(64) * 64;
        while 10 + header.len() + 1 < total {
            header.push(' ');
        }
        header.push('\n');
        let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
        f.write_all(b"\x93NUMPY\x01\x00")?;
        f.write_all(&(header.len() as u16).to_le_bytes())?;
        f.write_all(header.as_bytes())?;
        f.write_all(bytes)?;
        f.flush()
    }
    pub fn write_f64(path: &std::path::Path, v: &[f64]) -> std::io::Result<()> {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        write(path, "<f8", v.len(), &bytes)
    }
    pub fn write_i64(path: &std::path::Path, v: &[i64]) -> std::io::Result<()> {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        write(path, "<i8", v.len(), &bytes)
    }
}
