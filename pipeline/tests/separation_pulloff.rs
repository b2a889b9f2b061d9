//! A pad at zero preload pulled off the rotor, through the whole pipeline (scene → model →
//! transient): issue 26, "with P0 = 0 and a load pulling the pads off, no gap ever opens"
//! (the run held every gap in tension, 320 048 tensile gap-steps, and the verdict was
//! `squeal`).
//!
//! Scene: a block pad (1 × 1 × 1, hex8 2×2×2) on a block rotor (hex8 2×2×1, its base fixed),
//! tied by `pairing = "surface"`; the pad is held in x, y on its abutment face `x0` and in z
//! on its top `z1`, and a force +z (away from the rotor) on its trailing face `y1` is ramped
//! in TLOAD. P0 = 0: at t = 0 every gap carries exactly zero pressure, and any t > 0 needs
//! tension to keep the pad's contact face on the rotor. Reference (exact, no number to
//! compute): with unilateral contact no gap may carry tension, so the run has no tensile
//! gap-step and the gaps the pull lifts open at the ramp's start; bilateral (the paper's
//! contact) the same scene is tensile from the first step — which shows what the check
//! would see if the crossing at zero were missed.

use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::model;
use squeal_pipeline::stages::transient::guard::VerdictState;
use squeal_pipeline::stages::transient::{self, guard::Unresolved, TransientOptions};
use squeal_pipeline::{RunDir, Scene};

fn pulled_pad(separation: bool) -> String {
    format!(
        r#"title = "a pad at P0 = 0 pulled off the rotor"
units = "consistent"

[[components]]
name = "rotor"
element = "hex8"
geometry = {{ kind = "block", origin = [2.0, -0.5, -0.2], lx = 1.0, ly = 1.0, lz = 0.2, nx = 2, ny = 2, nz = 1 }}
material = {{ young = 1.0e4, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "z0" }}]

[[components]]
name = "pad"
element = "hex8"
geometry = {{ kind = "block", origin = [2.0, -0.5, 0.0], lx = 1.0, ly = 1.0, lz = 1.0, nx = 2, ny = 2, nz = 2 }}
material = {{ young = 5.0e3, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "x0", dofs = "xy" }}, {{ set = "z1", dofs = "z" }}]

[reduction]
n_modes = 6

[[contact]]
pad = "pad"
pad_faces = "z0"
rotor = "rotor"
rotor_faces = "z1"
pairing = "surface"
p0 = 0.0
separation = {separation}

[friction]
law = {{ kind = "constant", mu = 0.5 }}

[rotor]
rpm = 10.0

[loads]
pmax = 1.0
tload = 0.005
force = [{{ component = "pad", nodes = "y1", force = [0.0, 0.0, 1.0] }}]

[damping]
modal_ratio = 0.02

[transient]
tfinal = 0.02
"#
    )
}

