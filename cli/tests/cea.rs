//! System tests of `squeal cea`: every output on the tiny brake scene, the friction sweep and
//! its critical μ on a Hoffmann-type 2-DOF contact model (stored matrices + a gap table), and
//! transient ↔ CEA agreement on the same model just above μc.

mod common;
use common::{json, root, run, squeal, tmp};

use squeal_reduction::matrix::{MatrixForm, NamedMatrix};
use squeal_reduction::op4::{self, Op4WriteOptions};
use std::path::{Path, PathBuf};

/// The tiny brake scene with a `[cea]` table appended.
fn tiny_brake_with(dir: &Path, cea: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/transient/tiny-brake.toml")).unwrap();
    let p = dir.join("tiny-cea.toml");
    std::fs::write(&p, format!("{text}\n{cea}\n")).unwrap();
    p
}

/// Base64 (standard alphabet, `=` padding) to bytes.
fn base64_decode(text: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    } as u32;
    let clean: Vec<u8> = text.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    let mut out = Vec::new();
    for chunk in clean.chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let mut n = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            n |= (if c == b'=' { 0 } else { val(c) }) << (18 - 6 * i);
        }
        let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&bytes[..3 - pad]);
    }
    out
}

/// The text between the `<DataArray ... Name="name" ...>` tag and its `</DataArray>`.
fn data_array_text<'a>(vtu: &'a str, name: &str) -> &'a str {
    let at = vtu
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("no array {name}"));
    let start = at + vtu[at..].find('>').unwrap() + 1;
    let end = start + vtu[start..].find("</DataArray>").unwrap();
    &vtu[start..end]
}

