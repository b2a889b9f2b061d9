//! System test of `squeal limit-cycle`: harmonic balance on the band-limited model of
//! examples/limit-cycle/hoffmann.toml (Hoffmann's mode-coupling model with a compliant contact
//! that separates, μ = 0.6 above μc ≈ 0.35) through the command line.
//!
//! Reference: the pipeline's own time integration of the same scene into its limit cycle
//! (`pipeline/tests/limit_cycle.rs`, docs/limit-cycle.md): 0.1591 Hz and a peak normal velocity
//! of the rotor point of 0.9694; the command's cycle agrees within 1 %. A bad band option is an
//! error naming the key and the value, with a nonzero exit and no `limit_cycle.json`.

mod common;
use common::{json, root, run, squeal, tmp};

#[test]
fn limit_cycle_of_hoffmann_through_the_command_line() {
    let d = tmp("limit-cycle");
    let scene = root().join("examples/limit-cycle/hoffmann.toml");
    let out = d.join("run");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "limit-cycle"])
        .arg(&scene)
        .arg("--out")
        .arg(&out));
    assert!(ok, "{stderr}");
    let r = json(&out.join("limit_cycle.json"));
    assert_eq!(r["verb"], "limit-cycle");
    let modes = r["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 1, "{r:#}");
    let m = &modes[0];
    assert_eq!(m["reached"], true, "{m:#}");
    let (f, peak) = (
        m["frequency_hz"].as_f64().unwrap(),
        m["peak_normal_velocity"].as_f64().unwrap(),
    );
    eprintln!("limit cycle: {f:.6} Hz, peak normal velocity {peak:.6}");
    assert!((f - 0.1591).abs() <= 0.01 * 0.1591, "{f}");
    assert!((peak - 0.9694).abs() <= 0.01 * 0.9694, "{peak}");
    assert!(r["band_model"].is_object());

    let bad = d.join("bad");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "limit-cycle"])
        .arg(&scene)
        .args(["--set", "transient.band_tolerance=-1.0"])
        .arg("--out")
        .arg(&bad));
    assert!(!ok);
    assert!(
        stderr.contains("transient.band_tolerance") && stderr.contains("-1"),
        "{stderr}"
    );
    assert!(!bad.join("limit_cycle.json").exists());
}
