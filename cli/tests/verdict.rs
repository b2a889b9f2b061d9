//! The false negative of issue 11: a run whose steps are too coarse for the vibration must not
//! say "no squeal". On a hex20 version of the coarse study brake (examples/sample-brake/
//! base.toml with every component in hex20, 502 reduced DOFs) loaded as the shipped hex20
//! example was (1 psi on each pad's back), the error test at the paper's ATOL1 steps over the
//! 2 kHz vibration without a step bound (230 steps to 6 ms, 14 per period of the response,
//! 2.9 per period of the highest in-band unstable CEA root at 9.3 kHz; measured): that run
//! found no growth and used to report `squeal: false`. Whenever the CEA at the run's state has
//! an in-band unstable root, the verdict must be `squeal` or `unresolved`, never `no_squeal`.

mod common;
use common::{json, root, run, squeal, tmp};

fn hex20_run(name: &str, extra: &[&str]) -> serde_json::Value {
    let out = tmp(name);
    let mut cmd = squeal();
    cmd.args(["-q", "transient"])
        .arg(root().join("examples/sample-brake/base.toml"))
        .arg("--out")
        .arg(&out);
    for s in [
        "components.0.element=hex20",
        "components.1.element=hex20",
        "components.2.element=hex20",
        "components.3.element=hex20",
        "loads.pressure.0.pressure=1.0",
        "loads.pressure.1.pressure=1.0",
    ]
    .iter()
    .chain(extra)
    {
        cmd.args(["--set", s]);
    }
    let (ok, _, stderr) = run(&mut cmd);
    assert!(ok, "{stderr}");
    json(&out.join("summary.json"))
}

#[test]
fn coarse_steps_never_give_no_squeal_when_the_cea_has_an_unstable_root() {
    for (name, extra) in [
        (
            "verdict-hex20-unbounded",
            vec!["transient.band_step_bound=false"],
        ),
        ("verdict-hex20-band-bound", vec![]),
    ] {
        let s = hex20_run(name, &extra);
        let cea = &s["verdict_cea"];
        assert!(cea["error"].is_null(), "{cea}");
        let unstable = cea["unstable_in_band"].as_array().unwrap();
        assert!(
            !unstable.is_empty(),
            "the CEA finds in-band unstable roots: {cea}"
        );
        let v = &s["verdict"];
        let state = v["state"].as_str().unwrap();
        assert!(state == "squeal" || state == "unresolved", "{name}: {v}");
        assert_eq!(s["squeal"].as_bool().unwrap(), state == "squeal");
        if name.ends_with("unbounded") {
            // The reason is named with its numbers: the highest in-band unstable frequency
            // gets fewer than 20 steps per period.
            let coarse: Vec<&serde_json::Value> = v["reasons"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|r| r["reason"] == "steps_too_coarse")
                .collect();
            assert!(!coarse.is_empty(), "{v}");
            assert!(
                coarse.iter().any(|r| r["source"] == "cea_unstable"
                    && r["samples_per_period"].as_f64().unwrap() < 20.0),
                "{v}"
            );
        } else {
            // The band bound keeps every step at or below 1/(40 × 10 kHz).
            assert!(
                v["h_max_window"].as_f64().unwrap() <= 2.5e-6 * (1.0 + 1e-12),
                "{v}"
            );
            assert_eq!(s["step_bound"]["band_h_max"].as_f64().unwrap(), 2.5e-6);
        }
    }
}

/// Issue 11, part 2: study case 2 (examples/sample-brake/base.toml) at tight tolerance
/// (RTOL1 = 1e-8, ATOL1 = 1e-10; 163 427 steps): the response's largest root from the
/// estimator (`transient_vs_cea[0]`, paired with the CEA at the same state) within 0.5 % of
/// the CEA's Re p and 0.1 % of its frequency. Slow (~70 s release):
/// `cargo test --release -p squeal-cli --test verdict -- --ignored case2`.
///
/// Measured on the study brake under its clamp load (157.2 psi): σ = 277.5 /s against
/// Re p = +274.3 /s (+1.2 %, FAILS the 0.5 %), f = 2159.1 against 2158.2 Hz (+0.04 %). The
/// response after the ramp is 1–3 in/s against a sliding speed of 47–65 in/s: the fit's
/// residual is 1.6 % and σ moves by ±2 % with the window; the residual stays at 0.8–1.2 %
/// whatever the model order (40–120) and the sampling (5–20 µs), so the response is not a sum
/// of damped exponentials to better than ~1 %: the nonlinearity the linear CEA does not have
/// (docs/verdict.md). Left failing rather than loosened; the same state reached by a gentler
/// ramp passes (`case2_state_slow_ramp_top_root_matches_the_cea`).
#[test]
#[ignore]
fn case2_tight_tolerance_top_root_matches_the_cea() {
    case2_top_root_matches_the_cea("verdict-case2-tight", &[]);
}

/// The estimator's accuracy where the response is linear enough: study case 2's final state
/// (the same steady sliding state and CEA root, Re p = +274.31 /s at 2158.21 Hz), reached by
/// a 2 ms load ramp instead of 0.5 ms (TF 7.5 ms, the same 5.5 ms window after the ramp).
/// The gentler ramp rings the strongly damped modes far less (the 9.5 kHz root's amplitude
/// at the window's start 0.21 against 0.84 in/s): the fit's residual is 0.26 % and σ =
/// 274.09 /s (−0.08 %), f = 2158.23 Hz (+0.001 %) (measured, release build, 133 793 steps,
/// ~70 s CPU). `cargo test --release -p squeal-cli --test verdict -- --ignored slow_ramp`.
#[test]
#[ignore]
fn case2_state_slow_ramp_top_root_matches_the_cea() {
    case2_top_root_matches_the_cea(
        "verdict-case2-slow-ramp",
        &["loads.tload=0.002", "transient.tfinal=0.0075"],
    );
}

/// Study case 2 (base.toml) at RTOL1 = 1e-8, ATOL1 = 1e-10 with `extra` settings: the
/// estimator's largest root within 0.5 % of the paired CEA root's Re p and 0.1 % of its
/// frequency.
fn case2_top_root_matches_the_cea(name: &str, extra: &[&str]) {
    let out = tmp(name);
    let mut cmd = squeal();
    cmd.args(["-q", "transient"])
        .arg(root().join("examples/sample-brake/base.toml"))
        .arg("--out")
        .arg(&out);
    for s in ["transient.rtol1=1e-8", "transient.atol1=1e-10"]
        .iter()
        .chain(extra)
    {
        cmd.args(["--set", s]);
    }
    let (ok, _, stderr) = run(&mut cmd);
    assert!(ok, "{stderr}");
    let s = json(&out.join("summary.json"));
    let p = &s["transient_vs_cea"][0];
    let (ds, df) = (
        p["rel_diff_growth"].as_f64().unwrap(),
        p["rel_diff_frequency"].as_f64().unwrap(),
    );
    eprintln!("{name}: {p}");
    assert!(p["cea_real_part"].as_f64().unwrap() > 0.0, "{p}");
    assert!(ds.abs() < 5e-3, "sigma {ds:+.4} relative: {p}");
    assert!(df.abs() < 1e-3, "f {df:+.5} relative: {p}");
}