/// A Float64 array of a binary VTU (squeal_meshes::vtu: base64 of a UInt64 byte count + data).
fn binary_f64(vtu: &str, name: &str) -> Vec<f64> {
    let bytes = base64_decode(data_array_text(vtu, name));
    let len = u64::from_le_bytes(bytes[..8].try_into().unwrap()) as usize;
    assert_eq!(len, bytes.len() - 8, "{name}: byte count");
    bytes[8..]
        .chunks(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

/// An ASCII array of a VTU.
fn ascii_f64(vtu: &str, name: &str) -> Vec<f64> {
    data_array_text(vtu, name)
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

/// `NumberOfPoints` of a VTU piece.
fn n_points(vtu: &str) -> usize {
    let at = vtu.find("NumberOfPoints=\"").unwrap() + "NumberOfPoints=\"".len();
    vtu[at..at + vtu[at..].find('"').unwrap()].parse().unwrap()
}

#[test]
fn cea_on_the_tiny_brake_writes_every_output() {
    let d = tmp("cea-tiny");
    let scene = tiny_brake_with(&d, "[cea]\nmax_frequency_hz = 2000.0\n");
    let out = d.join("run");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "cea"])
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .args(["--export-tangents", "--mu", "0.1:0.5:5"]));
    assert!(ok, "{stderr}");
    for f in [
        "cea.json",
        "summary.json",
        "scene.resolved.toml",
        "stability_map.png",
        "stability_map.svg",
        "cea_modes.vtu",
        "cea_modes_rotor.vtu",
        "cea_modes_pad.vtu",
        "tangents.op4",
        "tangents.pch",
        "cea.sweep.json",
        "root_locus.png",
        "root_locus.svg",
        "root_locus_mu.png",
        "root_locus_mu.svg",
        "cea_modes.pvd",
        "mode_shape_rotor.png",
        "mode_shape_rotor.svg",
    ] {
        let p = out.join(f);
        assert!(
            p.metadata().map(|m| m.len() > 0).unwrap_or(false),
            "{f} missing or empty"
        );
    }
    let cea = json(&out.join("cea.json"));
    let modes = cea["modes"].as_array().unwrap();
    assert!(!modes.is_empty());
    for m in modes {
        let (f, re) = (
            m["frequency_hz"].as_f64().unwrap(),
            m["real_part"].as_f64().unwrap(),
        );
        assert!((0.0..=2000.0).contains(&f), "{m}");
        // ζ = −2 Re p/|Im p| (the issue's definition), where Im p = 2πf.
        if let Some(z) = m["damping_ratio"].as_f64() {
            let expect = -2.0 * re / (2.0 * std::f64::consts::PI * f);
            assert!((z - expect).abs() <= 1e-9 * expect.abs().max(1.0), "{m}");
        }
        if m["unstable"].as_bool().unwrap() {
            assert!(re > 0.0, "{m}");
        }
    }
    // The state: full brake load (PMAX = 2 on a unit pad pressure over a unit face = total
    // normal force 2 from the load, as the scene says), sliding.
    let st = &cea["steady_state"];
    assert_eq!(st["source"]["kind"], "steady_state");
    assert!((st["source"]["load_factor"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert!(st["contact"]["min_slip_speed"].as_f64().unwrap() > 0.0);
    assert!(
        st["contact"]["min_pressure"].as_f64().unwrap() >= 1.0,
        "{st}"
    );
    // No spurious roots: as many modes as reduced DOFs minus constraints (none above 2 kHz here).
    let stats = &cea["stats"];
    assert_eq!(
        stats["n_reduced"].as_u64().unwrap(),
        stats["n"].as_u64().unwrap() - stats["n_constraints"].as_u64().unwrap()
    );
    // The unstable modes are written to the VTU as real/imaginary point arrays.
    let unstable = cea["unstable"].as_array().unwrap();
    assert!(
        !unstable.is_empty(),
        "the tiny brake at mu ≈ 0.45–0.5 has unstable modes"
    );
    let vtu = std::fs::read_to_string(out.join("cea_modes.vtu")).unwrap();
    let k = unstable[0].as_u64().unwrap();
    assert!(
        vtu.contains(&format!("Name=\"mode{k}_re\""))
            && vtu.contains(&format!("Name=\"mode{k}_im\""))
    );
    // The same shapes expanded to each component's full mesh: as many points as the mesh
    // (a 2×2×1 hex8 block in the scene: 3·3·2 = 18 nodes), and at the nodes that are grid
    // points of the reduced model the recovered values are the reduced eigenvector's (the
    // Craig–Bampton transformation is the identity on boundary DOFs), while interior nodes
    // carry the recovered motion: nonzero on the pad's free upper face, zero on the rotor's
    // clamped base (`fixed = [{ set = "z0" }]`, its only non-contact nodes).
    let grid_ids = ascii_f64(&vtu, "grid");
    let freq = modes[k as usize]["frequency_hz"].as_f64().unwrap();
    let stem = format!("mode{k}_{freq:.1}Hz");
    for comp in ["rotor", "pad"] {
        let full = std::fs::read_to_string(out.join(format!("cea_modes_{comp}.vtu"))).unwrap();
        assert_eq!(n_points(&full), 18, "{comp}");
        let grids = binary_f64(&full, "grid");
        assert_eq!(grids.len(), 18, "{comp}");
        let mut matched = 0;
        let mut interior_motion = 0.0f64;
        for part in ["re", "im"] {
            let red = ascii_f64(&vtu, &format!("mode{k}_{part}"));
            let vals = binary_f64(&full, &format!("{stem}_{part}"));
            assert_eq!(vals.len(), 3 * 18, "{comp} {part}");
            let scale = red.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(scale > 0.0);
            for (node, &g) in grids.iter().enumerate() {
                match grid_ids.iter().position(|&x| x == g) {
                    Some(p) => {
                        matched += 1;
                        for c in 0..3 {
                            let (a, b) = (vals[3 * node + c], red[3 * p + c]);
                            assert!(
                                (a - b).abs() <= 1e-12 * scale,
                                "{comp} grid {g} comp {c} {part}: full {a} vs reduced {b}"
                            );
                        }
                    }
                    None => {
                        for c in 0..3 {
                            interior_motion = interior_motion.max(vals[3 * node + c].abs());
                        }
                    }
                }
            }
        }
        // Every contact face node (3·3 per component) is a grid point, in both parts.
        assert_eq!(matched, 2 * 9, "{comp}");
        if comp == "pad" {
            assert!(interior_motion > 0.0, "pad: interior nodes not recovered");
        } else {
            assert_eq!(interior_motion, 0.0, "rotor: clamped base moves");
        }
    }
    // The exported tangents hold the named matrices with the model's sizes.
    let mats = op4::read(out.join("tangents.op4")).unwrap();
    let n = stats["n"].as_u64().unwrap() as usize;
    let ng = stats["n_constraints"].as_u64().unwrap() as usize;
    for (name, r, c) in [
        ("KR", n, n),
        ("MR", n, n),
        ("GC", ng, n),
        ("DFDL", n, ng),
        ("CF", n, n),
        ("HT", n, ng),
    ] {
        let m = mats
            .iter()
            .find(|m| m.name == name)
            .unwrap_or_else(|| panic!("{name}"));
        assert_eq!((m.nrows, m.ncols), (r, c), "{name}");
    }
    check_phase_animation(&out, &stem, unstable.len().min(20));
    let sweep = json(&out.join("cea.sweep.json"));
    assert_eq!(sweep["mu"].as_array().unwrap().len(), 5);
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["verb"], "cea");
    assert!(summary["mode_animation"]
        .as_str()
        .unwrap()
        .ends_with("cea_modes.pvd"));
    assert!(summary["rotor_face_figure"]
        .as_str()
        .unwrap()
        .ends_with("mode_shape_rotor.png"));
    assert_eq!(
        summary["n_unstable"].as_u64().unwrap() as usize,
        unstable.len()
    );

    // No [cea] and no --mu: an error that says how to ask.
    let plain = root().join("examples/transient/tiny-brake.toml");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "cea"])
        .arg(&plain)
        .arg("--out")
        .arg(d.join("none")));
    assert!(
        !ok && stderr.contains("[cea]") && stderr.contains("--mu"),
        "{stderr}"
    );
}

