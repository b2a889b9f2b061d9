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
