//! The operating point (issue 21 item 4) and the contact pairs it describes (issue 23 item 4):
//! the model's gap geometry carries no operating value, the problem's gaps carry the scene's,
//! and a pair may have a law of its own and no steady sliding.
//!
//! On the tiny brake (one pad pair; the rotor turns about z at 10 rpm, the pad abutment holds
//! x, y), references by construction:
//! - v_slide = ω × (x − origin) with ω = 2π·rpm/60 about z [Paper eq. (2)];
//! - a pair with `sliding = "none"` has no steady slip, so no steady friction force: its steady
//!   state is the frictionless one (μ = 0), to round-off;
//! - a pair whose own law equals what the scene's `[friction]` would be gives the same gaps
//!   and steady state as that scene.

use squeal_contact::FrictionLaw;
use squeal_pipeline::model::{self, ReducedModel};
use squeal_pipeline::problem::{system, tangents, OperatingPoint};
use squeal_pipeline::progress::Progress;
use squeal_pipeline::{RunDir, Scene};
use squeal_solver::bsql::SteadyOptions;

fn tiny(dir: &std::path::Path, contact_extra: &str, friction: &str) -> Scene {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap();
    let text = std::fs::read_to_string(root.join("examples/transient/tiny-brake.toml")).unwrap();
    let text = text
        .replace(
            "p0 = 1.0                                        # preload pressure P0 of every gap",
            &format!("p0 = 1.0\n{contact_extra}"),
        )
        .replace(
            "law = { kind = \"linear_speed\", mu0 = 0.6, slope = -0.05 }",
            &format!("law = {friction}"),
        );
    let path = dir.join(format!("tiny-{}.toml", text.len()));
    std::fs::write(&path, text).unwrap();
    Scene::load(&path, &[]).unwrap()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("squeal-operating-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn build(scene: &Scene, dir: &std::path::Path) -> ReducedModel {
    let rd = RunDir::create(&dir.join("run")).unwrap();
    model::build(scene, &rd, &Progress::quiet()).unwrap()
}

/// The steady sliding state under the full brake load: (u, λ̇).
fn steady(scene: &Scene, m: &ReducedModel) -> (Vec<f64>, Vec<f64>) {
    let p = system::problem(scene, m).unwrap();
    let opts = SteadyOptions {
        tol: 1e-12,
        ..Default::default()
    };
    let lin = tangents::at_steady_state(&p, &p.gaps, &opts).unwrap();
    (lin.u, lin.lambda_dot)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn the_model_has_geometry_and_the_problem_the_operating_values() {
    let d = tmp("values");
    let scene = tiny(
        &d,
        "",
        "{ kind = \"linear_speed\", mu0 = 0.6, slope = -0.05 }",
    );
    let m = build(&scene, &d);
    assert!(m.gap_geometry.len() == 9, "{} gaps", m.gap_geometry.len());
    assert!(m
        .gap_geometry
        .gaps
        .iter()
        .all(|g| g.v_slide == [0.0; 3] && g.p0 == 0.0));
    let gaps = system::problem(&scene, &m).unwrap().gaps;
    let w = 10.0 * 2.0 * std::f64::consts::PI / 60.0;
    for g in &gaps.gaps {
        // ω ẑ × (x, y, z) = ω (−y, x, 0).
        let want = [-w * g.coords[1], w * g.coords[0], 0.0];
        let err = max_diff(&g.v_slide, &want);
        assert!(err <= 1e-15 * w * 3.0, "{:?} vs {want:?}", g.v_slide);
        assert_eq!(g.p0, 1.0);
        assert!(g.friction.is_none());
    }
    assert_eq!(
        gaps.law,
        FrictionLaw::LinearSpeed {
            mu0: 0.6,
            slope: -0.05
        }
    );
    // Another operating point on the same model: the rotor at 20 rpm doubles every speed.
    let mut op = OperatingPoint::of(&scene);
    op.rotor.rpm = 20.0;
    let fast = op.gaps(&m).unwrap();
    for (a, b) in gaps.gaps.iter().zip(&fast.gaps) {
        assert!(max_diff(&b.v_slide, &a.v_slide.map(|v| 2.0 * v)) <= 1e-14);
    }
}

#[test]
fn a_pair_without_steady_sliding_carries_no_steady_friction() {
    let d = tmp("sliding");
    let law = "{ kind = \"constant\", mu = 0.4 }";
    let still = tiny(&d, "sliding = \"none\"", law);
    let sliding = tiny(&d, "", law);
    let frictionless = tiny(&d, "", "{ kind = \"constant\", mu = 0.0 }");
    let m = build(&still, &d);
    let gaps = system::problem(&still, &m).unwrap().gaps;
    assert!(gaps.gaps.iter().all(|g| g.v_slide == [0.0; 3]));
    let (u0, l0) = steady(&frictionless, &m);
    let (us, ls) = steady(&still, &m);
    let (ur, _) = steady(&sliding, &m);
    let (du_still, du_sliding) = (max_diff(&us, &u0), max_diff(&ur, &u0));
    eprintln!(
        "max |u − u(μ=0)|: sliding = none {du_still:.3e}, sliding = rotor {du_sliding:.3e} \
         (max |u| {:.3e})",
        max_abs(&u0)
    );
    assert!(du_still <= 1e-12 * max_abs(&u0), "{du_still}");
    assert!(max_diff(&ls, &l0) <= 1e-12 * max_abs(&l0));
    // The same pair sliding with μ = 0.4 drags the pad: its state moves.
    assert!(du_sliding > 1e-3 * max_abs(&u0), "{du_sliding}");
}

#[test]
fn a_pair_law_of_its_own_acts_as_the_scenes_law_would() {
    let d = tmp("pair-law");
    let own = tiny(
        &d,
        "friction = { kind = \"constant\", mu = 0.25 }",
        "{ kind = \"linear_speed\", mu0 = 0.6, slope = -0.05 }",
    );
    let scene_law = tiny(&d, "", "{ kind = \"constant\", mu = 0.25 }");
    let m = build(&own, &d);
    let gaps = system::problem(&own, &m).unwrap().gaps;
    assert!(gaps
        .gaps
        .iter()
        .all(|g| g.friction == Some(FrictionLaw::Constant { mu: 0.25 })));
    let (ua, la) = steady(&own, &m);
    let (ub, lb) = steady(&scene_law, &m);
    assert!(max_diff(&ua, &ub) <= 1e-13 * max_abs(&ub));
    assert!(max_diff(&la, &lb) <= 1e-13 * max_abs(&lb));
    // A bad law is an error naming the pair's key and the value.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap();
    let text = std::fs::read_to_string(root.join("examples/transient/tiny-brake.toml"))
        .unwrap()
        .replace(
            "tolerance = 1e-6",
            "tolerance = 1e-6\nfriction = { kind = \"constant\", mu = -0.5 }",
        );
    let path = d.join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let e = Scene::load(&path, &[]).unwrap_err().to_string();
    assert!(
        e.contains("contact[0].friction") && e.contains("-0.5"),
        "{e}"
    );
}