/// `cea_modes.pvd` groups, per phase θ_j = 2πj/24 (its `timestep`), one frame per component
/// (`part`), and each frame's array `stem` is Re(u e^{iθ}) = Re u cos θ − Im u sin θ of the
/// full-mesh shape in `cea_modes_<component>.vtu`, node by node; `n_modes` mode arrays per frame.
/// So θ = 0 shows Re u, θ = π/2 shows −Im u, and the amplitude over the cycle at each node is
/// |u| (max over the frames of |Re(u e^{iθ})| within the 15° sampling: ≥ cos(7.5°)·|u|).
fn check_phase_animation(out: &Path, stem: &str, n_modes: usize) {
    let pvd = std::fs::read_to_string(out.join("cea_modes.pvd")).unwrap();
    assert!(pvd.contains("type=\"Collection\""));
    let sets: Vec<&str> = pvd.split("<DataSet ").skip(1).collect();
    assert_eq!(sets.len(), 24 * 2, "24 phases x 2 components");
    let attr = |s: &str, key: &str| -> String {
        let at = s.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        s[at..at + s[at..].find('"').unwrap()].to_string()
    };
    let mut amp_seen: std::collections::HashMap<String, Vec<f64>> = Default::default();
    for (i, set) in sets.iter().enumerate() {
        let (j, part) = (i / 2, i % 2);
        let theta: f64 = attr(set, "timestep").parse().unwrap();
        assert!((theta - 2.0 * std::f64::consts::PI * j as f64 / 24.0).abs() < 1e-12);
        assert_eq!(attr(set, "part"), part.to_string());
        let comp = attr(set, "name");
        let frame = std::fs::read_to_string(out.join(attr(set, "file"))).unwrap();
        let full = std::fs::read_to_string(out.join(format!("cea_modes_{comp}.vtu"))).unwrap();
        assert_eq!(n_points(&frame), n_points(&full));
        // One 3-vector array per mode, and the points.
        assert_eq!(
            frame.matches("NumberOfComponents=\"3\"").count(),
            n_modes + 1
        );
        let re = binary_f64(&full, &format!("{stem}_re"));
        let im = binary_f64(&full, &format!("{stem}_im"));
        let u = binary_f64(&frame, stem);
        let scale = re.iter().chain(&im).fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..u.len() {
            let want = re[k] * theta.cos() - im[k] * theta.sin();
            assert!(
                (u[k] - want).abs() <= 1e-12 * scale,
                "{comp} frame {j} entry {k}"
            );
        }
        let amp = amp_seen.entry(comp).or_insert_with(|| vec![0.0; u.len()]);
        for k in 0..u.len() {
            amp[k] = amp[k].max(u[k].abs());
        }
    }
    for (comp, amp) in amp_seen {
        let full = std::fs::read_to_string(out.join(format!("cea_modes_{comp}.vtu"))).unwrap();
        let re = binary_f64(&full, &format!("{stem}_re"));
        let im = binary_f64(&full, &format!("{stem}_im"));
        for k in 0..amp.len() {
            let m = re[k].hypot(im[k]);
            assert!(amp[k] <= m * (1.0 + 1e-12) + 1e-300, "{comp} {k}");
            assert!(
                amp[k] >= m * (7.5f64.to_radians().cos()) - 1e-300,
                "{comp} {k}"
            );
        }
    }
}

