//! `squeal compare`: the tiny brake's reduced model against itself (no difference, exit 0) and
//! against a copy with one KR diagonal entry raised by 5 % (the matrix norm is exactly that
//! change, the frequency table shows the shift a Rayleigh-quotient perturbation estimate
//! predicts, exit 4 with a tolerance tighter than the change and 0 with a looser one); two
//! CEA run folders; inputs of different kinds.

mod common;
use common::{json, root, run, squeal, tmp};

use squeal_reduction::matrix::NamedMatrix;
use squeal_reduction::op4::{self, Op4WriteOptions};
use std::path::Path;

fn scene() -> std::path::PathBuf {
    root().join("examples/transient/tiny-brake.toml")
}

/// `squeal compare a b --out out extra…`: (exit code, stderr).
fn compare(a: &Path, b: &Path, out: &Path, extra: &[&str]) -> (i32, String) {
    let o = squeal()
        .args(["-q", "compare"])
        .arg(a)
        .arg(b)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn matrices(p: &Path) -> Vec<NamedMatrix> {
    op4::read(p).unwrap()
}

#[test]
fn a_reduced_model_against_itself_and_with_one_stiffness_changed() {
    let d = tmp("compare-models");
    let red = d.join("red");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "reduce"])
        .arg(scene())
        .arg("--out")
        .arg(&red));
    assert!(ok, "{stderr}");

    // Against itself: every difference exactly zero, every mode paired with MAC 1, exit 0 with
    // zero tolerances.
    let (code, stderr) = compare(
        &red,
        &red,
        &d.join("self"),
        &[
            "--tol-matrix",
            "0",
            "--tol-freq",
            "0",
            "--tol-mac",
            "0.999999",
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    let r = json(&d.join("self/compare.json"));
    assert_eq!(r["passed"], true);
    for m in r["matrices"].as_array().unwrap() {
        assert_eq!(m["norm_difference"], 0.0, "{m}");
    }
    let n = r["n_dofs"][0].as_u64().unwrap() as usize;
    assert_eq!(r["modes"].as_array().unwrap().len(), n);
    for p in r["modes"].as_array().unwrap() {
        assert_eq!(p["mode_a"], p["mode_b"], "{p}");
        assert_eq!(p["relative_frequency_difference"], 0.0, "{p}");
        assert!(p["mac"].as_f64().unwrap() > 1.0 - 1e-9, "{p}");
    }
    assert!(d.join("self/compare.md").is_file());

    // The modes of A, to choose the entry and to predict the shift (M-normalised shapes).
    let mats = matrices(&red.join("reduced.op4"));
    let get = |name: &str| {
        mats.iter()
            .find(|m| m.name == name)
            .unwrap()
            .as_real()
            .unwrap()
            .clone()
    };
    let (k, m) = (get("KR"), get("MR"));
    let (lam, phi) = squeal_reduction::cb::dense_generalized_eigen(k.as_ref(), m.as_ref()).unwrap();
    // A mode well apart from its neighbours (no degenerate pair), above the rigid ones.
    let i = (1..n - 1)
        .find(|&i| {
            lam[i] > 1e-3 * lam[n - 1]
                && (lam[i] - lam[i - 1]) > 0.05 * lam[i]
                && (lam[i + 1] - lam[i]) > 0.05 * lam[i]
        })
        .expect("a well separated mode");
    // The diagonal entry that mode strains most.
    let j = (0..n)
        .max_by(|&a, &b| {
            (k[(a, a)] * phi[(a, i)].powi(2)).total_cmp(&(k[(b, b)] * phi[(b, i)].powi(2)))
        })
        .unwrap();
    let delta = 0.05 * k[(j, j)];
    let mut changed = Vec::new();
    for mut mm in mats.clone() {
        if mm.name == "KR" {
            let mut a = mm.as_real().unwrap().clone();
            a[(j, j)] += delta;
            mm = NamedMatrix::real("KR", a);
        }
        changed.push(mm);
    }
    let stiff = d.join("stiff");
    std::fs::create_dir_all(&stiff).unwrap();
    for f in ["dofmap.json", "gaps.json"] {
        std::fs::copy(red.join(f), stiff.join(f)).unwrap();
    }
    let refs: Vec<&NamedMatrix> = changed.iter().collect();
    op4::write(
        stiff.join("reduced.op4"),
        &refs,
        &Op4WriteOptions::default(),
    )
    .unwrap();

    // The change itself: ‖δK‖_F/‖K‖_F = δ/‖K‖_F exactly (one entry), nothing else changed.
    let knorm = (0..n)
        .flat_map(|a| (0..n).map(move |b| (a, b)))
        .map(|(a, b)| k[(a, b)].powi(2))
        .sum::<f64>()
        .sqrt();
    let expected = (k[(j, j)] + delta - k[(j, j)]).abs() / knorm;
    let (code, stderr) = compare(
        &red,
        &stiff,
        &d.join("loose"),
        &["--tol-matrix", &format!("{}", 2.0 * expected)],
    );
    assert_eq!(code, 0, "a looser tolerance passes: {stderr}");
    let r = json(&d.join("loose/compare.json"));
    let of = |name: &str| {
        r["matrices"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == name)
            .unwrap()
            .clone()
    };
    let kr = of("KR");
    let rel = kr["relative"].as_f64().unwrap();
    assert!(
        (rel - expected).abs() <= 1e-12 * expected,
        "KR: {rel:e} vs {expected:e}"
    );
    assert_eq!(kr["at"], serde_json::json!([j, j]));
    assert_eq!(of("MR")["norm_difference"], 0.0);
    assert_eq!(of("PBRAKE")["norm_difference"], 0.0);

    // The frequency table: mode i shifts by what the perturbation of λ = ω² predicts,
    // δλ = φ_iᵀ δK φ_i = δ φ_ji² to first order; the second-order term
    // Σ_k (φ_kᵀ δK φ_i)² / (λ_i − λ_k) bounds the difference (and is small against the shift).
    let d_ik = |kk: usize| delta * phi[(j, i)] * phi[(j, kk)];
    let first = d_ik(i);
    let second: f64 = (0..n)
        .filter(|&kk| kk != i)
        .map(|kk| d_ik(kk).powi(2) / (lam[i] - lam[kk]).abs())
        .sum();
    assert!(second < 0.1 * first, "{second:e} vs {first:e}");
    let pair = r["modes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["mode_a"] == i)
        .unwrap()
        .clone();
    let two_pi = 2.0 * std::f64::consts::PI;
    let (fa, fb) = (
        pair["frequency_a_hz"].as_f64().unwrap(),
        pair["frequency_b_hz"].as_f64().unwrap(),
    );
    let dlam = (two_pi * fb).powi(2) - (two_pi * fa).powi(2);
    assert!(
        (dlam - first).abs() <= 2.0 * second + 1e-9 * lam[i],
        "mode {i}: δλ = {dlam:e}, first-order estimate {first:e} (second order {second:e})"
    );
    let shift = pair["relative_frequency_difference"].as_f64().unwrap();
    assert!(shift > 0.0, "a stiffer entry raises the frequency: {pair}");

    // Tolerances tighter than the change: exit 4, naming the check.
    let (code, stderr) = compare(
        &red,
        &stiff,
        &d.join("tight"),
        &["--tol-matrix", &format!("{}", 0.5 * expected)],
    );
    assert_eq!(code, 4, "{stderr}");
    assert!(
        stderr.contains("tol_matrix") && stderr.contains("KR"),
        "{stderr}"
    );
    let (code, stderr) = compare(
        &red,
        &stiff,
        &d.join("tight-f"),
        &["--tol-freq", &format!("{}", 0.5 * shift)],
    );
    assert_eq!(code, 4, "{stderr}");
    assert_eq!(json(&d.join("tight-f/compare.json"))["passed"], false);
    let (code, stderr) = compare(
        &red,
        &stiff,
        &d.join("loose-f"),
        &[
            "--tol-freq",
            &format!(
                "{}",
                2.0 * shift.max(
                    r["modes"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .filter_map(|p| p["relative_frequency_difference"].as_f64())
                        .fold(0.0f64, |m, x| m.max(x.abs())),
                )
            ),
        ],
    );
    assert_eq!(code, 0, "{stderr}");

    // A DOF map with one DOF another: an error naming it.
    let other = d.join("other");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::copy(red.join("reduced.op4"), other.join("reduced.op4")).unwrap();
    let mut map = json(&red.join("dofmap.json"));
    let first_grid = map["dofs"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|x| x.get("grid").is_some())
        .unwrap();
    first_grid["grid"] = 999_999.into();
    std::fs::write(other.join("dofmap.json"), map.to_string()).unwrap();
    let (code, stderr) = compare(&red, &other, &d.join("other-out"), &[]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("grid 999999") || stderr.contains("DOF map"),
        "{stderr}"
    );

    // A model and a run folder are not compared.
    let (code, stderr) = compare(&red, &d.join("self"), &d.join("mixed"), &[]);
    assert_eq!(code, 1, "{stderr}");
}

#[test]
fn two_cea_run_folders_side_by_side() {
    let d = tmp("compare-runs");
    // The tiny brake with the default `[cea]` (the state under full load, no sweep).
    let cea_scene = d.join("tiny-cea.toml");
    let text = std::fs::read_to_string(scene()).unwrap();
    std::fs::write(&cea_scene, text + "\n[cea]\n").unwrap();
    for (name, sets) in [
        ("a", vec![]),
        ("b", vec![]),
        ("mu", vec!["friction.law.mu0=0.5"]),
    ] {
        let mut cmd = squeal();
        cmd.args(["-q", "cea"])
            .arg(&cea_scene)
            .arg("--out")
            .arg(d.join(name));
        for s in sets {
            cmd.args(["--set", s]);
        }
        let (ok, _, stderr) = run(&mut cmd);
        assert!(ok, "{stderr}");
    }
    // The same run twice: the same roots, the same summary values (timings aside).
    let (code, stderr) = compare(
        &d.join("a"),
        &d.join("b"),
        &d.join("ab"),
        &["--tol-root", "0", "--tol-summary", "0"],
    );
    assert_eq!(code, 0, "{stderr}");
    let r = json(&d.join("ab/compare.json"));
    let roots = r["roots"].as_array().unwrap();
    assert!(!roots.is_empty());
    for p in roots {
        assert_eq!(p["real_part_difference"], 0.0, "{p}");
    }
    assert!(r["summaries"]
        .as_array()
        .unwrap()
        .iter()
        .any(|s| s["key"] == "wall_s" && s["timing"] == true));
    // Another friction coefficient moves the roots: beyond a tight root tolerance.
    let (code, stderr) = compare(
        &d.join("a"),
        &d.join("mu"),
        &d.join("amu"),
        &["--tol-root", "1e-9"],
    );
    assert_eq!(code, 4, "{stderr}");
    assert!(stderr.contains("tol_root"), "{stderr}");
}

/// The tolerances are validated before anything is compared (issue 26): a MAC above 1, a
/// pairing threshold above the MAC tolerance, and `--modes 0` with a mode tolerance (which
/// checked nothing and passed models 9.5 % apart) are errors naming the option; `--tol-mac`
/// below the default pairing threshold lowers it, so a model against itself passes.
#[test]
fn compare_tolerances_are_validated() {
    let d = tmp("compare-options");
    let red = d.join("red");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "reduce"])
        .arg(scene())
        .arg("--out")
        .arg(&red));
    assert!(ok, "{stderr}");
    for (extra, named) in [
        (&["--tol-mac", "1.5"][..], "compare.tol_mac"),
        (
            &["--pair-mac", "2", "--tol-mac", "0.9"][..],
            "compare.pair_mac",
        ),
        (
            &["--pair-mac", "0.95", "--tol-mac", "0.9"][..],
            "compare.pair_mac",
        ),
        (&["--modes", "0", "--tol-freq", "1e-9"][..], "compare.modes"),
        (&["--tol-root=-1"][..], "compare.tol_root"),
    ] {
        let (code, stderr) = compare(&red, &red, &d.join("bad"), extra);
        assert_eq!(code, 1, "{extra:?}: {stderr}");
        assert!(stderr.contains(named), "{extra:?}: {stderr}");
    }
    let (code, stderr) = compare(&red, &red, &d.join("low"), &["--tol-mac", "0.3"]);
    assert_eq!(code, 0, "{stderr}");
}
