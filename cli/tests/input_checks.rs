//! Bad input is an error naming the file, line or key and the value (issue 14): stored-model
//! inputs (gap table, DOF map, matrices), scene numbers, and the warnings channel.

mod common;

use common::{json, root, run, squeal, tmp};
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::accuracy::models::{self, StoredModel};
use squeal_pipeline::stages::model::{self, ReducedModel};
use squeal_pipeline::{RunDir, Scene};
use std::path::{Path, PathBuf};

const HEADER: &str = "pad_grid,rotor_grid,x,y,z,nx,ny,nz,area,p0,temperature";
const GAP: &str = "1,100001,1,0,0,0,0,1,1,10,0";

/// The belt model (3 DOFs, one gap; `stages::accuracy::models::belt`) as `m.op4`,
/// `m.dofmap.json`, `m.gaps.csv` with a scene `scene.toml` reading them.
fn fixture(name: &str, model: &StoredModel) -> (PathBuf, PathBuf) {
    let dir = tmp(name);
    model.write(&dir, "m").unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        format!(
            "[model]\nfrom = \"op4\"\nmatrices = \"m.op4\"\ndofmap = \"m.dofmap.json\"\n\
             gaps = \"m.gaps.csv\"\n\n[friction]\nlaw = {{ kind = \"constant\", mu = 0.3 }}\n\n\
             [rotor]\nrpm = {}\n\n[loads]\npmax = 0.05\ntload = 0.0\n\n\
             [transient]\ntfinal = 0.01\nnrstrt = 0\n\n[cea]\n",
            models::RPM
        ),
    )
    .unwrap();
    (dir, scene)
}