/// Hoffmann-type 2-DOF mode-coupling model written as a stored reduced model: a pad point
/// (grid 1: tangential x, normal z) with springs k11 (x), k22 − k3 (z) and coupling k12,
/// pressed on a (nearly) massless rotor point (grid 2: z) held by a normal spring k3. The gap ties the
/// normal displacements, so the contact force is k3·z and friction (sliding along ±x) enters
/// the x-row as ∓μ k3 z: K = [[k11, k12 ∓ μk3], [k21, k22]] on (x, z), the issue's model.
/// Stiffnesses are scaled by `S` (frequencies × √S), damping by √S (so μc is unchanged).
const S: f64 = 1.0e4;

fn hoffmann(dir: &Path, c1: f64, c2: f64, pbrake_z: f64) {
    let (k11, k12, k22, k3) = (1.0, 0.3, 1.2, 1.0);
    let k = faer::Mat::from_fn(3, 3, |i, j| {
        S * [[k11, k12, 0.0], [k12, k22 - k3, 0.0], [0.0, 0.0, k3]][i][j]
    });
    // Normal mass split between the pad (1 − ε) and the rotor point (ε): the constrained
    // system has M = I; ε only adds μ·ε·z̈ to the friction force (μc moves by O(ε)).
    let eps = 1e-6;
    let m = faer::Mat::from_fn(3, 3, |i, j| {
        if i == j {
            [1.0, 1.0 - eps, eps][i]
        } else {
            0.0
        }
    });
    let b = faer::Mat::from_fn(3, 3, |i, j| {
        if i == j && i < 2 {
            S.sqrt() * [c1, c2][i]
        } else {
            0.0
        }
    });
    let p = faer::Mat::from_fn(3, 1, |i, _| if i == 1 { pbrake_z } else { 0.0 });
    let mats = [
        NamedMatrix::real("KR", k),
        NamedMatrix::real("MR", m),
        NamedMatrix::real("BR", b),
        NamedMatrix::real("PBRAKE", p).with_form(MatrixForm::Rectangular),
    ];
    let refs: Vec<&NamedMatrix> = mats.iter().collect();
    std::fs::write(
        dir.join("hoffmann.op4"),
        op4::write_bytes(&refs, &Op4WriteOptions::default()).unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("dofmap.json"),
        r#"{"dofs": [
            {"component": "pad", "kind": "grid", "grid": 1, "comp": 1},
            {"component": "pad", "kind": "grid", "grid": 1, "comp": 3},
            {"component": "rotor", "kind": "grid", "grid": 2, "comp": 3}]}"#,
    )
    .unwrap();
    // The gap at (0, −1, 0): the rotor turning about +z slides it along +x.
    std::fs::write(
        dir.join("gaps.csv"),
        "pad_grid,rotor_grid,x,y,z,nx,ny,nz,area,p0,temperature\n1,2,0,-1,0,0,0,1,1,1,0\n",
    )
    .unwrap();
}

