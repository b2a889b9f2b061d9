//! System test of `squeal reproduce` on a coarse version of the sample brake
//! (`examples/sample-brake/base.toml` with fewer fixed-interface modes and a short TF): two of
//! the paper's cases run and produce `cases.json`, the table, the figures and the report.

mod common;
use common::{root, tmp};

use std::process::Command;

/// Cases 2 (μ = 0.7 − 0.0005V) and 5 (μ = 0.3) of the paper's table, to TF = 0.0008 s.
#[test]
fn reproduce_two_coarse_cases_writes_table_figures_and_report() {
    let dir = tmp("reproduce_two_cases");
    let base = root().join("examples/sample-brake/base.toml");
    let study = format!(
        r#"base = "{}"
cea = false
[[cases]]
case = 2
rtol1 = 1e-4
tload = 0.0005
friction = {{ kind = "linear_speed", mu0 = 0.7, slope = -0.0005 }}
tf = 0.0008
[[cases]]
case = 5
rtol1 = 1e-4
tload = 0.0005
friction = {{ kind = "constant", mu = 0.3 }}
tf = 0.0008
[[figures]]
name = "fig_mu"
title = "cases 2 and 5"
cases = [2, 5]
[[figures]]
name = "fig_zoom"
title = "cases 2 and 5, last 0.0002 s"
cases = [2, 5]
last = 0.0002
"#,
        base.display().to_string().replace('\\', "/")
    );
    let study_path = dir.join("study.toml");
    std::fs::write(&study_path, study).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["-q", "reproduce"])
        .arg(&study_path)
        .arg("--out")
        .arg(&out)
        .args(["--set", "reduction.n_modes=8", "--jobs", "2"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cases: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("cases.json")).unwrap()).unwrap();
    let cases = cases.as_array().unwrap();
    assert_eq!(cases.len(), 2);
    for (c, want_mu, want_case) in [(&cases[0], "0.7-0.0005V", 2), (&cases[1], "0.3", 5)] {
        assert_eq!(c["case"], want_case);
        assert_eq!(c["mu"], want_mu);
        assert_eq!(c["tload"], 0.0005);
        for k in [
            "rtol1",
            "steps",
            "cpu_s",
            "squeal",
            "growth_rate_per_s",
            "dominant_frequency_hz",
        ] {
            assert!(c.get(k).is_some(), "cases.json lacks {k}: {c}");
        }
        // The step is bounded by h_max = 2.5e-6 s (base.toml): at least TF / h_max steps.
        assert!(c["steps"].as_u64().unwrap() >= 320, "{c}");
        // P0 = 40 lb/in of the base scene (the paper's table).
        assert_eq!(c["p0"], 40.0);
    }
    let table = std::fs::read_to_string(out.join("cases.md")).unwrap();
    assert!(
        table.contains("| 2 | 1e-4 | 0.0005 | 0.7-0.0005V |"),
        "{table}"
    );
    for f in [
        "fig_mu.png",
        "fig_mu.svg",
        "fig_zoom.png",
        "report.md",
        "summary.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("![cases 2 and 5](fig_mu.png)") || report.contains("(fig_mu.png)"));
    assert!(report.contains("(b) μ = 0.3 does not squeal"), "{report}");
}

/// The paper's finding (b) and the transient ↔ CEA agreement on the study brake itself: case 4
/// (μ = 0.7) and case 5 (μ = 0.3) of examples/sample-brake/study.toml to the paper's TF, with
/// the CEA of each case and the μ sweep of the base scene.
///
/// References: the growth rate of the squealing transient must match the real part of the most
/// unstable complex eigenvalue at its steady sliding state (eqs. 19–24; linear growth phase,
/// measured −1.5 % on this model); μ = 0.3 lies below the lowest critical μ of the base scene
/// (0.391 measured with the study's compliant interface, study.toml's notes), μ = 0.7 above it.
#[test]
fn study_brake_squeals_at_mu_07_as_its_cea_says_and_not_at_mu_03() {
    let dir = tmp("reproduce_cases_4_5");
    let study = root().join("examples/sample-brake/study.toml");
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["-q", "reproduce"])
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--cases", "4,5", "--jobs", "2"])
        // The study's first load set (1 psi on each pad's back) and its step h_max = 2.5e-6
        // s: a small-amplitude, linear growth phase with the contact compressive throughout,
        // where the transient must agree with the CEA. (Under the study's physical load, a
        // light stop's clamp, case 4's ramp dips gap 19 to p_n = -0.03 psi and its 6 ms window
        // shows +119 /s as a factor < 2: `unresolved`; README "The sample-brake study".)
        .args([
            "--set",
            "loads.pressure.0.pressure=1.0",
            "--set",
            "loads.pressure.1.pressure=1.0",
            "--set",
            "transient.h_max=2.5e-6",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cases: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("cases.json")).unwrap()).unwrap();
    let (c4, c5) = (&cases[0], &cases[1]);
    assert_eq!(c4["case"], 4);
    assert_eq!(c5["case"], 5);
    for c in [c4, c5] {
        assert_eq!(c["status"]["status"], "reached", "{c}");
    }
    // Case 4 squeals with valid contact; its growth is the CEA's most unstable root in the
    // squeal band.
    assert_eq!(c4["squeal"], true, "{c4}");
    assert_eq!(c4["verdict"]["state"], "squeal", "{c4}");
    assert!(c4["contact"]["first_separation"].is_null(), "{c4}");
    let growth = c4["growth_rate_per_s"].as_f64().unwrap();
    let f = c4["dominant_frequency_hz"].as_f64().unwrap();
    let top = c4["cea_unstable_modes"]
        .as_array()
        .unwrap()
        .iter()
        .max_by(|a, b| {
            a["real_part"]
                .as_f64()
                .unwrap()
                .total_cmp(&b["real_part"].as_f64().unwrap())
        })
        .unwrap()
        .clone();
    let (re, fc) = (
        top["real_part"].as_f64().unwrap(),
        top["frequency_hz"].as_f64().unwrap(),
    );
    assert!((2000.0..10000.0).contains(&fc), "{top}");
    assert!(
        (growth - re).abs() < 0.05 * re,
        "transient {growth} vs CEA {re}"
    );
    assert!(
        (f - fc).abs() < 0.02 * fc,
        "transient {f} Hz vs CEA {fc} Hz"
    );
    // Case 5 does not: its envelope decays and the CEA has no unstable mode. Its 6 ms window
    // cannot show a growth of 100 /s (the default smallest growth that matters), so the
    // verdict is not a negative but `unresolved`, naming the window.
    assert_eq!(c5["squeal"], false, "{c5}");
    assert_eq!(c5["verdict"]["state"], "unresolved", "{c5}");
    assert!(
        c5["verdict"]["reasons"]
            .to_string()
            .contains("window_too_short"),
        "{c5}"
    );
    assert!(c5["growth_rate_per_s"].as_f64().unwrap() < 0.0, "{c5}");
    assert_eq!(
        c5["cea_unstable_modes"].as_array().unwrap().len(),
        0,
        "{c5}"
    );
    // The base scene's μ sweep puts the lowest critical μ between the two.
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("cea_sweep/cea.sweep.json")).unwrap(),
    )
    .unwrap();
    let mu_c = summary["lowest_critical_mu"].as_f64().unwrap();
    assert!(mu_c > 0.3 && mu_c < 0.7, "lowest critical mu {mu_c}");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Complex eigenvalues: which modes couple at which μ"));
    assert!(report.contains("## The model"));
}
