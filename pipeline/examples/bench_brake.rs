//! Brake-sized benchmark: mesh → assembly → Craig–Bampton of every component of a scene
//! (default `examples/cad-brake/brake.toml`: a ~280k-DOF hex20 hat rotor and two pads),
//! with the wall time and peak resident memory (VmHWM, as getrusage's maxrss) of each stage.
//!
//! ```text
//! cargo build --release -p squeal-pipeline --example bench_brake
//! target/release/examples/bench_brake [SCENE.toml] [--set key=value ...] [--out FILE.json]
//!                                     [--rotor-boundary nearest|faces] [--ordering nd|amd]
//!                                     [--lanczos-max-dim N]
//! target/release/examples/bench_brake --pipeline [SCENE.toml] [--set key=value ...]
//!                                     [--sweep N] [--out FILE.json]
//! ```
//!
//! `--pipeline` runs the pipeline itself instead: `stages::model::build_from_mesh` (mesh →
//! assembly → Craig–Bampton of the components in parallel → superelement assembly → surface
//! pairing → gaps; the scene's own contact boundary, e.g. with
//! `--set components.0.interface.degree=6` for an interface-reduced rotor), then the CEA at
//! the steady state (`stages::cea::compute`) and, with `--sweep N`, an N-point μ sweep
//! (0.1…0.9) of the reduced model in the same call, as `squeal cea SCENE --mu 0.1:0.9:N` runs
//! them (`cea_s` is that call's time less the sweep's own `stats.time_s`); each timed, with
//! the peak memory after each.
//!
//! The Craig–Bampton boundary is what a pad/rotor contact pairing makes it: every node of each
//! pad's `friction` face (one gap each), and on the rotor either (`--rotor-boundary nearest`,
//! the default) the rotor friction-face node nearest to each pad node — one rotor node per
//! gap, as the coincident-node pairing has — or (`--rotor-boundary faces`) every node of the
//! rotor friction quads under a pad (centroid within one quad diameter of a pad friction-face
//! node), what a projection onto the faces makes boundary. Both counts are reported.
//! `--ordering amd` factorises K_ii in faer's AMD order instead of squeal's nested dissection
//! (what the pipeline uses from 20 000 interior DOFs). Components run one after the other (the pipeline runs them in parallel), so each stage's
//! time is its own. Writes the JSON document to `--out` (default:
//! `docs/bench/brake_sized.json` under the workspace) and prints it.

use serde_json::json;
use squeal_fe::{assemble, AssemblyOptions, DofMap};
use squeal_meshes::Mesh;
use squeal_pipeline::model::mesh::fixed_dofs;
use squeal_pipeline::output::RunDir;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::scene::Scene;
use squeal_pipeline::stages::mesh::mesh_component;
use squeal_reduction::cb::{self, peak_rss_kib};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn face_nodes(mesh: &Mesh, name: &str) -> Vec<usize> {
    mesh.faces.get(name).map(|b| b.nodes()).unwrap_or_default()
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum()
}