fn hoffmann_scene(dir: &Path, name: &str, mu: f64, extra: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(
        &p,
        format!(
            r#"
[model]
from = "op4"
matrices = "hoffmann.op4"
dofmap = "dofmap.json"
gaps = "gaps.csv"

[friction]
law = {{ kind = "constant", mu = {mu} }}
vtol = 1e-6

[rotor]
rpm = 9549.296585513720    # |ω| = 1000 rad/s: |V_t| = 1000 = 1e9 VTOL (friction saturated)
axis = [0.0, 0.0, 1.0]

[loads]
pmax = 1.0
tload = 0.0

{extra}
"#
        ),
    )
    .unwrap();
    p
}

fn lowest_critical(out: &Path) -> (f64, serde_json::Value) {
    let s = json(&out.join("cea.sweep.json"));
    let c = s["couplings"][0].clone();
    (s["lowest_critical_mu"].as_f64().unwrap(), c)
}

/// Sweep on the Hoffmann model through squeal's contact formulation: the critical μ and the
/// merging pair. References (issue 5, analytic for this model): undamped μc = 1/3 with lock-in
/// ω = 1.048809 (× √S here); equal damping c = 0.05: μc = 0.34250; c1 = 0.1, c2 = 0: μc = 0.30000.
#[test]
fn sweep_finds_hoffmann_critical_mu_and_merging_pair() {
    let d = tmp("cea-hoffmann-sweep");
    for (c1, c2, mu_c) in [
        (0.0, 0.0, 1.0 / 3.0),
        (0.05, 0.05, 0.34250),
        (0.1, 0.0, 0.30000),
    ] {
        hoffmann(&d, c1, c2, 0.0);
        let scene = hoffmann_scene(
            &d,
            "sweep.toml",
            0.1,
            "[cea]\nfriction_damping = true\nsweep = { mu = [0.1, 0.6, 11] }\n",
        );
        let out = d.join(format!("run-{c1}-{c2}"));
        let (ok, _, stderr) = run(squeal()
            .args(["-q", "cea"])
            .arg(&scene)
            .arg("--out")
            .arg(&out));
        assert!(ok, "{stderr}");
        let (mu, c) = lowest_critical(&out);
        // A small model is swept exactly (dense): its onsets are crossings of exact roots.
        let sw = json(&out.join("cea.sweep.json"));
        assert_eq!(
            sw["lowest_critical_mu_in_band_status"], "exact_sweep",
            "{sw}"
        );
        assert!(
            (mu - mu_c).abs() < 1e-4,
            "c = ({c1}, {c2}): mu_c = {mu}, expected {mu_c}: {c}"
        );
        // The merging pair: two tracks whose frequencies approach each other.
        assert!(c["partner"].is_u64(), "{c}");
        if c1 == 0.0 && c2 == 0.0 {
            let f_lock = 1.048809 * S.sqrt() / (2.0 * std::f64::consts::PI);
            let f = c["frequency_hz"].as_f64().unwrap();
            assert!(
                (f - f_lock).abs() < 1e-4 * f_lock,
                "lock-in {f} Hz, expected {f_lock}"
            );
            let before = c["pair_frequencies_before_hz"].as_array().unwrap();
            let (fa, fb) = (before[0].as_f64().unwrap(), before[1].as_f64().unwrap());
            assert!((fa - fb).abs() < 0.1 * f_lock && fa != fb, "{c}");
        }
    }
}

