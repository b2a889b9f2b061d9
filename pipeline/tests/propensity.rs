//! `squeal propensity` (issue 24 item 4) through the pipeline: on Hoffmann's 2-DOF
//! mode-coupling model with μ ~ U(a, b), P(unstable) = (b − μc)/(b − a) exactly (μc = 1/3,
//! Hoffmann, Fischer, Bieser & Gaul 2002); an input that cannot move the roots has Sobol
//! indices 0 and μ has S_1 = S_T = 1 (a function of one input: Sobol 1993); the late values
//! applied to the reused model equal a fresh build's; a component's modulus on the reduced
//! model equals a re-reduction; an input that changes the reduced model is refused naming the
//! key.

mod common;
use squeal_pipeline::problem::system;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::model;
use squeal_pipeline::stages::propensity::{self, PropensityArgs};
use squeal_pipeline::{RunDir, Scene};

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("squeal-propensity-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Hoffmann's model (`common::hoffmann`) without damping at μ = 0.1: its two frequencies
/// coalesce at μc = 1/3 (discriminant 0.4 − 1.2μ); stable below μc, a flutter pair at
/// ≈16.7 Hz above.
fn hoffmann(dir: &std::path::Path) -> std::path::PathBuf {
    common::hoffmann(dir, 0.0, 0.1, "[cea]\nfriction_damping = true\n")
}

fn args(dists: &[(&str, &str)], samples: usize) -> PropensityArgs {
    PropensityArgs {
        dists: dists
            .iter()
            .map(|(k, d)| (k.to_string(), d.to_string()))
            .collect(),
        samples,
        ..Default::default()
    }
}

/// μ ~ U(0.2, 0.5): P(unstable) = (0.5 − 1/3)/0.3 = 5/9. Each replicate's A (and B) points
/// are a scrambled Sobol set, whose one-dimensional projection is a (0, m, 1)-net: one point in
/// each of the n_base intervals of width 1/n_base, so each set's fraction above μc is within
/// 1/n_base of the exact value, and so is the mean. The estimate holds that bound (plus O(ε)
/// for μc's shift by the rotor point's mass ε = 1e-6) and its interval holds the exact value.
/// The unstable pair's band (16 Hz: 14.1–17.8 Hz) has the same probability; propensity.json
/// and samples.csv are written.
#[test]
fn hoffmann_probability_of_instability_is_the_uniform_fraction() {
    let d = tmp("hoffmann");
    let scene = Scene::load(&hoffmann(&d), &[]).unwrap();
    let dir = RunDir::create(&d.join("run")).unwrap();
    let a = args(&[("friction.law.mu", "uniform(0.2, 0.5)")], 1024);
    let out = propensity::run(&scene, &dir, &Progress::quiet(), &a, None).unwrap();
    let exact = 5.0 / 9.0;
    let p = &out.p_unstable;
    eprintln!(
        "P = {:.6} in [{:.4}, {:.4}] (exact {exact:.6}, error {:.2e}, n_base {}, {} replicates)",
        p.p,
        p.interval[0],
        p.interval[1],
        p.p - exact,
        out.n_base,
        out.replicates
    );
    assert_eq!(out.stats.evaluations, 1024);
    assert_eq!(out.stats.failed, 0, "{:?}", out.errors);
    assert!((p.p - exact).abs() <= 1.0 / out.n_base as f64 + 1e-4);
    assert!(p.interval[0] <= exact && exact <= p.interval[1]);
    assert!(p.interval[1] - p.interval[0] < 0.1);
    let b16 = out
        .bands
        .iter()
        .find(|b| b.band.lower_hz < 16.7 && 16.7 < b.band.upper_hz)
        .unwrap();
    assert!((b16.p - p.p).abs() < 1e-12, "band {} vs {}", b16.p, p.p);
    let others: f64 = out
        .bands
        .iter()
        .filter(|b| b.band.center_hz != b16.band.center_hz)
        .map(|b| b.p)
        .sum();
    assert_eq!(others, 0.0);
    let re = out.max_real_part.as_ref().unwrap();
    assert!(re.min.abs() < 1e-6 && re.max > 1.0, "{re:?}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("run/propensity.json")).unwrap())
            .unwrap();
    assert_eq!(json["inputs"][0]["key"], "friction.law.mu");
    assert!(json["p_unstable"]["interval"].is_array());
    let csv = std::fs::read_to_string(d.join("run/samples.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1025);
    assert!(csv.starts_with("row,replicate,kind,friction.law.mu,max_real_part"));
}

/// Two inputs, one of which cannot move the roots (the brake load scales PBRAKE = 0): its
/// total index is 0 (Jansen's estimator is exactly 0 when f_A = f_AB), and μ's first-order and
/// total indices are 1 (the output is a function of μ alone) to within the estimator's error.
#[test]
fn sobol_indices_of_a_model_of_one_relevant_input() {
    let d = tmp("hoffmann-sobol");
    let scene = Scene::load(&hoffmann(&d), &[]).unwrap();
    let dir = RunDir::create(&d.join("run")).unwrap();
    let a = args(
        &[
            ("friction.law.mu", "uniform(0.2, 0.5)"),
            ("loads.pmax", "lognormal(0, 0.3)"),
        ],
        1024,
    );
    let out = propensity::run(&scene, &dir, &Progress::quiet(), &a, None).unwrap();
    for s in [&out.sobol_max_real_part, &out.sobol_unstable] {
        let s = s.as_ref().unwrap();
        eprintln!(
            "S1 {:?} {:?}, ST {:?} {:?}",
            s.indices.first_order,
            s.indices.first_order_interval,
            s.indices.total,
            s.indices.total_interval
        );
        assert_eq!(s.keys, ["friction.law.mu", "loads.pmax"]);
        assert!(s.indices.total[1].abs() < 1e-9, "{:?}", s.indices.total);
        assert!(s.indices.first_order[1].abs() < 1e-9);
        assert!((s.indices.total[0] - 1.0).abs() < 0.05);
        assert!((s.indices.first_order[0] - 1.0).abs() < 0.1);
    }
}

/// The operating values (μ, rpm, P0, VTOL) are not the model's (issue 21, item 4): a fresh
/// build of the changed scene has the base model's gap geometry, and the reused base model
/// makes, at the changed scene's operating point, the gaps the fresh build's problem has — on a
/// meshed model (the tiny brake) and a stored one.
#[test]
fn the_reused_model_at_a_changed_operating_point_equals_a_fresh_build() {
    let d = tmp("relate");
    let tiny = root().join("examples/transient/tiny-brake.toml");
    let hoff = hoffmann(&d);
    for (path, sets) in [
        (
            &tiny,
            vec![
                "friction.law.mu0=0.45",
                "rotor.rpm=12.5",
                "contact.0.p0=1.7",
                "friction.vtol=2e-3",
            ],
        ),
        (
            &hoff,
            vec!["friction.law.mu=0.41", "rotor.rpm=1000.0", "model.p0=2.5"],
        ),
    ] {
        let base = Scene::load(path, &[]).unwrap();
        let dir = RunDir::create(&d.join("base")).unwrap();
        let m = model::build(&base, &dir, &Progress::quiet()).unwrap();
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let changed = Scene::load(path, &sets).unwrap();
        let fresh = model::build(&changed, &dir, &Progress::quiet()).unwrap();
        assert_eq!(m.gap_geometry, fresh.gap_geometry, "{}", path.display());
        let fresh_gaps = system::problem(&changed, &fresh).unwrap().gaps;
        let reused = system::problem(&changed, &m).unwrap().gaps;
        assert_eq!(reused, fresh_gaps, "{}", path.display());
        assert_ne!(system::problem(&base, &m).unwrap().gaps, fresh_gaps);
    }
}

/// Bad inputs: an unknown key, a malformed distribution, a < b violated, a key that changes
/// the reduced model, and too few samples for the Sobol indices name the flag and the value.
#[test]
fn bad_inputs_name_the_flag_and_the_value() {
    let tiny = root().join("examples/transient/tiny-brake.toml");
    let scene = Scene::load(&tiny, &[]).unwrap();
    for (dists, n, frag) in [
        (
            vec![("friction.law.mux", "uniform(0.3, 0.5)")],
            64,
            "--dist friction.law.mux=uniform(0.3, 0.5)",
        ),
        (
            vec![("friction.law.mu0", "uniform[0.3, 0.5]")],
            64,
            "expected NAME(ARGS)",
        ),
        (vec![("friction.law.mu0", "uniform(0.5, 0.3)")], 64, "a < b"),
        (
            // Poisson's ratio changes the Craig-Bampton basis (a modulus alone scales on the
            // reduced model: `component_modulus_on_the_reduced_model_tracks_re_reduction`).
            vec![("components.1.material.poisson", "uniform(0.25, 0.35)")],
            64,
            "`components.1.material.poisson` changes the reduced model",
        ),
        (
            vec![
                ("friction.law.mu0", "uniform(0.3, 0.5)"),
                ("contact.0.p0", "uniform(0.5, 1.5)"),
            ],
            20,
            "--samples",
        ),
    ] {
        let e = propensity::plan(&scene, &args(&dists, n))
            .unwrap_err()
            .to_string();
        eprintln!("{e}");
        assert!(e.contains(frag), "{frag}: {e}");
    }
    // With --rereduce the component key is accepted and marked.
    let mut a = args(
        &[("components.1.material.poisson", "uniform(0.25, 0.35)")],
        16,
    );
    a.rereduce = true;
    let p = propensity::plan(&scene, &a).unwrap();
    assert!(p.rereduce && !p.inputs[0].reuses_model);
}

/// A component's Young's modulus varied on the one reduced model (the reduced-matrix
/// derivative, Craig–Bampton basis held fixed) against re-reducing the model at that modulus
/// (`--rereduce`): the tiny brake's pad (one material, E₀ = 5e3) at 0.7, 1 and 1.3 E₀.
///
/// Reference: scaling every modulus of a component by s scales K_c by s, which leaves its
/// Craig–Bampton basis unchanged (the constraint modes −K_ii⁻¹K_ib are invariant, the
/// fixed-interface modes of (s K_ii, M_ii) are those of (K_ii, M_ii) with ω² scaled by s), so
/// T_cᵀ(s K_c)T_c is the re-reduced matrix and the two agree to round-off at every s, as long
/// as the re-reduction keeps the same number of modes (here a fixed count). A one-material
/// component's `material.young` key is the same scale; a scale key combined with a re-reduced
/// input, and a missing component, are refused naming the key.
#[test]
fn component_modulus_on_the_reduced_model_tracks_re_reduction() {
    let d = tmp("component");
    let tiny = root().join("examples/transient/tiny-brake.toml");
    let scene = Scene::load(&tiny, &[]).unwrap();
    let eval = |dists: &[(&str, &str)], rereduce: bool, values: &[f64]| {
        let mut a = args(dists, 64);
        a.rereduce = rereduce;
        let plan = propensity::plan(&scene, &a).unwrap();
        assert_eq!(plan.rereduce, rereduce);
        let dir = RunDir::create(&d.join(format!("run-{rereduce}"))).unwrap();
        let ev = propensity::Evaluator::new(&scene, &plan, &dir, &Progress::quiet(), None).unwrap();
        values
            .iter()
            .map(|&v| {
                let s = ev.evaluate(0, &[v], &Progress::quiet()).unwrap();
                assert!(s.error.is_none(), "{:?}", s.error);
                (
                    s.outcome.unwrap().max_real_part,
                    s.max_real_part_frequency_hz.unwrap(),
                )
            })
            .collect::<Vec<_>>()
    };
    let e0 = 5.0e3;
    let scales = [0.7, 1.0, 1.3];
    let on_model = eval(
        &[("components.pad.young_scale", "uniform(0.7, 1.3)")],
        false,
        &scales,
    );
    let material = eval(
        &[("components.1.material.young", "uniform(3.5e3, 6.5e3)")],
        false,
        &scales.map(|s| s * e0),
    );
    let rebuilt = eval(
        &[("components.1.material.young", "uniform(3.5e3, 6.5e3)")],
        true,
        &scales.map(|s| s * e0),
    );
    for (k, s) in scales.iter().enumerate() {
        let ((ra, fa), (rb, fb), (rc, fc)) = (on_model[k], material[k], rebuilt[k]);
        eprintln!(
            "E = {s} E0: reduced derivative Re {ra:.6e} /s at {fa:.4} Hz; material key \
             {rb:.6e}; re-reduced {rc:.6e} /s at {fc:.4} Hz (|dRe| {:.3e}, df/f {:.3e})",
            (ra - rc).abs(),
            (fa - fc).abs() / fc
        );
        assert!((ra - rb).abs() <= 1e-9 * ra.abs().max(1.0) && (fa - fb).abs() <= 1e-9 * fa);
        let scale = ra.abs().max(rc.abs()).max(1e-3 * fc);
        assert!((ra - rc).abs() <= 1e-9 * scale, "{s}: {ra} vs {rc}");
        assert!((fa - fc).abs() <= 1e-10 * fc, "{s}: {fa} vs {fc}");
    }
    let refused = |dists: &[(&str, &str)], rereduce: bool| {
        let mut a = args(dists, 64);
        a.rereduce = rereduce;
        propensity::plan(&scene, &a).unwrap_err().to_string()
    };
    let e = refused(
        &[("components.caliper.young_scale", "uniform(0.7, 1.3)")],
        false,
    );
    assert!(
        e.contains("components.caliper.young_scale") && e.contains("no component"),
        "{e}"
    );
    let e = refused(
        &[
            ("components.pad.young_scale", "uniform(0.7, 1.3)"),
            ("components.0.material.young", "uniform(0.9e4, 1.1e4)"),
        ],
        true,
    );
    assert!(
        e.contains("components.pad.young_scale") && e.contains("--rereduce"),
        "{e}"
    );
}

/// A material key of a component with materials of its own volumes (the cad brake's pads:
/// steel backplate + lining) is not a scale of the component: refused, naming the volumes and
/// the keys that work; the component's scale key is accepted.
#[test]
fn a_material_key_of_a_several_material_component_is_refused() {
    let cad = Scene::load(&root().join("examples/cad-brake/brake.toml"), &[]).unwrap();
    let e = propensity::component_input(&cad, "components.1.material.young").unwrap_err();
    assert!(
        e.contains("lining") && e.contains("young_scale") && e.contains("--rereduce"),
        "{e}"
    );
    let name = cad.components[1].name.clone();
    let c = propensity::component_input(&cad, &format!("components.{name}.young_scale"))
        .unwrap()
        .unwrap();
    assert_eq!((c.component.as_str(), c.base), (name.as_str(), 1.0));
    assert!(propensity::component_input(&cad, "friction.law.mu0")
        .unwrap()
        .is_none());
}

/// Prints each basis check: the largest Re λ as the rows run and afresh.
fn print_checks(checks: &[propensity::evaluate::BasisCheck]) {
    for c in checks {
        eprintln!(
            "{:?} {} = {:.4e}: Re {:.6e} /s at {:.2} Hz as the rows run, {:.6e} /s at {:.2} Hz \
             afresh (|dRe| {:.3e} /s, df/f {:.3e}, allowed {:.3e})",
            c.kind,
            c.key,
            c.value,
            c.derivative.0,
            c.derivative.1,
            c.rereduced.0,
            c.rereduced.1,
            c.real_part_change,
            c.frequency_change,
            c.allowed
        );
    }
}

/// One volume's material (the sample brake's inboard pad lining, E₀ = 1e6 psi, under a steel
/// backplate) on the reduced model, the Craig–Bampton basis held fixed:
/// - the volume derivatives of a component add up to the component's (Σ_V K_V = K_c: the
///   lining's and the backplate's against `component_matrix_derivative`, to 1e-10);
/// - against re-reduction at the 0.5 % and 99.5 % quantiles of E ~ U(0.7, 1.3) E₀
///   (`Evaluator::check_basis`): the largest Re λ moves by 0.15 /s of 118 /s and 0.044 /s of
///   147 /s (frequency 4.6e-6): within the default tolerance (5 % of |Re λ|, at least
///   1 /s); with no change allowed the study is refused naming the key.
#[test]
fn one_volume_on_the_reduced_model_is_checked_against_re_reduction() {
    use squeal_pipeline::stages::cea::params::{component_matrix_derivative, ComponentProperty};
    use squeal_pipeline::stages::cea::volume::volume_matrix_derivative;
    let d = tmp("volume");
    let scene = Scene::load(&root().join("examples/sample-brake/base.toml"), &[]).unwrap();
    let dir = RunDir::create(&d.join("run")).unwrap();
    let m = model::build(&scene, &dir, &Progress::quiet()).unwrap();
    let k = |r: squeal_pipeline::stages::cea::params::ReducedDerivative| r.k.unwrap();
    let whole =
        k(
            component_matrix_derivative(&scene, &m, "inboard_pad", ComponentProperty::YoungScale)
                .unwrap(),
        );
    let sum = &k(volume_matrix_derivative(
        &scene,
        &m,
        "inboard_pad",
        "lining",
        ComponentProperty::YoungScale,
    )
    .unwrap())
        + &k(volume_matrix_derivative(
            &scene,
            &m,
            "inboard_pad",
            "backplate",
            ComponentProperty::YoungScale,
        )
        .unwrap());
    let err = (&sum - &whole).norm_max() / whole.norm_max();
    eprintln!("lining + backplate derivative vs the pad's: {err:.3e}");
    assert!(err < 1e-10, "{err}");
    let e = volume_matrix_derivative(
        &scene,
        &m,
        "inboard_pad",
        "linning",
        ComponentProperty::YoungScale,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("linning") && e.contains("lining"), "{e}");

    let key = "components.inboard_pad.materials.lining.young";
    let a = args(&[(key, "uniform(0.7e6, 1.3e6)")], 64);
    let plan = propensity::plan(&scene, &a).unwrap();
    assert!(!plan.rereduce);
    let mut ev = propensity::Evaluator::new(&scene, &plan, &dir, &Progress::quiet(), None).unwrap();
    let checked = ev.check_basis(&plan, &dir, (0.05, 1.0), &Progress::quiet());
    let checks = ev.info().basis_checks;
    print_checks(&checks);
    assert_eq!(checks.len(), 2, "{checked:?}");
    assert!((checks[0].value - 0.703e6).abs() < 1e3 && (checks[1].value - 1.297e6).abs() < 1e3);
    assert_eq!(checked.is_ok(), checks.iter().all(|c| c.passed));
    // No change allowed at all: refused, naming the key and the way out.
    let e = ev
        .check_basis(&plan, &dir, (0.0, 0.0), &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(e.contains(key) && e.contains("--rereduce"), "{e}");
}

/// The CEA's projection basis is made once, at the design's centre, and every row projects on
/// it; the in-band unstable roots are refined exactly either way. On the sample brake with the
/// CEA projected (`auto_single_min_dofs = 0`: the real modes up to 2.5 × the band), for
/// μ0 ~ U(0.35, 0.55) (the law's μ at zero speed; with compliant pairs μ k_n enters K, so the
/// basis moves a little with μ) and the inboard pad's modulus scale ~ U(0.7, 1.3):
/// - `check_basis` compares the shared basis with the row's own at the 0.5 % and 99.5 %
///   quantiles (kind `projection`): μ0 moves the largest Re λ by ≤ 1e-6 /s (3.1e-8 measured),
///   the modulus within the default 5 %;
/// - every row whose largest root is unstable (refined exactly) agrees with the CEA on its own
///   fresh basis to 1e-8 (the refinement makes the root exact whatever the basis), with the
///   same unstable bands;
/// - with no change allowed the study is refused, naming the key and the projection basis.
#[test]
fn the_rows_share_one_projection_basis_and_its_error_is_checked() {
    use propensity::evaluate::BasisKind;
    let d = tmp("projection");
    let scene = Scene::load(
        &root().join("examples/sample-brake/base.toml"),
        &["cea.solver.projection.auto_single_min_dofs=0".to_string()],
    )
    .unwrap();
    for (key, dist, moved) in [
        ("friction.law.mu0", "uniform(0.35, 0.55)", 1e-6),
        (
            "components.inboard_pad.young_scale",
            "uniform(0.7, 1.3)",
            f64::INFINITY,
        ),
    ] {
        let plan = propensity::plan(&scene, &args(&[(key, dist)], 16)).unwrap();
        let dir = RunDir::create(&d.join(key)).unwrap();
        let mut ev =
            propensity::Evaluator::new(&scene, &plan, &dir, &Progress::quiet(), None).unwrap();
        let basis = ev.info().projection_basis.expect("the CEA projects");
        eprintln!(
            "{key}: basis {} modes up to {:.0} Hz",
            basis.n_modes, basis.max_frequency_hz
        );
        assert!(basis.n_modes > 0);
        let checked = ev.check_basis(&plan, &dir, (0.05, 1.0), &Progress::quiet());
        let checks = ev.info().basis_checks;
        print_checks(&checks);
        assert_eq!(checks.len(), 2, "{checks:?}");
        assert!(checks
            .iter()
            .all(|c| c.kind == BasisKind::Projection && c.key == key));
        assert!(checks.iter().all(|c| c.real_part_change <= moved));
        assert!(
            checked.is_ok() && checks.iter().all(|c| c.passed),
            "{checked:?}"
        );
        let eval = |ev: &propensity::Evaluator| {
            plan.design
                .rows
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let s = ev.evaluate(i, &r.values, &Progress::quiet()).unwrap();
                    assert!(s.error.is_none(), "{:?}", s.error);
                    s.outcome.unwrap()
                })
                .collect::<Vec<_>>()
        };
        let shared = eval(&ev);
        let e = ev
            .check_basis(&plan, &dir, (0.0, 0.0), &Progress::quiet())
            .unwrap_err()
            .to_string();
        assert!(e.contains(key) && e.contains("projection basis"), "{e}");
        ev.forget_projection_basis();
        let fresh = eval(&ev);
        let exact_scene = Scene::load(
            &root().join("examples/sample-brake/base.toml"),
            &["cea.solver.method=exact".to_string()],
        )
        .unwrap();
        let ex_ev = propensity::Evaluator::new(&exact_scene, &plan, &dir, &Progress::quiet(), None)
            .unwrap();
        let exact = eval(&ex_ev);
        for (((a, b), c), r) in shared.iter().zip(&fresh).zip(&exact).zip(&plan.design.rows) {
            eprint!("{:?} ", r.values);
            eprintln!(
                "row shared {:.6} {:?} fresh {:.6} {:?} exact {:.6} {:?}",
                a.max_real_part,
                a.unstable_bands,
                b.max_real_part,
                b.unstable_bands,
                c.max_real_part,
                c.unstable_bands
            );
        }
        let mut n_unstable = 0;
        for (a, c) in shared.iter().zip(&exact) {
            assert_eq!(a.unstable, c.unstable, "{a:?} vs {c:?}");
            assert_eq!(a.unstable_bands, c.unstable_bands, "{a:?} vs {c:?}");
            let err = (a.max_real_part - c.max_real_part).abs() / c.max_real_part.abs();
            assert!(err <= 1e-5, "{a:?} vs {c:?}: {err:.3e}");
            n_unstable += usize::from(a.unstable);
        }
        let missed = fresh
            .iter()
            .zip(&exact)
            .filter(|(b, c)| b.unstable_bands != c.unstable_bands)
            .count();
        eprintln!(
            "{key}: {n_unstable} of {} rows unstable; a fresh basis per row misses a band in \
             {missed}",
            shared.len()
        );
        assert!(n_unstable > 0, "the sample brake squeals over these ranges");
    }
}