#[test]
fn a_pad_at_zero_preload_pulled_off_opens_and_holds_no_tension() {
    let d = std::env::temp_dir().join(format!("squeal-pulloff-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let build = |separation: bool| {
        let scene = Scene::from_toml_str(&pulled_pad(separation), d.clone(), &[]).unwrap();
        let run = RunDir::create(&d.join(format!("run-{separation}"))).unwrap();
        let m = model::build(&scene, &run, &Progress::quiet()).unwrap();
        (scene, m)
    };
    let opts = TransientOptions::default();

    // Bilateral: the pull holds gaps in tension from the start (what the bug did with
    // separation on).
    let (scene, m) = build(false);
    let r = transient::compute(&scene, &m, &Progress::quiet(), &opts).unwrap();
    eprintln!(
        "bilateral: {:?}, {} tensile gap-steps, min p_n {:?}, verdict {:?}",
        r.status, r.contact.tensile_gap_steps, r.contact.min_pressure, r.verdict.state
    );
    assert!(r.contact.tensile_gap_steps > 0, "{:?}", r.contact);

    // Unilateral: the gaps open at the start of the pull, none carries tension.
    let (scene, m) = build(true);
    let r = transient::compute(&scene, &m, &Progress::quiet(), &opts).unwrap();
    let s = r.separation.as_ref().expect("separation stats");
    eprintln!(
        "unilateral: {:?}, {} steps, {} tensile gap-steps, min p_n {:?}, openings {}, \
         closings {}, first separation {:?}, max open {}, drift {:e}, verdict {:?}",
        r.status,
        r.steps,
        r.contact.tensile_gap_steps,
        r.contact.min_pressure,
        s.openings,
        s.closings,
        s.first_separation_t,
        s.max_open,
        r.max_constraint_drift,
        r.verdict.state
    );
    assert!(r.status.is_success(), "{:?}", r.status);
    assert!(s.openings > 0, "{s:?}");
    let t_open = s.first_separation_t.expect("a gap opened");
    assert!(
        t_open < 1e-3 * 0.005,
        "first opening at {t_open} (the pull starts at 0)"
    );
    assert_eq!(r.contact.tensile_gap_steps, 0, "{:?}", r.contact);
    assert!(
        r.contact.first_tensile_after_ramp.is_none(),
        "{:?}",
        r.contact
    );
    // Closed rows hold: the drift counts the closed rigid rows only (an open gap's G v is its
    // lift-off speed).
    assert!(r.max_constraint_drift < 1e-8, "{}", r.max_constraint_drift);
    match &r.verdict.state {
        VerdictState::Squeal => panic!("squeal from a pad pulled off: {:?}", r.verdict),
        VerdictState::Unresolved { reasons } => assert!(
            !reasons
                .iter()
                .any(|x| matches!(x, Unresolved::ContactTensile(_))),
            "{reasons:?}"
        ),
        _ => {}
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// The keys of contact that opens (README "Unilateral contact"): bad values are errors naming
/// the key and the value; good ones load.
#[test]
fn separation_keys_are_checked_naming_key_and_value() {
    let d = std::env::temp_dir();
    let load = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        Scene::from_toml_str(&pulled_pad(true), d.clone(), &sets).map_err(|e| e.to_string())
    };
    for (sets, key, shown) in [
        (
            &[
                "contact.0.normal_stiffness=1e6",
                "contact.0.separation_smoothing=0.0",
            ][..],
            "contact[0].separation_smoothing",
            "0 must be finite and > 0",
        ),
        (
            &[
                "contact.0.normal_stiffness=1e6",
                "contact.0.separation_smoothing=nan",
            ],
            "contact[0].separation_smoothing",
            "NaN must",
        ),
        // The smooth law is a compliant gap's.
        (
            &["contact.0.separation_smoothing=0.1"],
            "contact[0].separation_smoothing",
            "normal_stiffness absent",
        ),
        (
            &[
                "contact.0.normal_stiffness=1e6",
                "contact.0.separation=false",
                "contact.0.separation_smoothing=0.1",
            ],
            "contact[0].separation_smoothing",
            "separation = false",
        ),
        (
            &["transient.collapse_factor=-1.0"],
            "transient.collapse_factor",
            "-1 must be finite and >= 0",
        ),
        (
            &["transient.collapse_steps=0"],
            "transient.collapse_steps",
            "0 must be >= 1",
        ),
        (
            &["transient.event_restart=\"order3\""],
            "event_restart",
            "order3",
        ),
    ] {
        let e = load(sets).expect_err(&format!("{sets:?} must be refused"));
        assert!(e.contains(key) && e.contains(shown), "{sets:?}: {e}");
    }
    for sets in [
        &[
            "contact.0.normal_stiffness=1e6",
            "contact.0.separation_smoothing=0.1",
        ][..],
        &[
            "transient.event_restart=\"order1\"",
            "transient.collapse_factor=0.0",
        ],
    ] {
        load(sets).unwrap_or_else(|e| panic!("{sets:?}: {e}"));
    }
}

/// `transient.collapse_factor` and `collapse_steps` reach the integrator, and a collapse ends
/// the run at once as `unresolved` (`stopped`, status `step_collapse`): with the factor 0.5 the
/// threshold is 2 h_max (h_max = the band bound 1/(40 × 10 kHz) = 2.5e-6 s), which every step
/// is below, so the first 5 steps are a "collapse" by construction.
#[test]
fn a_collapsed_step_stops_the_run_and_the_verdict_says_so() {
    use squeal_solver::bdf::Status;
    let d = std::env::temp_dir().join(format!("squeal-collapse-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let sets: Vec<String> = [
        "transient.collapse_factor=0.5",
        "transient.collapse_steps=5",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let scene = Scene::from_toml_str(&pulled_pad(false), d.clone(), &sets).unwrap();
    let run = RunDir::create(&d.join("run")).unwrap();
    let m = model::build(&scene, &run, &Progress::quiet()).unwrap();
    let r =
        transient::compute(&scene, &m, &Progress::quiet(), &TransientOptions::default()).unwrap();
    match &r.status {
        Status::StepCollapse {
            h_collapse, steps, ..
        } => {
            assert_eq!(*h_collapse, 2.0 * 2.5e-6);
            assert_eq!(*steps, 5);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(r.steps, 5);
    assert!(
        matches!(&r.verdict.state, VerdictState::Unresolved { reasons }
            if reasons.iter().any(|x| matches!(x, Unresolved::Stopped { .. }))),
        "{:?}",
        r.verdict.state
    );
    let _ = std::fs::remove_dir_all(&d);
}
