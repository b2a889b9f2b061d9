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

/// Issue 11, part 2: study case 2 (examples/sample-brake/base.toml, compliant contact
/// k_n = 1e6 psi/in) at tight tolerance (RTOL1 = 1e-8, ATOL1 = 1e-10; 119 174 steps): the
/// response's largest root from the estimator (`transient_vs_cea[0]`, paired with the CEA at
/// the same state) within 0.5 % of the CEA's Re p and 0.1 % of its frequency. Slow (~30 s
/// release): `cargo test --release -p squeal-cli --test verdict -- --ignored case2`.
///
/// Measured: σ = 128.8 /s against Re p = +136.72 /s (−5.8 %, FAILS the 0.5 %), f = 2097.06
/// against 2101.34 Hz (−0.20 %, FAILS the 0.1 %). The paper's 6 ms leave a 5.5 ms window after
/// the 0.5 ms ramp in which the 2.1 kHz root grows by a factor of 2.1 only, while the ramp rings
/// strongly damped modes of the same size (5.8 kHz at −680 /s starts at the squealing root's
/// amplitude) and the response carries 3–4 % that is not a sum of damped exponentials (the
/// fit's residual stays at 3.2–4.1 % for model orders 40–160; σ moves by ±15 % with the
/// window's start). Left failing rather than loosened; the same case observed to 13 ms
/// passes (`case2_to_13ms_top_root_matches_the_cea`). With the rigid contact of the earlier
/// study (Re p +274.3 /s, a factor of 4.5 in the window) this test gave +1.2 %.
/// The 6 ms history holds σ only loosely: fitted by least squares on the CEA's own roots
/// (fixed), 1.58 % of it is left over (92 % at 10–20 kHz), and Re p × 0.94 or × 1.06 raises
/// that residual only to 1.60 % (`python/bench/pinned_roots_fit.py`; on 13 ms × 0.98 already
/// gives 0.70 % → 0.96 %).
#[test]
#[ignore]
fn case2_tight_tolerance_top_root_matches_the_cea() {
    case2_top_root_matches_the_cea("verdict-case2-tight", &[]);
}

/// The estimator's accuracy once the window shows the growth: study case 2 at the same tight
/// tolerance observed to TF = 13 ms (12.5 ms after the ramp, a growth factor of 5.5; the
/// contact stays compressive throughout, min p_n +0.29 psi at gap 19, so the state is the
/// CEA's). Measured (release build, 217 391 steps, ~75 s wall): σ = 136.47 /s against Re p =
/// +136.72 /s (−0.19 %), f = 2101.321 against 2101.336 Hz (−0.0007 %), residual 0.79 %.
/// (To 16 ms: −0.18 %, but gap 19 turns tensile from 13.1 ms.)
/// `cargo test --release -p squeal-cli --test verdict -- --ignored to_13ms`.
#[test]
#[ignore]
fn case2_to_13ms_top_root_matches_the_cea() {
    case2_top_root_matches_the_cea("verdict-case2-13ms", &["transient.tfinal=0.013"]);
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
    // The CEA's state is the run's only while every gap stays compressive.
    assert_eq!(s["contact"]["tensile_gap_steps"], 0, "{}", s["contact"]);
    assert!(p["cea_real_part"].as_f64().unwrap() > 0.0, "{p}");
    assert!(ds.abs() < 5e-3, "sigma {ds:+.4} relative: {p}");
    assert!(df.abs() < 1e-3, "f {df:+.5} relative: {p}");
}