/// Transient ↔ CEA: the Hoffmann model just above μc (undamped μc = 1/3; μ = 0.36) in the
/// linear regime (constant μ, saturated friction direction, bilateral contact: the BSQL
/// equations are linear in the perturbation), excited by a step normal load. The transient's
/// envelope growth rate equals the largest Re p within 2 % and its dominant frequency Im p/2π
/// within 0.5 % (issue 5, item 5).
#[test]
fn transient_growth_and_frequency_match_the_unstable_eigenvalue() {
    let d = tmp("cea-hoffmann-transient");
    hoffmann(&d, 0.0, 0.0, 1.0);
    let mu = 0.36;
    let scene = hoffmann_scene(
        &d,
        "above.toml",
        mu,
        "[cea]\n\n[transient]\ntfinal = 2.0\nrtol1 = 1e-8\natol1 = 1e-12\nnoutpt = 1\nnrstrt = 0\n\n[output]\ngrids = [1]\n",
    );
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "cea"])
        .arg(&scene)
        .arg("--out")
        .arg(d.join("cea")));
    assert!(ok, "{stderr}");
    let cea = json(&d.join("cea").join("cea.json"));
    let top = &cea["modes"][cea["unstable"][0].as_u64().unwrap() as usize];
    let (re, f) = (
        top["real_part"].as_f64().unwrap(),
        top["frequency_hz"].as_f64().unwrap(),
    );
    assert_eq!(cea["unstable"].as_array().unwrap().len(), 1, "{cea}");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "transient"])
        .arg(&scene)
        .arg("--out")
        .arg(d.join("tr")));
    assert!(ok, "{stderr}");
    let s = json(&d.join("tr").join("summary.json"));
    let g = s["growth_rate_per_s"].as_f64().unwrap();
    // Dominant frequency of the verdict's response (a velocity, zero mean about the steady
    // state) from its zero crossings over the second half of the run, when the stable partner
    // of the coalesced pair (Re p = −σ) has decayed by e^{−σ T/2}. The summary's
    // `dominant_frequency_hz` (spacing of the response's extremes over the whole window after
    // the ramp) is checked too; it once counted crossings of x − mean(x), biased on a growing
    // signal by O(σ/ω) (16.83 Hz here, +0.8 %).
    let (rows, cols, data) =
        squeal_pipeline::history::npy::read_npy(&d.join("tr").join("history.npy")).unwrap();
    let map = json(&d.join("tr").join("history_map.json"));
    let col = map["columns"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == s["response"])
        .unwrap()["column"]
        .as_u64()
        .unwrap() as usize;
    let (t, x): (Vec<f64>, Vec<f64>) = (0..rows)
        .map(|r| (data[r * cols], data[r * cols + col]))
        .filter(|&(t, _)| t > 1.0)
        .unzip();
    let crossings: Vec<f64> = (1..x.len())
        .filter(|&i| x[i - 1] * x[i] < 0.0)
        .map(|i| t[i - 1] + (t[i] - t[i - 1]) * x[i - 1] / (x[i - 1] - x[i]))
        .collect();
    let ft = (crossings.len() - 1) as f64 / (2.0 * (crossings[crossings.len() - 1] - crossings[0]));
    eprintln!(
        "CEA: Re p = {re}, f = {f}; transient: growth = {g}, f = {ft} (summary: {})",
        s["dominant_frequency_hz"]
    );
    assert!((g - re).abs() < 0.02 * re, "growth {g} vs Re p {re}");
    assert!((ft - f).abs() < 0.005 * f, "frequency {ft} vs {f}");
    let fs = s["dominant_frequency_hz"].as_f64().unwrap();
    assert!((fs - f).abs() < 0.005 * f, "summary frequency {fs} vs {f}");
}

