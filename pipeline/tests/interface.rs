//! Interface reduction of the rotor's contact boundary (`[components.interface]`): a small
//! brake (a plate rotor clamped on two edges, a pad pressed on the middle of it, non-matching
//! meshes tied by surface pairing) reduced with exact Craig–Bampton and with polynomial
//! interface bases of increasing degree. The CEA roots and the steady-state contact forces
//! approach the exact-CB ones as the degree grows, and equal them to round-off once the basis
//! spans the patch's nodal fields.

mod common;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::cea::{self, CeaArgs};
use squeal_pipeline::stages::model::{self, ReducedModel};
use squeal_pipeline::{PipelineError, RunDir, Scene};
use squeal_reduction::superelement::DofKind;
use squeal_solver::cea::Cplx;

/// The plate brake (`common::plate_brake`) with the pad on the middle of the rotor's top face
/// (rotor cells 1/3, pad cells 1/4: non-matching). `interface`: the rotor's
/// `[components.interface]` table, or "" for exact CB.
fn plate_brake(interface: &str) -> String {
    common::plate_brake(interface, [1.0, 1.0], "")
}

fn interface(degree: usize) -> String {
    format!("interface = {{ degree = {degree} }}")
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("squeal-iface-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene(text: &str, dir: &std::path::Path) -> Result<Scene, PipelineError> {
    Scene::from_toml_str(text, dir.to_path_buf(), &[])
}

use common::build_model as build;

/// CEA roots (sorted by |Im|) and the steady-state contact forces λ̇.
fn cea_of(s: &Scene, m: &ReducedModel) -> (Vec<Cplx>, Vec<f64>) {
    let c = cea::compute(s, m, &Progress::quiet(), &CeaArgs::default()).unwrap();
    let mut r: Vec<_> = c.modes.iter().map(|m| m.eigenvalue).collect();
    r.sort_by(|a, b| a.im.abs().total_cmp(&b.im.abs()));
    (r, c.lin.lambda_dot.clone())
}

/// Largest relative distance from each of the first `k` roots of `a` to the nearest of `b`.
fn root_error(a: &[Cplx], b: &[Cplx], k: usize) -> f64 {
    a.iter()
        .take(k)
        .map(|x| {
            b.iter()
                .map(|y| (x - y).norm() / x.norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

fn rel(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    let n: f64 = b.iter().map(|y| y * y).sum();
    (d / n).sqrt()
}

/// Measured (debug build, `--nocapture`; 25 gaps tie the pad to 16 rotor nodes, 48 rotor
/// boundary DOFs with exact CB, 137 reduced DOFs): largest relative error of the lowest 10
/// CEA roots / relative error of the steady-state contact forces λ̇ —
/// degree 1 (9 interface coordinates): 1.8e-1 / 5.8e-1; degree 2 (18): 3.7e-2 / 4.7e-2;
/// degree 4 (39): 4.2e-4 / 3.8e-3; degree 8 (48, the whole patch): 8.6e-14 / 2.4e-14.
/// (Degree 3, 30 coordinates, not run here: 4.4e-3 / 2.4e-2.)
#[test]
fn interface_basis_converges_to_exact_craig_bampton() {
    let d = tmp("converge");
    let (s0, m0) = build(&plate_brake(""), &d);
    assert!(m0.dofs.recovered.is_empty());
    let (roots0, lam0) = cea_of(&s0, &m0);
    let k = 10.min(roots0.len());
    let rotor_boundary = m0.components[0].n_boundary_dofs;
    let mut rows = Vec::new();
    for degree in [1, 2, 4, 8] {
        let (s, m) = build(&plate_brake(&interface(degree)), &d);
        let n_iface = m
            .dofs
            .dofs
            .iter()
            .filter(|x| matches!(x.kind, DofKind::Interface { .. }))
            .count();
        assert_eq!(
            m.dofs.recovered.len(),
            rotor_boundary,
            "every rotor gap DOF recovered"
        );
        assert!(m.gap_geometry.gaps.iter().all(|g| !g.rotor_rows.is_empty()));
        let (roots, lam) = cea_of(&s, &m);
        let (er, el) = (root_error(&roots0, &roots, k), rel(&lam, &lam0));
        eprintln!(
            "degree {degree}: {n_iface} interface coordinates (exact CB: {rotor_boundary} \
             boundary DOFs), reduced {} DOFs (exact {}): lowest {k} CEA roots {er:.2e}, \
             contact forces {el:.2e}",
            m.n(),
            m0.n()
        );
        rows.push((degree, n_iface, er, el));
    }
    // Nested bases: the errors fall (to round-off plateaus) as the degree grows.
    for w in rows.windows(2) {
        assert!(w[1].2 <= w[0].2 * 1.05 + 1e-10, "roots: {rows:?}");
        assert!(w[1].3 <= w[0].3 * 1.05 + 1e-10, "contact forces: {rows:?}");
    }
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    assert!(
        first.2 > 1e-4 && first.3 > 1e-4,
        "degree 1 is a real restriction: {rows:?}"
    );
    assert!(
        last.2 < 1e-8 && last.3 < 1e-8,
        "a spanning basis is exact CB: {rows:?}"
    );
}

#[test]
fn interface_key_is_validated() {
    let d = tmp("keys");
    let err = |text: &str| scene(text, &d).unwrap_err().to_string();
    let e = err(&plate_brake("interface = { degree = 0 }"));
    assert!(
        e.contains("components[0].interface.degree") && e.contains('0'),
        "{e}"
    );
    let e = err(&plate_brake("interface = { degree = 3, order = 2 }"));
    assert!(e.contains("order"), "{e}");
    // On the pad (the second component) it is an error naming the key.
    let text = plate_brake("").replace(
        "fixed = [{ set = \"x0\", dofs = \"xy\" }]",
        "fixed = [{ set = \"x0\", dofs = \"xy\" }]\ninterface = { degree = 2 }",
    );
    let e = err(&text);
    assert!(
        e.contains("components[1].interface") && e.contains("pad"),
        "{e}"
    );
}

/// An interface-reduced model written by `squeal reduce` (OP4, `dofmap.json` with the
/// interface coordinates and the recovery rows, `gaps.csv`) and read back as a stored model:
/// the same recovery rows per gap and the same CEA roots to round-off.
#[test]
fn interface_model_round_trips_through_a_stored_model() {
    let d = tmp("stored");
    let (s, m) = build(&plate_brake(&interface(2)), &d);
    let run = RunDir::create(&d.join("reduced")).unwrap();
    let gaps = squeal_pipeline::problem::OperatingPoint::of(&s)
        .gaps(&m)
        .unwrap();
    model::write_stored(&m, &gaps, &run).unwrap();
    let stored = r#"title = "stored plate brake, interface-reduced rotor"
units = "consistent"

[model]
from = "op4"
matrices = "reduced/reduced.op4"
dofmap = "reduced/dofmap.json"
gaps = "reduced/gaps.csv"

[friction]
law = { kind = "linear_speed", mu0 = 0.6, slope = -0.05 }
vtol = 1e-3

[rotor]
rpm = 10.0

[loads]
pmax = 2.0
tload = 0.01

[damping]
modal_ratio = 0.01

[cea]
at = "steady_state"
friction_damping = true
"#;
    let (s2, m2) = build(stored, &d);
    assert_eq!(m2.dofs.recovered, m.dofs.recovered);
    for (a, b) in m.gap_geometry.gaps.iter().zip(&m2.gap_geometry.gaps) {
        assert_eq!(a.rotor_rows.len(), b.rotor_rows.len());
        for (x, y) in a.rotor_rows.iter().zip(&b.rotor_rows) {
            assert_eq!(x.dof, y.dof);
            for k in 0..3 {
                assert!(
                    (x.weights[k] - y.weights[k]).abs() < 1e-12,
                    "{x:?} vs {y:?}"
                );
            }
        }
    }
    let ((r1, _), (r2, _)) = (cea_of(&s, &m), cea_of(&s2, &m2));
    let e = root_error(&r1, &r2, r1.len());
    assert!(e < 1e-9, "stored model roots differ by {e:e}");
    // A recovery row pointing past the reduced vector is an error naming it.
    let path = d.join("reduced/dofmap.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut j: serde_json::Value = serde_json::from_str(&text).unwrap();
    j["recovered"][0]["dofs"][0] = serde_json::json!(100_000);
    std::fs::write(&path, serde_json::to_string(&j).unwrap()).unwrap();
    let s3 = scene(stored, &d).unwrap();
    let run3 = RunDir::create(&d.join("run_bad")).unwrap();
    let e = model::build(&s3, &run3, &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(e.contains("recovered[0]") && e.contains("100000"), "{e}");
}

/// The transient sees the rotor through the recovery rows too: the short transient of the
/// plate brake (0.03 s: the load ramps in 0.01 s, then the pad rings), mean pad displacements
/// over [0.01, 0.03] s. With the basis spanning the patch (degree 8) the model is exact CB in
/// other coordinates, so the runs agree to the integrator's tolerance; degree 2 differs more.
/// Measured (debug build): largest relative difference 1.9e-2 (degree 2), 3e-16 (degree 8:
/// the same steps).
#[test]
fn transient_through_recovery_rows_matches_exact_cb() {
    use squeal_pipeline::stages::transient::{self, TransientOptions};
    let d = tmp("transient");
    let extra = "\n[transient]\ntfinal = 0.03\natol1 = 1e-9\nrtol1 = 1e-4\nnoutpt = 2\n";
    let mean_pad = |text: &str| {
        let (s, m) = build(text, &d);
        let opts = TransientOptions {
            keep_history: true,
            ..Default::default()
        };
        let r = transient::compute(&s, &m, &Progress::quiet(), &opts).unwrap();
        let h = r.history.expect("history kept");
        let t = h.column("t").unwrap();
        assert!((t[t.len() - 1] - 0.03).abs() < 1e-12);
        let mut u = std::collections::BTreeMap::new();
        for c in h.columns.iter().filter(|c| c.name.starts_with("u_")) {
            let x = h.column(&c.name).unwrap();
            let mut acc = 0.0;
            for i in 1..t.len() {
                if t[i - 1] >= 0.01 {
                    acc += 0.5 * (x[i] + x[i - 1]) * (t[i] - t[i - 1]);
                }
            }
            u.insert(c.name.clone(), acc / 0.02);
        }
        u
    };
    let exact = mean_pad(&format!("{}{extra}", plate_brake("")));
    let diff = |other: &std::collections::BTreeMap<String, f64>| {
        let common: Vec<_> = exact.keys().filter(|k| other.contains_key(*k)).collect();
        assert!(
            common.len() >= 3,
            "pad DOFs recorded in both runs: {common:?}"
        );
        let scale = common.iter().fold(0.0f64, |s, k| s.max(exact[*k].abs()));
        common
            .iter()
            .fold(0.0f64, |s, k| s.max((exact[*k] - other[*k]).abs()))
            / scale
    };
    let e8 = diff(&mean_pad(&format!("{}{extra}", plate_brake(&interface(8)))));
    let e2 = diff(&mean_pad(&format!("{}{extra}", plate_brake(&interface(2)))));
    eprintln!(
        "transient mean pad displacements against exact CB: degree 2 {e2:.2e}, degree 8 {e8:.2e}"
    );
    assert!(e8 < 1e-4 && e8 < e2, "degree 8 {e8:e}, degree 2 {e2:e}");
}
