//! `squeal limit-cycle` (harmonic balance on the band-limited model, issue 22 item 4) against
//! the transient's limit cycle on Hoffmann's mode-coupling model with a compliant contact that
//! separates (examples/limit-cycle/hoffmann.toml): the model of `pipeline/tests/separation.rs`
//! and of the solver's HB test
//! (Hoffmann, Fischer, Allgaier & Gaul, Mech. Res. Commun. 29 (2002) 197–205: pad x, pad z, a
//! rotor point z of mass 0.05 on a unit spring with a damper 0.05; pad damping 0.02; μ = 0.6
//! above the critical μ ≈ 0.35), as a stored reduced model, with the contact compliant
//! (k_n A = 10) and unilateral and a tangential brake load of 0.02 ramped over 2 s.
//!
//! Reference: the pipeline's own time integration of the same scene into its limit cycle, on
//! the full reduced model (BDF with separation events) and on the band-limited model, each
//! analysed by the verdict's limit-cycle monitor (the rotor face's normal velocity over the
//! last cycles): frequency and peak within 1 %.

use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::limit_cycle;
use squeal_pipeline::stages::model;
use squeal_pipeline::stages::transient::{self, TransientOptions};
use squeal_pipeline::{RunDir, Scene};

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("squeal_lc_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// examples/limit-cycle/hoffmann.toml (its stored model written by the example
/// `limit_cycle_model`) with `extra` overrides.
fn scene(extra: &[&str]) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/limit-cycle/hoffmann.toml");
    let sets: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    Scene::load(&path, &sets).unwrap()
}

#[test]
fn hoffmann_with_separation_harmonic_balance_matches_the_transient() {
    let s = scene(&[]);
    let run = RunDir::create(&tmp("hoffmann")).unwrap();
    let m = model::build(&s, &run, &Progress::quiet()).unwrap();
    let t0 = std::time::Instant::now();
    let lc = limit_cycle::compute(&s, &m, &Progress::quiet()).unwrap();
    let t_hb = t0.elapsed().as_secs_f64();
    println!("{}", lc.band_model.line());
    assert_eq!(lc.modes.len(), 1, "{:#?}", lc.modes);
    let hb = &lc.modes[0];
    println!(
        "HB: {:?}; {:.6} Hz, peak {:.6}, rms {:.6}, H {}, stable {:?}, {:.2} s",
        hb.detail.status,
        hb.frequency_hz,
        hb.peak_normal_velocity,
        hb.rms_normal_velocity,
        hb.detail.harmonics,
        hb.stable,
        t_hb
    );
    println!(
        "Hopf point: s {:?}, {:?} Hz",
        hb.detail.hopf_scale, hb.detail.hopf_frequency_hz
    );
    for p in hb.detail.branch.iter().step_by(5) {
        println!(
            "  s {:.4} f {:.5} Hz peak {:.5}",
            p.scale, p.frequency_hz, p.peak_face_velocity
        );
    }
    assert!(hb.reached);
    assert_eq!(hb.stable, Some(true));
    for (name, sets) in [
        ("full", vec![]),
        ("band", vec!["transient.band_limited=true"]),
    ] {
        let st = scene(&sets);
        let t1 = std::time::Instant::now();
        let r =
            transient::compute(&st, &m, &Progress::quiet(), &TransientOptions::default()).unwrap();
        let t_tr = t1.elapsed().as_secs_f64();
        let c = r.limit_cycle.clone().expect("the transient's limit cycle");
        println!(
            "{name} transient: {:?}, {:?}, {} steps, {:.2} s; cycle reached {}, {:.6} Hz, peak {:.6}, \
             rms {:.6}, envelope variation {:.1e}",
            r.status,
            r.verdict.state,
            r.steps,
            t_tr,
            c.reached,
            c.frequency_hz,
            c.peak_normal_velocity,
            c.rms_normal_velocity,
            c.envelope_variation
        );
        assert!(c.reached, "{name}: {c:?}");
        let df = (hb.frequency_hz - c.frequency_hz).abs() / c.frequency_hz;
        let dp = (hb.peak_normal_velocity - c.peak_normal_velocity).abs() / c.peak_normal_velocity;
        println!("{name}: HB vs transient: f {df:.2e}, peak {dp:.2e}");
        assert!(
            df <= 0.01,
            "{name}: f {} vs {}",
            hb.frequency_hz,
            c.frequency_hz
        );
        assert!(
            dp <= 0.01,
            "{name}: peak {} vs {}",
            hb.peak_normal_velocity,
            c.peak_normal_velocity
        );
    }
}

/// Bad `[limit_cycle]` options are refused when the scene is read, naming the table.
#[test]
fn limit_cycle_options_are_validated() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/limit-cycle/hoffmann.toml");
    let e = Scene::load(&path, &["limit_cycle.harmonics=0".to_string()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("limit_cycle") && e.contains("harmonics"), "{e}");
}