/// `[[contact]] normal_stiffness` on the tiny brake: the CEA's in-band roots tend to the rigid
/// contact's as k_n grows, the error falling like 1/k_n (squeal_solver::bsql::compliance: the
/// compliant rows fold into K with the compliance c = 1/(k_n A)); the transient with the same
/// compliance closes its energy balance (the contact springs' energy stored); generalized-α
/// refuses it naming the key.
#[test]
fn normal_compliance_tends_to_rigid_contact_and_keeps_the_energy_balance() {
    let d = tmp("cea-compliance");
    let scene = tiny_brake_with(&d, "[cea]\nmax_frequency_hz = 100.0\n");
    let roots = |name: &str, kn: Option<f64>| -> Vec<(f64, f64)> {
        let out = d.join(name);
        let mut cmd = squeal();
        cmd.args(["-q", "cea"]).arg(&scene).arg("--out").arg(&out);
        if let Some(k) = kn {
            cmd.args(["--set", &format!("contact.0.normal_stiffness={k:e}")]);
        }
        let (ok, _, stderr) = run(&mut cmd);
        assert!(ok, "{stderr}");
        json(&out.join("cea.json"))["modes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| {
                (
                    m["real_part"].as_f64().unwrap(),
                    2.0 * std::f64::consts::PI * m["frequency_hz"].as_f64().unwrap(),
                )
            })
            .collect()
    };
    let rigid = roots("rigid", None);
    assert!(!rigid.is_empty());
    // The error of each rigid root against the nearest compliant one, relative to |p|.
    let err = |c: &[(f64, f64)]| {
        rigid
            .iter()
            .map(|&(re, im)| {
                c.iter()
                    .map(|&(r, i)| ((r - re).powi(2) + (i - im).powi(2)).sqrt())
                    .fold(f64::INFINITY, f64::min)
                    / (re * re + im * im).sqrt()
            })
            .fold(0.0, f64::max)
    };
    // The lining's own stiffness per area is E/t = 5e3/0.2 = 2.5e4: k_n = 1e7, 1e8 are 400
    // and 4000 times stiffer.
    let e7 = err(&roots("kn1e7", Some(1e7)));
    let e8 = err(&roots("kn1e8", Some(1e8)));
    println!(
        "tiny brake, {} in-band roots: max relative error k_n = 1e7: {e7:e}, 1e8: {e8:e}",
        rigid.len()
    );
    assert!(e8 < 1e-3, "{e8:e}");
    assert!((e7 / e8 - 10.0).abs() < 2.0, "{e7:e} / {e8:e}");

    // The transient with a soft contact (the contact springs matter): energy balance.
    let out = d.join("transient");
    let mut cmd = squeal();
    cmd.args(["-q", "transient"])
        .arg(&scene)
        .arg("--out")
        .arg(&out);
    for s in ["contact.0.normal_stiffness=2.5e4", "transient.tfinal=0.03"] {
        cmd.args(["--set", s]);
    }
    let (ok, _, stderr) = run(&mut cmd);
    assert!(ok, "{stderr}");
    let s = json(&out.join("summary.json"));
    let e = &s["energy"];
    let scale = [
        "friction_work",
        "external_work",
        "initial_energy",
        "damping_dissipated",
    ]
    .iter()
    .map(|k| e[k].as_f64().unwrap().abs())
    .fold(0.0, f64::max);
    let res = s["energy_residual"].as_f64().unwrap();
    println!("compliant transient: energy {e}, residual {res:e} of {scale:e}");
    assert!(
        res.abs() < 1e-3 * scale,
        "energy residual {res:e} vs {scale:e}"
    );
    assert_eq!(e["constraint_work"].as_f64().unwrap(), 0.0, "{e}");

    // Generalized-α carries the rigid constraint only.
    let mut cmd = squeal();
    cmd.args(["-q", "transient"])
        .arg(&scene)
        .arg("--out")
        .arg(d.join("ga"));
    for s in [
        "contact.0.normal_stiffness=2.5e4",
        "transient.integrator=generalized_alpha",
    ] {
        cmd.args(["--set", s]);
    }
    let (ok, _, stderr) = run(&mut cmd);
    assert!(!ok);
    assert!(stderr.contains("contact[0].normal_stiffness"), "{stderr}");
}