/// Rotor nodes of the quads of `faces` under any of `pad_points`: a quad whose centroid is
/// within its own diameter (corner to opposite corner) of a pad point.
fn rotor_nodes_under(mesh: &Mesh, faces: &[&str], pad_points: &[[f64; 3]]) -> Vec<usize> {
    let mut out = Vec::new();
    for name in faces {
        let Some(block) = mesh.faces.get(*name) else {
            continue;
        };
        for face in block.iter() {
            let cell = face.nodes;
            let corners: Vec<[f64; 3]> = cell[..4].iter().map(|&n| mesh.nodes[n]).collect();
            let mut c = [0.0; 3];
            for p in &corners {
                for k in 0..3 {
                    c[k] += 0.25 * p[k];
                }
            }
            let diam2 = dist2(corners[0], corners[2]).max(dist2(corners[1], corners[3]));
            if pad_points.iter().any(|&p| dist2(p, c) <= diam2) {
                out.extend_from_slice(cell);
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// For each pad point, the nearest node of the quads of `faces` (deduplicated).
fn nearest_nodes(mesh: &Mesh, faces: &[&str], pad_points: &[[f64; 3]]) -> Vec<usize> {
    let mut cand = Vec::new();
    for f in faces {
        cand.extend(face_nodes(mesh, f));
    }
    let mut out: Vec<usize> = pad_points
        .iter()
        .filter_map(|&p| {
            cand.iter()
                .copied()
                .min_by(|&a, &b| dist2(mesh.nodes[a], p).total_cmp(&dist2(mesh.nodes[b], p)))
        })
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let _ = load_at_start();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut args = std::env::args().skip(1);
    let mut scene_path = root.join("examples/cad-brake/brake.toml");
    let mut out_path = root.join("docs/bench/brake_sized.json");
    let mut sets = Vec::new();
    let mut rotor_boundary = "nearest".to_string();
    let mut ordering = "nd".to_string();
    let mut lanczos_max_dim: Option<usize> = None;
    let (mut pipeline, mut sweep) = (false, None::<usize>);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--pipeline" => pipeline = true,
            "--sweep" => sweep = Some(args.next().ok_or("--sweep needs N")?.parse()?),
            "--set" => sets.push(args.next().ok_or("--set needs key=value")?),
            "--out" => out_path = PathBuf::from(args.next().ok_or("--out needs a file")?),
            "--lanczos-max-dim" => {
                lanczos_max_dim = Some(args.next().ok_or("--lanczos-max-dim needs N")?.parse()?)
            }
            "--ordering" => ordering = args.next().ok_or("--ordering needs amd or nd")?,
            "--rotor-boundary" => {
                rotor_boundary = args
                    .next()
                    .ok_or("--rotor-boundary needs nearest or faces")?
            }
            _ => scene_path = PathBuf::from(a),
        }
    }
    let start = Instant::now();
    let scene = Scene::load(&scene_path, &sets)?;
    let work = std::env::temp_dir().join(format!("squeal-bench-brake-{}", std::process::id()));
    let dir = RunDir::create(&work)?;
    let progress = Progress::quiet();
    if pipeline {
        let out = run_pipeline(&scene, &dir, &progress, sweep, start)?;
        let mut out = out;
        out["scene"] = json!(scene_path
            .strip_prefix(&root)
            .unwrap_or(&scene_path)
            .display()
            .to_string());
        out["overrides"] = json!(sets);
        let text = serde_json::to_string_pretty(&out)?;
        if let Some(d) = out_path.parent() {
            std::fs::create_dir_all(d)?;
        }
        std::fs::write(&out_path, &text)?;
        println!("{text}");
        let _ = std::fs::remove_dir_all(&work);
        return Ok(());
    }

    // Mesh every component first (the rotor's boundary depends on the pads' faces).
    let mut meshes = Vec::new();
    let mut mesh_rows = Vec::new();
    for c in &scene.components {
        let t0 = Instant::now();
        let (mesh, report) = mesh_component(&scene, c, &dir, &progress)?;
        let wall = t0.elapsed().as_secs_f64();
        mesh_rows.push(json!({
            "component": c.name, "n_nodes": report.n_nodes, "n_cells": report.n_cells,
            "gmsh_s": report.gmsh_s, "mesh_total_s": wall,
            "read_s": wall - report.gmsh_s.unwrap_or(0.0),
            "peak_rss_kib": peak_rss_kib(),
        }));
        meshes.push(mesh);
    }
    let mut pad_points = Vec::new();
    for m in &meshes {
        for n in face_nodes(m, "friction") {
            pad_points.push(m.nodes[n]);
        }
    }

    // Closest pair of pad and rotor friction-face nodes (0 would be a coincident node).
    let mut rotor_face_points = Vec::new();
    for m in &meshes {
        for f in ["friction_in", "friction_out"] {
            rotor_face_points.extend(face_nodes(m, f).iter().map(|&n| m.nodes[n]));
        }
    }
    let min_pad_rotor_distance = pad_points
        .iter()
        .flat_map(|&p| rotor_face_points.iter().map(move |&q| dist2(p, q)))
        .fold(f64::INFINITY, f64::min)
        .sqrt();

    let red = scene.reduction.clone().unwrap_or_default();
    let mut cb_opts = red.cb_options();
    if let Some(d) = lanczos_max_dim {
        cb_opts.lanczos_max_dim = d;
    }
    let mut rows = Vec::new();
    let mut rotor_boundary_counts = None;
    let (mut n_full, mut n_reduced, mut n_gap_nodes) = (0usize, 0usize, 0usize);
    for (c, mesh) in scene.components.iter().zip(&meshes) {
        let bnodes = if mesh.faces.contains_key("friction") {
            let v = face_nodes(mesh, "friction");
            n_gap_nodes += v.len();
            v
        } else {
            let faces = rotor_nodes_under(mesh, &["friction_in", "friction_out"], &pad_points);
            let nearest = nearest_nodes(mesh, &["friction_in", "friction_out"], &pad_points);
            rotor_boundary_counts = Some((nearest.len(), faces.len()));
            match rotor_boundary.as_str() {
                "faces" => faces,
                _ => nearest,
            }
        };
        let t0 = Instant::now();
        let fixed = fixed_dofs(c, mesh)?;
        let dofs = DofMap::new(mesh.nodes.len(), &fixed)?;
        let materials = c.block_materials(mesh)?;
        let asm = assemble(
            mesh,
            &materials,
            &dofs,
            &AssemblyOptions {
                hex8: c.hex8,
                ..Default::default()
            },
        )?;
        let assembly_s = t0.elapsed().as_secs_f64();
        let rss_assembly = peak_rss_kib();
        let boundary: Vec<usize> = bnodes
            .iter()
            .flat_map(|&n| (0..3).map(move |k| (n, k)))
            .filter_map(|(n, k)| dofs.free(n, k))
            .collect();
        let t0 = Instant::now();
        let coords = squeal_fe::dof_coordinates(mesh, &dofs);
        let coords = (ordering != "amd").then_some(coords.as_slice());
        let model = cb::reduce_ordered(&asm.k, &asm.m, None, &boundary, &cb_opts, coords)?;
        let cb_s = t0.elapsed().as_secs_f64();
        n_full += dofs.n_free();
        n_reduced += model.n_reduced();
        eprintln!(
            "{}: {} DOFs, nnz(K) {}, {} boundary DOFs, {} modes to {:.0} Hz: assembly {:.1} s, CB {:.1} s",
            c.name,
            dofs.n_free(),
            asm.k.val().len(),
            boundary.len(),
            model.n_modes,
            model.fixed_frequencies_hz.last().copied().unwrap_or(0.0),
            assembly_s,
            cb_s
        );
        rows.push(json!({
            "component": c.name,
            "n_dofs": dofs.n_free(),
            "nnz_k": asm.k.val().len(),
            "n_boundary_dofs": boundary.len(),
            "n_modes": model.n_modes,
            "highest_fixed_interface_hz": model.fixed_frequencies_hz.last(),
            "assembly_s": assembly_s,
            "peak_rss_kib_after_assembly": rss_assembly,
            "craig_bampton_s": cb_s,
            "cb_stats": serde_json::to_value(&model.stats)?,
        }));
    }
    let total_s = start.elapsed().as_secs_f64();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let out = json!({
        "what": "mesh (gmsh on each .geo) -> assembly -> Craig-Bampton of every component, one after the other",
        "scene": scene_path.strip_prefix(&root).unwrap_or(&scene_path).display().to_string(),
        "overrides": sets,
        "frequency_of_interest_hz": red.frequency_of_interest_hz,
        "n_full_dofs": n_full,
        "n_pad_friction_nodes": n_gap_nodes,
        "rotor_boundary": rotor_boundary,
        "ordering_asked": ordering,
        "rotor_boundary_nodes_nearest_and_faces": rotor_boundary_counts,
        "min_pad_rotor_friction_node_distance": min_pad_rotor_distance,
        "n_reduced_dofs": n_reduced,
        "mesh": mesh_rows,
        "components": rows,
        "total_s": total_s,
        "peak_rss_kib": peak_rss_kib(),
        "threads": rayon::current_num_threads(),
        "loadavg_at_end": load.trim(),
    });
    let text = serde_json::to_string_pretty(&out)?;
    if let Some(d) = out_path.parent() {
        std::fs::create_dir_all(d)?;
    }
    std::fs::write(&out_path, &text)?;
    println!("{text}");
    let _ = std::fs::remove_dir_all(&work);
    Ok(())
}

/// `--pipeline`: the reduced model as the pipeline builds it, then the CEA (and a sweep).
fn run_pipeline(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    sweep: Option<usize>,
    start: Instant,
) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    use squeal_pipeline::stages::cea::{self, CeaArgs};
    use squeal_pipeline::stages::model::build_from_mesh;
    let t0 = Instant::now();
    let model = build_from_mesh(scene, dir, progress)?;
    let build_s = t0.elapsed().as_secs_f64();
    let rss_build = peak_rss_kib();
    let cpu_build = process_cpu_s();
    eprintln!(
        "model: {} reduced DOFs, {} gaps, built in {build_s:.1} s (peak {:?} KiB)",
        model.n(),
        model.gap_geometry.len(),
        rss_build
    );
    let components: Vec<serde_json::Value> = model
        .components
        .iter()
        .map(|c| {
            json!({
                "component": c.name, "n_free_dofs": c.n_free_dofs, "n_nodes": c.n_nodes,
                "n_boundary_coords": c.cb_stats.as_ref().map(|s| s.n_boundary), "n_modes": c.n_modes,
                "highest_fixed_interface_hz": c.fixed_interface_hz.last(),
                "fixed_interface_hz": c.fixed_interface_hz,
                "cb_stats": c.cb_stats,
            })
        })
        .collect();
    // The CEA and, with --sweep, the sweep in one call, as `squeal cea SCENE --mu A:B:N`
    // runs them (one steady state, one CEA with its sensitivities, then the sweep).
    let t0 = Instant::now();
    let args = CeaArgs {
        mu: sweep.map(|n| (0.1, 0.9, n)),
        ..Default::default()
    };
    let c = cea::compute(scene, &model, progress, &args)?;
    let cea_and_sweep_s = t0.elapsed().as_secs_f64();
    let sweep_s = c.sweep.as_ref().map(|r| r.stats.time_s);
    let cea_s = cea_and_sweep_s - sweep_s.unwrap_or(0.0);
    let rss_cea = peak_rss_kib();
    let cpu_cea = process_cpu_s();
    let unstable: Vec<serde_json::Value> = c
        .unstable()
        .iter()
        .map(|(_, m)| json!({"frequency_hz": m.eigenvalue.im.abs() / (2.0 * std::f64::consts::PI), "real_part": m.eigenvalue.re}))
        .collect();
    eprintln!(
        "CEA: {cea_s:.1} s, {} modes in the band, {} unstable",
        c.modes.len(),
        unstable.len()
    );
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let load_at_start = load_at_start();
    let mut out = json!({
        "loadavg_at_start": load_at_start,
        "what": "pipeline: build_from_mesh (mesh -> assembly -> Craig-Bampton of the components in parallel -> superelement assembly -> gaps), then CEA at the steady state (and a mu sweep)",
        "n_reduced_dofs": model.n(),
        "n_gaps": model.gap_geometry.len(),
        "n_recovered_grid_dofs": model.dofs.recovered.len(),
        "build_s": build_s,
        "peak_rss_kib_after_build": rss_build,
        "components": components,
        "checks": model.checks.iter().map(|(name, c)| json!({"component": name, "check": c})).collect::<Vec<_>>(),
        "warnings": model.warnings,
        "cea_s": cea_s,
        "peak_rss_kib_after_cea": rss_cea,
        "cea_stats": c.out.stats,
        "n_modes_in_band": c.modes.len(),
        "unstable": unstable,
        "roots_in_band": c
            .modes
            .iter()
            .map(|m| [m.eigenvalue.im.abs() / (2.0 * std::f64::consts::PI), m.eigenvalue.re])
            .collect::<Vec<_>>(),
        "contact_force_sum": c.lin.lambda_dot.iter().sum::<f64>(),
        "contact_force_norm": c.lin.lambda_dot.iter().map(|x| x * x).sum::<f64>().sqrt(),
        "contact_forces": c.lin.lambda_dot,
        "sensitivity_s": c.out.sensitivity.as_ref().map(|s| json!({
            "all": s.time_s, "triplets": s.time_triplets_s, "derivatives": s.time_derivatives_s,
            "products": s.time_products_s, "factorisation": s.triplet_factorisation,
            "n_roots": s.roots.len(), "n_parameters": s.parameters.len(),
        })),
        "sweep": null,
        "sweep_s": sweep_s,
        "cea_and_sweep_s": cea_and_sweep_s,
        "mesh_to_cea_s": build_s + cea_s,
        "process_cpu_s_after_build": cpu_build,
        "process_cpu_s_after_cea": cpu_cea,
        "total_s": start.elapsed().as_secs_f64(),
        "peak_rss_kib": peak_rss_kib(),
        "threads": rayon::current_num_threads(),
        "loadavg_at_end": load.trim(),
    });
    if let Some((n, r)) = sweep.zip(c.sweep.as_ref()) {
        // The in-band onsets with how each was found (exact crossing or not).
        let band = r.band_hz.unwrap_or(f64::INFINITY);
        let onsets: Vec<_> = r
            .tracks
            .iter()
            .filter_map(|t| t.critical.as_ref())
            .filter(|c| c.frequency_hz <= band)
            .map(|c| {
                json!({
                    "mu": c.mu, "mu_located": c.mu_located, "frequency_hz": c.frequency_hz,
                    "exact_converged": c.exact.as_ref().map(|x| x.converged),
                    "exact_max_real_part_error": c.exact.as_ref().map(|x| x.max_real_part_error),
                })
            })
            .collect();
        out["sweep"] = json!({
            "n_points": n, "lowest_critical_mu": r.lowest_critical_mu,
            "lowest_critical_mu_in_band": r.lowest_critical_mu_in_band,
            "lowest_critical_mu_in_band_status": r.lowest_critical_mu_in_band_status,
            "in_band_onsets": onsets,
            "stats": r.stats,
        });
        out["total_s"] = json!(start.elapsed().as_secs_f64());
        out["process_cpu_s_after_sweep"] = json!(process_cpu_s());
        out["peak_rss_kib"] = json!(peak_rss_kib());
        let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
        out["loadavg_at_end"] = json!(load.trim());
    }
    Ok(out)
}

/// The load average when the process started (first call), as /proc/loadavg prints it.
fn load_at_start() -> String {
    static START: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    START
        .get_or_init(|| {
            std::fs::read_to_string("/proc/loadavg")
                .unwrap_or_default()
                .trim()
                .to_string()
        })
        .clone()
}

/// CPU seconds (user + system, all threads) of this process so far, from /proc/self/stat
/// (fields 14 and 15, in USER_HZ = 100 ticks per second on Linux); None elsewhere. On a shared
/// machine the wall times measure the load; this measures the work.
fn process_cpu_s() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = &s[s.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}