/// The reduced model of the scene, or the error's text.
fn build(scene: &Path) -> Result<ReducedModel, String> {
    let s = Scene::load(scene, &[]).map_err(|e| e.to_string())?;
    let rd = RunDir::create(&scene.parent().unwrap().join("run")).unwrap();
    model::build(&s, &rd, &Progress::quiet()).map_err(|e| e.to_string())
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

#[test]
fn gap_table_values_are_checked_naming_line_column_and_value() {
    let (dir, scene) = fixture("input-gap-values", &models::belt());
    assert!(build(&scene).is_ok());
    let col = |c: &str| HEADER.split(',').position(|h| h == c).unwrap();
    for (c, v, shown) in [
        ("area", "-0.5", "-0.5"),
        ("area", "0", "0"),
        ("area", "nan", "NaN"),
        ("area", "inf", "inf"),
        ("p0", "nan", "NaN"),
        ("p0", "-1", "-1"),
        ("x", "nan", "NaN"),
        ("z", "-inf", "-inf"),
        ("temperature", "inf", "inf"),
    ] {
        let mut f: Vec<&str> = GAP.split(',').collect();
        f[col(c)] = v;
        write(&dir, "m.gaps.csv", &format!("{HEADER}\n{}\n", f.join(",")));
        let e = build(&scene).unwrap_err();
        for want in [
            "m.gaps.csv",
            "line 2",
            &format!("column `{c}`"),
            &format!(": {shown} must"),
        ] {
            assert!(e.contains(want), "{c} = {v}: `{want}` not in: {e}");
        }
    }
    // A zero normal, and a pad grid that is also the rotor grid.
    write(
        &dir,
        "m.gaps.csv",
        &format!("{HEADER}\n1,100001,1,0,0,0,0,0,1,10,0\n"),
    );
    let e = build(&scene).unwrap_err();
    assert!(e.contains("line 2") && e.contains("normal"), "{e}");
    write(
        &dir,
        "m.gaps.csv",
        &format!("{HEADER}\n1,1,1,0,0,0,0,1,1,10,0\n"),
    );
    let e = build(&scene).unwrap_err();
    assert!(e.contains("line 2") && e.contains("both 1"), "{e}");
}

/// The old reader skipped line 1 unread: a file without a header lost its first gap.
#[test]
fn gap_table_without_header_is_an_error_not_a_lost_gap() {
    let (dir, scene) = fixture("input-gap-header", &models::belt());
    write(&dir, "m.gaps.csv", &format!("{GAP}\n"));
    let e = build(&scene).unwrap_err();
    assert!(
        e.contains("m.gaps.csv") && e.contains("line 1") && e.contains("not a header"),
        "{e}"
    );
    write(&dir, "m.gaps.csv", "");
    assert!(build(&scene).unwrap_err().contains("empty"));
}

/// The old reader read columns by position: `rotor_grid,pad_grid,…` swapped pad and rotor.
#[test]
fn gap_table_columns_are_read_by_name() {
    let (dir, scene) = fixture("input-gap-order", &models::belt());
    let want = build(&scene).unwrap().gap_geometry;
    // Reversed columns, blank lines and spaces around fields.
    let rev = |l: &str| l.split(',').rev().collect::<Vec<_>>().join(" , ");
    write(
        &dir,
        "m.gaps.csv",
        &format!("\n{}\n\n{}\n", rev(HEADER), rev(GAP)),
    );
    let got = build(&scene).unwrap().gap_geometry;
    assert_eq!(got, want);
    assert_eq!(got.gaps[0].pad_node, 1);
    assert_eq!(got.gaps[0].rotor_node, 100001);
    for (text, want) in [
        (
            format!("{HEADER},colour\n{GAP},red\n"),
            "unknown column `colour`",
        ),
        (
            format!(
                "{}\n1,100001,1,0,0,0,0,1,1,10\n",
                &HEADER[..HEADER.len() - 12]
            ),
            "missing column(s) `temperature`",
        ),
        (
            format!("{HEADER},area\n{GAP},1\n"),
            "column `area` appears twice (columns 9 and 12)",
        ),
        (
            format!("{HEADER}\n{GAP},7\n"),
            "line 2: 12 fields, the header has 11",
        ),
        (
            format!("{HEADER}\n{GAP}\n{GAP}\n"),
            "line 3: pad grid 1 already has this gap (line 2)",
        ),
    ] {
        write(&dir, "m.gaps.csv", &text);
        let e = build(&scene).unwrap_err();
        assert!(
            e.contains("m.gaps.csv") && e.contains(want),
            "`{want}` not in: {e}"
        );
    }
}

#[test]
fn json_gap_table_is_checked_too() {
    let (dir, scene) = fixture("input-gap-json", &models::belt());
    let good = build(&scene).unwrap();
    let mut gaps = good.gap_geometry.gaps.clone();
    std::fs::write(
        dir.join("m.gaps.json"),
        serde_json::to_string(&gaps).unwrap(),
    )
    .unwrap();
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("m.gaps.csv", "m.gaps.json");
    std::fs::write(&scene, text).unwrap();
    assert_eq!(build(&scene).unwrap().gap_geometry, good.gap_geometry);
    gaps[0].area = -2.0;
    std::fs::write(
        dir.join("m.gaps.json"),
        serde_json::to_string(&gaps).unwrap(),
    )
    .unwrap();
    let e = build(&scene).unwrap_err();
    assert!(
        e.contains("m.gaps.json: gap 0, column `area`: -2 must be finite and > 0"),
        "{e}"
    );
    gaps[0].area = 1.0;
    gaps[0].normal = [0.0, 0.0, 2.0];
    std::fs::write(
        dir.join("m.gaps.json"),
        serde_json::to_string(&gaps).unwrap(),
    )
    .unwrap();
    let e = build(&scene).unwrap_err();
    assert!(e.contains("gap 0") && e.contains("unit vector"), "{e}");
}

/// A DOF listed twice was accepted, and one DOF disappeared.
#[test]
fn dofmap_with_a_dof_twice_names_both_entries() {
    let (dir, scene) = fixture("input-dofmap", &models::belt());
    let text = std::fs::read_to_string(dir.join("m.dofmap.json")).unwrap();
    // The third DOF (rotor grid 100001, z) becomes a second pad grid 1, z.
    let twice = text
        .replacen("\"grid\": 100001", "\"grid\": 1", 1)
        .replacen("\"rotor\"", "\"pad\"", 1);
    assert_ne!(twice, text);
    write(&dir, "m.dofmap.json", &twice);
    let e = build(&scene).unwrap_err();
    assert!(
        e.contains("m.dofmap.json")
            && e.contains("dofs[1] and dofs[2] are both grid 1 component 3"),
        "{e}"
    );
}

/// A non-symmetric KR was symmetrised without a word: now a warning with the measured value
/// below the tolerance, an error above it.
#[test]
fn asymmetric_stiffness_warns_below_the_tolerance_and_fails_above() {
    let mut m = models::belt();
    // The largest entry of KR is 50 (pad z and rotor z).
    let big = 50.0;
    m.k[(1, 0)] = 1e-8 * big;
    let (_, scene) = fixture("input-asym-small", &m);
    let model = build(&scene).unwrap();
    assert_eq!(model.warnings.len(), 1, "{:?}", model.warnings);
    let w = &model.warnings[0];
    assert!(
        (w.value - 1e-8).abs() < 1e-12 && w.input.contains("matrix KR"),
        "{w:?}"
    );
    assert_eq!(model.k[(1, 0)], model.k[(0, 1)]);
    assert_eq!(model.k[(1, 0)], 0.5e-8 * big);
    m.k[(1, 0)] = 1e-3 * big;
    let (_, scene) = fixture("input-asym-large", &m);
    let e = build(&scene).unwrap_err();
    assert!(
        e.contains("m.op4") && e.contains("matrix KR is not symmetric") && e.contains("1.000e-3"),
        "{e}"
    );
    let mut m = models::belt();
    m.m[(2, 1)] = 0.5;
    let (_, scene) = fixture("input-asym-mass", &m);
    let e = build(&scene).unwrap_err();
    assert!(e.contains("matrix MR is not symmetric"), "{e}");
}

/// An indefinite MR was accepted by `transient` (only `cea` rejected it); both verbs now stop
/// before computing, naming the matrix and its smallest eigenvalue.
#[test]
fn indefinite_or_singular_mass_is_rejected_by_transient_and_cea() {
    let mut m = models::belt();
    m.m[(1, 1)] = -2.0;
    let (dir, scene) = fixture("input-mass-indefinite", &m);
    for verb in ["transient", "cea"] {
        let (ok, _, err) = run(squeal()
            .args([verb, "-q"])
            .arg(&scene)
            .arg("--out")
            .arg(dir.join(verb)));
        assert!(!ok, "{verb} accepted an indefinite MR");
        assert!(
            err.contains("m.op4")
                && err.contains("matrix MR")
                && err.contains("indefinite")
                && err.contains("smallest eigenvalue -2.000000e0"),
            "{verb}: {err}"
        );
    }
    let mut m = models::belt();
    m.m[(2, 2)] = 0.0;
    let (_, scene) = fixture("input-mass-singular", &m);
    let e = build(&scene).unwrap_err();
    assert!(
        e.contains("matrix MR") && e.contains("singular") && e.contains("smallest eigenvalue 0"),
        "{e}"
    );
}

/// The warning reaches `summary.json` and the command's stderr.
#[test]
fn warnings_are_printed_and_written_to_the_summary() {
    let mut m = models::belt();
    m.k[(1, 0)] = 2e-7 * 50.0;
    let (dir, scene) = fixture("input-warning-cli", &m);
    let out = dir.join("run-cli");
    let (ok, _, err) = run(squeal()
        .args(["transient", "-q"])
        .arg(&scene)
        .arg("--out")
        .arg(&out));
    assert!(ok, "{err}");
    assert!(
        err.contains("squeal: warning:") && err.contains("matrix KR") && err.contains("2.000e-7"),
        "{err}"
    );
    let s = json(&out.join("summary.json"));
    let w = &s["warnings"][0];
    assert!((w["value"].as_f64().unwrap() - 2e-7).abs() < 1e-15, "{w}");
    assert_eq!(w["tolerance"].as_f64(), Some(1e-6));
}

#[test]
fn model_p0_temperature_and_rotor_origin_must_be_finite() {
    let (_, scene) = fixture("input-scene-numbers", &models::belt());
    for (set, key) in [
        ("model.p0=nan", "model.p0"),
        ("model.p0=-1.0", "model.p0"),
        ("model.p0=inf", "model.p0"),
        ("model.temperature=nan", "model.temperature"),
        ("rotor.origin=[0.0, nan, 0.0]", "rotor.origin"),
        ("rotor.origin=[inf, 0.0, 0.0]", "rotor.origin"),
    ] {
        let e = Scene::load(&scene, &[set.to_string()])
            .unwrap_err()
            .to_string();
        assert!(e.contains(&format!("`{key}`")), "{set}: {e}");
    }
    assert!(Scene::load(&scene, &["model.p0=0.0".to_string()]).is_ok());
}

#[test]
fn normal_stiffness_must_be_finite_and_positive() {
    let scene = root().join("examples/transient/tiny-brake.toml");
    for (set, shown) in [
        ("contact.0.normal_stiffness=0.0", "0 must"),
        ("contact.0.normal_stiffness=-1e6", "-1000000 must"),
        ("contact.0.normal_stiffness=nan", "NaN must"),
        ("contact.0.normal_stiffness=inf", "inf must"),
    ] {
        let e = Scene::load(&scene, &[set.to_string()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`contact[0].normal_stiffness`") && e.contains(shown),
            "{set}: {e}"
        );
    }
    assert!(Scene::load(&scene, &["contact.0.normal_stiffness=1e6".to_string()]).is_ok());
}

/// Every float leaf of a resolved scene, as a `--set` key and the assignments that put NaN,
/// +inf and −inf there (a float in an array is set by writing the whole array).
fn non_finite_assignments(doc: &toml::Value) -> Vec<(String, Vec<String>)> {
    let mut keys = Vec::new();
    float_keys(doc, "", &mut keys);
    let mut out = Vec::new();
    for key in keys {
        let segs: Vec<&str> = key.split('.').collect();
        let arr_at = segs
            .iter()
            .position(|s| s.parse::<usize>().is_ok())
            .filter(|&i| {
                // An index into an array of numbers (not an array of tables such as components.0).
                let mut v = doc;
                for s in &segs[..i] {
                    v = match v {
                        toml::Value::Table(t) => &t[*s],
                        toml::Value::Array(a) => &a[s.parse::<usize>().unwrap()],
                        _ => unreachable!(),
                    };
                }
                matches!(v, toml::Value::Array(a) if a.iter().all(|x| !x.is_table()))
            });
        let sets = ["nan", "inf", "-inf"]
            .iter()
            .map(|bad| match arr_at {
                None => format!("{key}={bad}"),
                Some(i) => {
                    let mut v = doc;
                    for s in &segs[..i] {
                        v = match v {
                            toml::Value::Table(t) => &t[*s],
                            toml::Value::Array(a) => &a[s.parse::<usize>().unwrap()],
                            _ => unreachable!(),
                        };
                    }
                    let mut arr = v.clone();
                    let mut slot = &mut arr;
                    for s in &segs[i..] {
                        slot = match slot {
                            toml::Value::Array(a) => &mut a[s.parse::<usize>().unwrap()],
                            toml::Value::Table(t) => t.get_mut(*s).unwrap(),
                            _ => unreachable!(),
                        };
                    }
                    *slot = toml::Value::Float(bad.parse().unwrap());
                    let text = toml::Value::Array(vec![arr]).to_string();
                    // `[[...]]` → the inner array's text.
                    let inner = text
                        .trim()
                        .strip_prefix('[')
                        .unwrap()
                        .strip_suffix(']')
                        .unwrap();
                    format!("{}={inner}", segs[..i].join("."))
                }
            })
            .collect();
        out.push((key, sets));
    }
    out
}

/// Every float leaf of a resolved scene, as `--set` keys (`rotor.origin.0`, `contact.0.p0`).
fn float_keys(v: &toml::Value, prefix: &str, out: &mut Vec<String>) {
    let key = |k: &str| {
        if prefix.is_empty() {
            k.to_string()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match v {
        toml::Value::Float(_) => out.push(prefix.to_string()),
        toml::Value::Table(t) => {
            for (k, x) in t {
                float_keys(x, &key(k), out);
            }
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                float_keys(x, &key(&i.to_string()), out);
            }
        }
        _ => {}
    }
}

fn example_scenes() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for dir in [
        "examples",
        "examples/accuracy",
        "examples/cea",
        "examples/transient",
        "examples/verification",
        "examples/sample-brake",
        "examples/interface-flutter",
    ] {
        for e in std::fs::read_dir(root().join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "toml")
                && !p
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("study"))
                && !p.ends_with("components.toml")
            {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// NaN, +inf and −inf in any number of any example scene are rejected by `Scene::load`, and the
/// error names the key (its last name segment).
#[test]
fn non_finite_scene_numbers_are_rejected_naming_the_key() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for path in example_scenes() {
        let scene = Scene::load(&path, &[]).unwrap();
        let doc: toml::Value = toml::from_str(&scene.resolved_toml()).unwrap();
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        for (key, sets) in non_finite_assignments(&doc) {
            let name = key
                .split('.')
                .rev()
                .find(|s| s.parse::<usize>().is_err())
                .unwrap()
                .to_string();
            for set in sets {
                checked += 1;
                match Scene::load(&path, std::slice::from_ref(&set)) {
                    Ok(_) => failures.push(format!("{file}: {set} accepted")),
                    Err(e) if !e.to_string().contains(&name) => failures.push(format!(
                        "{file}: {set}: error does not name `{name}`: {}",
                        e.to_string().lines().next().unwrap_or("")
                    )),
                    Err(_) => {}
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} cases");
    failures.sort();
    failures.dedup();
    assert!(
        failures.is_empty(),
        "{} of {checked}:\n{}",
        failures.len(),
        failures[..failures.len().min(60)].join("\n")
    );
}

/// A restart file with one field edited: the run stops before integrating, naming the file
/// and the field. Two of these panicked (an order above MAXORD: index out of bounds in
/// bdf/coeffs.rs; an empty order histogram: bdf/step.rs), two named no file (h ≤ 0, a short yp).
#[test]
fn restart_fields_are_checked_naming_the_file_and_the_field() {
    let (dir, scene) = fixture("input-restart", &models::belt());
    let s = Scene::load(&scene, &[]).unwrap();
    let first = RunDir::create(&dir.join("first")).unwrap();
    squeal_pipeline::stages::transient::run(&s, &first, &Progress::quiet(), None).unwrap();
    let good: serde_json::Value = json(&first.path("restart.json"));
    assert!(good["state"]["stats"]["steps"].as_u64().unwrap() > 10);
    let resume = |r: &serde_json::Value, extra: &[&str]| -> Result<(), String> {
        let p = dir.join("edited.restart.json");
        std::fs::write(&p, serde_json::to_string(r).unwrap()).unwrap();
        let mut set = vec![
            format!("transient.restart=\"{}\"", p.display()),
            "transient.tfinal=0.02".to_string(),
        ];
        set.extend(extra.iter().map(|s| s.to_string()));
        let s = Scene::load(&scene, &set).map_err(|e| e.to_string())?;
        let out = RunDir::create(&dir.join("resumed")).unwrap();
        squeal_pipeline::stages::transient::run(&s, &out, &Progress::quiet(), None)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    resume(&good, &[]).unwrap();
    type Edit = fn(&mut serde_json::Value);
    let cases: [(&str, Edit, &str); 15] = [
        (
            "order above MAXORD",
            |r| r["state"]["order"] = 7.into(),
            "field `state.order`: 7 is not in 1..=2",
        ),
        (
            "empty order histogram",
            |r| r["state"]["stats"]["order_histogram"] = serde_json::json!([]),
            "field `state.stats.order_histogram`: has 0 entries",
        ),
        (
            "negative h",
            |r| r["state"]["h"] = (-1e-3).into(),
            "field `state.h`: -0.001 must be finite and > 0",
        ),
        (
            "zero h",
            |r| r["state"]["h"] = 0.0.into(),
            "field `state.h`: 0 must be",
        ),
        (
            "short yp",
            |r| {
                r["state"]["yp"].as_array_mut().unwrap().pop();
            },
            "field `state.yp`: has 6 entries, expected 7",
        ),
        (
            "short phi row",
            |r| {
                r["state"]["phi"][1].as_array_mut().unwrap().pop();
            },
            "field `state.phi[1]`: has 6 entries",
        ),
        (
            "k_used above MAXORD",
            |r| r["state"]["k_used"] = 4.into(),
            "field `state.k_used`",
        ),
        (
            "phase 2",
            |r| r["state"]["phase"] = 2.into(),
            "field `state.phase`",
        ),
        ("time", |r| r["t"] = 1.0.into(), "field `t`: 1 differs"),
        (
            "max_order",
            |r| r["max_order"] = 9.into(),
            "field `max_order`: 9 is not a BDF order",
        ),
        (
            "state n",
            |r| r["state"]["n"] = 5.into(),
            "field `state.n`: 5 differs from 2n + ng = 7",
        ),
        // The run's checkpoint (records resumed).
        (
            "start after the state",
            |r| r["run"]["t_start"] = 1.0.into(),
            "field `run.t_start`: 1 is not a start time at or before",
        ),
        (
            "steps",
            |r| r["run"]["steps"] = 3.into(),
            "field `run.steps`: 3 differs from the state's",
        ),
        (
            "energy integrals elsewhere",
            |r| r["run"]["energy"]["balance"]["t"] = 0.5.into(),
            "field `run.energy.balance.t`",
        ),
        (
            "response DOF",
            |r| r["run"]["records"]["response_dofs"] = serde_json::json!([99]),
            "field `run.records.response_dofs`: DOF 99 is out of range",
        ),
    ];
    for (what, edit, want) in cases {
        let mut r = good.clone();
        edit(&mut r);
        let e = resume(&r, &[]).unwrap_err();
        assert!(
            e.contains("edited.restart.json") && e.contains(want),
            "{what}: {e}"
        );
    }
    // Another MAXORD than the run that wrote it.
    let e = resume(&good, &["transient.maxord=3"]).unwrap_err();
    assert!(
        e.contains("edited.restart.json: field `max_order`: 2") && e.contains("maxord is 3"),
        "{e}"
    );
}

/// A sweep in which one value failed exited 0. Now: the other values' results and every
/// sweep file are written, then `squeal sweep` exits 3 (`sweep::EXIT_VALUES_FAILED`).
#[test]
fn sweep_with_a_failed_value_exits_3_after_writing_the_others() {
    let (dir, scene) = fixture("input-sweep-exit", &models::belt());
    write(
        &dir,
        "bad.gaps.csv",
        &format!("{HEADER}\n1,100001,1,0,0,0,0,1,-0.5,10,0\n"),
    );
    let out = dir.join("sweep");
    let cmd = |values: &str| {
        let mut c = squeal();
        c.args(["-q", "sweep"])
            .arg(&scene)
            .args(["--param", "model.gaps", "--values", values, "--cache"])
            .arg(dir.join("cache"))
            .arg("--out")
            .arg(&out);
        c.output().unwrap()
    };
    let o = cmd("bad.gaps.csv,m.gaps.csv");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert_eq!(squeal_pipeline::stages::sweep::EXIT_VALUES_FAILED, 3);
    assert!(err.contains("1 value(s) failed: bad.gaps.csv"), "{err}");
    let rep = json(&out.join("sweep.json"));
    assert_eq!(rep["n_failed"], 1);
    assert!(rep["points"][0]["error"]
        .as_str()
        .unwrap()
        .contains("bad.gaps.csv: line 2, column `area`"));
    assert!(rep["points"][1]["error"].is_null());
    for f in [
        "01_m.gaps.csv/cea/cea.json",
        "sweep.md",
        "summary.json",
        "sweep_indicators.svg",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    // Every value ran: 0.
    let o = cmd("m.gaps.csv");
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(json(&out.join("sweep.json"))["n_failed"], 0);
}

// ------------------------------------------------------------------ issue 26

/// An indefinite stored KR is refused with its most negative eigenvalue; a gap normal with
/// no component along its grids' DOFs names the gap and the normal; an empty DOF map is an
/// error. Reference: the belt's (K, M) is diagonal, so its eigenvalues are k_ii/m_ii
/// (−50/2 = −25 with KR[1,1] = −50).
#[test]
fn indefinite_stiffness_unusable_normal_and_empty_model_are_named() {
    let mut m = models::belt();
    m.k[(1, 1)] = -50.0;
    let (_, scene) = fixture("input-k-indefinite", &m);
    let e = build(&scene).unwrap_err();
    assert!(
        e.contains("m.op4") && e.contains("matrix KR is indefinite") && e.contains("-2.500000e1"),
        "{e}"
    );
    // Belt DOFs: pad y, z and rotor z; a normal along x touches none of them.
    let mut m = models::belt();
    m.gaps[0].2 = [1.0, 0.0, 0.0];
    let (_, scene) = fixture("input-normal-unusable", &m);
    let e = build(&scene).unwrap_err();
    assert!(
        e.contains("m.gaps.csv")
            && e.contains("gap 0 (pad grid 1, rotor grid 100001")
            && e.contains("[1.0, 0.0, 0.0]")
            && e.contains("pad: yz; rotor: z"),
        "{e}"
    );
    let empty = squeal_pipeline::scene::StoredArrays {
        k: faer::Mat::zeros(0, 0),
        m: faer::Mat::zeros(0, 0),
        b: None,
        p_brake: None,
        dofs: squeal_reduction::superelement::ReducedDofMap {
            dofs: Vec::new(),
            recovered: Vec::new(),
        },
        gaps: Vec::new(),
    };
    let s = Scene::with_arrays("[cea]\n", ".", &[], empty).unwrap();
    let rd = RunDir::create(&tmp("input-empty-model")).unwrap();
    let e = model::build(&s, &rd, &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(e.contains("<arrays>.dofs") && e.contains("no DOF"), "{e}");
}

/// μ = 1e300 is refused when the scene is read, with the bound; a component whose fixed sets
/// hold every node names the key, the sets and the mesh; a second `[[contact]]` table or a
/// pair P0 on a stored model is an error (they would be ignored).
#[test]
fn huge_mu_all_fixed_and_ignored_pair_keys_are_refused() {
    let tiny = root().join("examples/transient/tiny-brake.toml");
    let (ok, _, err) = run(squeal()
        .arg("check")
        .arg(&tiny)
        .args(["--set", "friction.law={kind=\"constant\",mu=1e300}"]));
    assert!(!ok);
    assert!(
        err.contains("friction.mu") && err.contains("1e300") && err.contains("[0, 10]"),
        "{err}"
    );
    let d = tmp("input-all-fixed");
    let (ok, _, err) = run(squeal()
        .args(["-q", "reduce"])
        .arg(&tiny)
        .arg("--out")
        .arg(&d)
        .args(["--set", "components.0.fixed=[{set=\"z0\"},{set=\"z1\"}]"]));
    assert!(!ok);
    assert!(
        err.contains("components[0].fixed")
            && err.contains("`z0`")
            && err.contains("`z1`")
            && err.contains("rotor.msh")
            && err.contains("no free DOF"),
        "{err}"
    );
    let (_, scene) = fixture("input-stored-pairs", &models::belt());
    let pair = "{pad=\"pad\",pad_faces=\"f\",rotor=\"rotor\",rotor_faces=\"g\"}";
    let two = format!("contact=[{pair},{pair}]");
    let s = Scene::load(&scene, &[two]).unwrap();
    let rd = RunDir::create(&tmp("input-stored-pairs-run")).unwrap();
    let e = model::build(&s, &rd, &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("contact[1]") && e.contains("one contact pair"),
        "{e}"
    );
    let s = Scene::load(
        &scene,
        &[format!("contact=[{pair}]"), "contact.0.p0=3.0".into()],
    )
    .unwrap();
    let e = model::build(&s, &rd, &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(e.contains("contact[0].p0") && e.contains("model.p0"), "{e}");
}

/// `[[contact]] separation = true` on a stored model (the tiny brake written by `squeal
/// reduce`, its gap table one pair) opens the gaps as on the meshed model it came from: the
/// same openings, closings and first separation time (the stored matrices are the meshed
/// ones to 16–17 digits).
#[test]
fn separation_on_a_stored_model_opens_the_gaps_like_the_meshed_model() {
    let tiny = root().join("examples/transient/tiny-brake.toml");
    let d = tmp("input-stored-separation");
    let sets = [
        "contact.0.separation=true",
        "loads.pmax=-2.0",
        "transient.tfinal=0.05",
    ];
    let mut cmd = squeal();
    cmd.args(["-q", "transient"])
        .arg(&tiny)
        .arg("--out")
        .arg(d.join("meshed"));
    for s in sets {
        cmd.args(["--set", s]);
    }
    let (ok, _, err) = run(&mut cmd);
    assert!(ok, "{err}");
    let (ok, _, err) = run(squeal()
        .args(["-q", "reduce"])
        .arg(&tiny)
        .arg("--out")
        .arg(d.join("reduced")));
    assert!(ok, "{err}");
    // The same analysis settings over the stored files (the pressure set is in PBRAKE).
    let mut doc: toml::Value = toml::from_str(&std::fs::read_to_string(&tiny).unwrap()).unwrap();
    let t = doc.as_table_mut().unwrap();
    t.remove("components");
    t.remove("reduction");
    t["loads"].as_table_mut().unwrap().remove("pressure");
    t.insert(
        "model".into(),
        toml::Value::try_from(toml::toml! {
            from = "op4"
            matrices = "reduced/reduced.op4"
            dofmap = "reduced/dofmap.json"
            gaps = "reduced/gaps.json"
            band_hz = 100.0
        })
        .unwrap(),
    );
    // The pair's P0 is in the gap table (1.0 per gap): the stored pair must not repeat it.
    t["contact"].as_array_mut().unwrap()[0]
        .as_table_mut()
        .unwrap()
        .remove("p0");
    let stored = d.join("stored.toml");
    std::fs::write(&stored, toml::to_string(&doc).unwrap()).unwrap();
    let mut cmd = squeal();
    cmd.args(["-q", "transient"])
        .arg(&stored)
        .arg("--out")
        .arg(d.join("stored"));
    for s in sets {
        cmd.args(["--set", s]);
    }
    let (ok, _, err) = run(&mut cmd);
    assert!(ok, "{err}");
    let (a, b) = (
        json(&d.join("meshed/summary.json")),
        json(&d.join("stored/summary.json")),
    );
    let (sa, sb) = (&a["separation"], &b["separation"]);
    println!("meshed {sa}\nstored {sb}");
    assert!(sa["openings"].as_u64().unwrap() >= 1, "{sa}");
    for k in ["openings", "closings"] {
        assert_eq!(sa[k], sb[k], "{k}: meshed {sa} stored {sb}");
    }
    let (ta, tb) = (
        sa["first_separation_t"].as_f64().unwrap(),
        sb["first_separation_t"].as_f64().unwrap(),
    );
    assert!((ta - tb).abs() <= 1e-6 * ta.abs(), "{ta} vs {tb}");
    assert!(b["active_effects"].to_string().contains("separation"));
}
