//! Fuzz strategies and checks of the in-memory surfaces (issue 26): scenes over arrays
//! (`Scene::with_arrays`, what `squeal.Scene.from_arrays` builds), scene documents built as
//! values (`squeal.Scene.from_dict`: a dict → TOML → `Scene::from_toml_str`), and the options
//! of `squeal compare`. The targets are in `tests/tests/fuzz.rs`.
//!
//! Each case must not panic and either be accepted — and then meet the guarantees (finite,
//! symmetric K, M; every gap row usable; a compare report whose verdict is its checks') — or
//! be refused with an error naming its input (`<arrays>.…`, a scene key, a `compare.` option).

use super::Outcome;
use faer::Mat;
use proptest::prelude::*;
use squeal_contact::Gap;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::scene::StoredArrays;
use squeal_pipeline::stages::compare::{self, CompareOptions};
use squeal_pipeline::stages::model;
use squeal_pipeline::{PipelineError, RunDir, Scene};
use squeal_reduction::superelement::{DofKind, ReducedDof, ReducedDofMap};
use std::path::Path;

/// Values that break readers: specials, extremes, signs.
const SPECIAL: [f64; 12] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    -1.0,
    1e300,
    -1e300,
    1e-300,
    f64::MIN_POSITIVE,
    f64::EPSILON,
    2.5,
];

/// A number: usually `base`, sometimes a special value, sometimes `base` perturbed.
fn value(base: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => Just(base),
        1 => proptest::sample::select(SPECIAL.to_vec()),
        1 => (-1e3f64..1e3).prop_map(move |x| base + 1e-7 * x),
        1 => any::<f64>(),
    ]
}

/// An arrays case: the belt model (3 DOFs: pad y, z, rotor z; one gap) mutated entry by
/// entry, sometimes resized, with a scene text.
#[derive(Debug, Clone)]
pub struct ArraysCase {
    pub k: Vec<f64>,
    pub m: Vec<f64>,
    pub n_k: usize,
    pub n_m: usize,
    pub dofs: Vec<(u64, u8, bool)>,
    pub gaps: Vec<[f64; 8]>,
    pub toml: String,
}

const TOMLS: [&str; 6] = [
    "",
    "[cea]\n",
    "[friction]\nlaw = { kind = \"constant\", mu = 0.5 }\n[cea]\n",
    "[[contact]]\npad = \"p\"\npad_faces = \"f\"\nrotor = \"r\"\nrotor_faces = \"g\"\nseparation = true\n[transient]\ntfinal = 0.01\n",
    "[[contact]]\npad = \"p\"\npad_faces = \"f\"\nrotor = \"r\"\nrotor_faces = \"g\"\np0 = 2.0\n",
    "[model]\np0 = -1.0\n",
];

pub fn arrays_case() -> impl Strategy<Value = ArraysCase> {
    let belt = squeal_pipeline::stages::accuracy::models::belt();
    let k: Vec<f64> = (0..9).map(|i| belt.k[(i / 3, i % 3)]).collect();
    let m: Vec<f64> = (0..9).map(|i| belt.m[(i / 3, i % 3)]).collect();
    let entries = |v: Vec<f64>| v.into_iter().map(value).collect::<Vec<_>>().prop_map(|x| x);
    let dof = |grid: u64, comp: u8| {
        (
            prop_oneof![8 => Just(grid), 1 => Just(1u64), 1 => 0u64..200_000],
            prop_oneof![8 => Just(comp), 1 => 0u8..8],
            prop_oneof![9 => Just(true), 1 => Just(false)],
        )
    };
    let gap = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 10.0]; // x, y, z, nx, ny, nz, area, p0
    (
        entries(k),
        entries(m),
        prop_oneof![10 => Just(3usize), 1 => 0usize..5],
        prop_oneof![10 => Just(3usize), 1 => 0usize..5],
        (dof(1, 2), dof(1, 3), dof(100_001, 3)),
        proptest::collection::vec(gap.map(value), 0..3),
        proptest::sample::select(TOMLS.to_vec()),
    )
        .prop_map(|(k, m, n_k, n_m, (a, b, c), gaps, toml)| ArraysCase {
            k,
            m,
            n_k,
            n_m,
            dofs: vec![a, b, c],
            gaps: gaps.into_iter().map(|g| g.try_into().unwrap()).collect(),
            toml: toml.to_string(),
        })
}

fn square(v: &[f64], n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| v.get(3 * i + j).copied().unwrap_or(0.0))
}

/// The arrays of a case (grid DOFs, or modal ones where the flag is false).
pub fn arrays_of(c: &ArraysCase) -> StoredArrays {
    let dofs = ReducedDofMap {
        dofs: c
            .dofs
            .iter()
            .enumerate()
            .map(|(i, &(grid, comp, is_grid))| ReducedDof {
                component: if i < 2 { "pad" } else { "rotor" }.into(),
                kind: if is_grid {
                    DofKind::Grid { grid, comp }
                } else {
                    DofKind::Modal { index: i }
                },
                shared_with: Vec::new(),
            })
            .collect(),
        recovered: Vec::new(),
    };
    let gaps = c
        .gaps
        .iter()
        .map(|g| Gap {
            pad_node: 1,
            rotor_node: 100_001,
            coords: [g[0], g[1], g[2]],
            pad_dofs: [None; 3],
            rotor_dofs: [None; 3],
            normal: [g[3], g[4], g[5]],
            area: g[6],
            v_slide: [0.0; 3],
            p0: g[7],
            temperature: 0.0,
            tie: None,
            rotor_rows: Vec::new(),
            pad_side: None,
            friction: None,
        })
        .collect();
    StoredArrays {
        k: square(&c.k, c.n_k),
        m: square(&c.m, c.n_m),
        b: None,
        p_brake: Some(vec![1.0, 0.0, 0.0]),
        dofs,
        gaps,
    }
}

fn symmetric_finite(a: &Mat<f64>) -> bool {
    (0..a.nrows()).all(|i| (0..a.ncols()).all(|j| a[(i, j)].is_finite() && a[(i, j)] == a[(j, i)]))
}

/// Builds the model of an arrays scene: accepted models have finite symmetric K, M with a
/// positive diagonal of M and unit-usable gaps; refusals name `<arrays>` or a scene key.
pub fn check_arrays(dir: &Path, c: &ArraysCase) -> Result<Outcome, String> {
    let scene = match Scene::with_arrays(&c.toml, dir, &[], arrays_of(c)) {
        Ok(s) => s,
        Err(PipelineError::Scene { field, .. }) if !field.is_empty() => {
            return Ok(Outcome::Rejected)
        }
        Err(e) => return named(e.to_string(), "<string>"),
    };
    let rd = RunDir::create(dir).map_err(|e| e.to_string())?;
    match model::build(&scene, &rd, &Progress::quiet()) {
        Ok(m) => {
            if !(symmetric_finite(&m.k) && symmetric_finite(&m.m)) {
                return Err("accepted a non-finite or non-symmetric K or M".into());
            }
            if (0..m.n()).any(|i| m.m[(i, i)] <= 0.0) || m.n() == 0 {
                return Err(format!(
                    "accepted a mass with a non-positive diagonal ({} DOFs)",
                    m.n()
                ));
            }
            if m.gap_geometry.gaps.iter().any(|g| {
                let n = g.normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                !(n.is_finite() && (n - 1.0).abs() < 1e-6 && g.area > 0.0 && g.p0 >= 0.0)
            }) {
                return Err("accepted a gap with a bad normal, area or P0".into());
            }
            Ok(Outcome::Accepted)
        }
        Err(PipelineError::Scene { field, .. }) if !field.is_empty() => Ok(Outcome::Rejected),
        Err(e) => named(e.to_string(), "<arrays>"),
    }
}

fn named(msg: String, input: &str) -> Result<Outcome, String> {
    if msg.contains(input) {
        Ok(Outcome::Rejected)
    } else {
        Err(format!("the error does not name `{input}`: {msg}"))
    }
}

// ------------------------------------------------------------------ scene documents

/// A scene document (what a Python dict becomes) with structural mutations applied.
#[derive(Debug, Clone)]
pub struct DocCase {
    pub doc: toml::Value,
}

/// A TOML value of any type, specials included.
fn any_value() -> impl Strategy<Value = toml::Value> {
    let leaf = prop_oneof![
        proptest::sample::select(SPECIAL.to_vec()).prop_map(toml::Value::Float),
        any::<i64>().prop_map(toml::Value::Integer),
        (-1e4f64..1e4).prop_map(toml::Value::Float),
        any::<bool>().prop_map(toml::Value::Boolean),
        "[a-z_]{0,8}".prop_map(toml::Value::String),
        Just(toml::Value::String("hex8".into())),
    ];
    leaf.prop_recursive(2, 8, 3, |inner| {
        prop_oneof![
            proptest::collection::vec(inner.clone(), 0..3).prop_map(toml::Value::Array),
            proptest::collection::btree_map("[a-z_]{1,6}", inner, 0..3)
                .prop_map(|m| toml::Value::Table(m.into_iter().collect())),
        ]
    })
}

/// Every (path to a value) of a document: table keys and array indices.
fn paths(v: &toml::Value, at: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t {
                at.push(k.clone());
                out.push(at.clone());
                paths(x, at, out);
                at.pop();
            }
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                at.push(i.to_string());
                out.push(at.clone());
                paths(x, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

/// Replaces (`Some`) or removes (`None`) the value at `path`.
fn edit(doc: &mut toml::Value, path: &[String], new: Option<toml::Value>) {
    let Some((last, parents)) = path.split_last() else {
        return;
    };
    let mut v = doc;
    for p in parents {
        v = match v {
            toml::Value::Table(t) => match t.get_mut(p) {
                Some(x) => x,
                None => return,
            },
            toml::Value::Array(a) => match p.parse::<usize>().ok().and_then(|i| a.get_mut(i)) {
                Some(x) => x,
                None => return,
            },
            _ => return,
        };
    }
    match (v, new) {
        (toml::Value::Table(t), Some(x)) => {
            t.insert(last.clone(), x);
        }
        (toml::Value::Table(t), None) => {
            t.remove(last);
        }
        (toml::Value::Array(a), Some(x)) => {
            if let Some(slot) = last.parse::<usize>().ok().and_then(|i| a.get_mut(i)) {
                *slot = x;
            }
        }
        (toml::Value::Array(a), None) => {
            if let Some(i) = last.parse::<usize>().ok().filter(|&i| i < a.len()) {
                a.remove(i);
            }
        }
        _ => {}
    }
}

/// Seed documents with 1–4 edits: a value replaced by any value, removed, or a new key.
pub fn doc_case(seeds: Vec<toml::Value>) -> impl Strategy<Value = DocCase> {
    let edits = proptest::collection::vec(
        (
            any::<prop::sample::Index>(),
            0u8..3,
            any_value(),
            "[a-z_]{1,8}",
        ),
        1..5,
    );
    (proptest::sample::select(seeds), edits).prop_map(|(mut doc, edits)| {
        for (ix, op, v, key) in edits {
            let mut all = Vec::new();
            paths(&doc, &mut Vec::new(), &mut all);
            if all.is_empty() {
                continue;
            }
            let p = all[ix.index(all.len())].clone();
            match op {
                0 => edit(&mut doc, &p, Some(v)),
                1 => edit(&mut doc, &p, None),
                _ => {
                    let mut q = p;
                    q.pop();
                    q.push(key);
                    edit(&mut doc, &q, Some(v));
                }
            }
        }
        DocCase { doc }
    })
}

/// As `squeal.Scene.from_dict`: the document written as TOML, then read. Accepted scenes hold
/// only finite numbers and re-read equal; refusals name a key or the source `<string>`.
pub fn check_doc(dir: &Path, c: &DocCase) -> Result<Outcome, String> {
    let text = match toml::to_string(&c.doc) {
        Ok(t) => t,
        Err(_) => return Ok(Outcome::Rejected), // not writable as TOML (from_dict says so)
    };
    match Scene::from_toml_str(&text, dir, &[]) {
        Ok(s) => {
            let again = Scene::from_toml_str(&s.resolved_toml(), dir, &[])
                .map_err(|e| format!("the resolved scene does not read back: {e}"))?;
            if again != s {
                return Err("the resolved scene reads back different".into());
            }
            Ok(Outcome::Accepted)
        }
        Err(PipelineError::Scene { field, .. }) if !field.is_empty() => Ok(Outcome::Rejected),
        Err(e) => named(e.to_string(), "<string>"),
    }
}

// ------------------------------------------------------------------ compare options

/// `squeal compare` options drawn around their valid ranges.
pub fn compare_options() -> impl Strategy<Value = CompareOptions> {
    let tol = || {
        prop_oneof![
            2 => Just(None),
            3 => (0.0f64..1.0).prop_map(Some),
            1 => proptest::sample::select(SPECIAL.to_vec()).prop_map(Some),
            1 => (1.0f64..3.0).prop_map(Some),
        ]
    };
    (
        (tol(), tol(), tol(), tol(), tol()),
        prop_oneof![2 => Just(None), 1 => (0usize..6).prop_map(Some)],
        tol(),
        any::<bool>(),
    )
        .prop_map(
            |((tol_freq, tol_mac, tol_matrix, tol_root, tol_summary), modes, pair_mac, cea)| {
                CompareOptions {
                    tol_freq,
                    tol_mac,
                    tol_matrix,
                    tol_root,
                    tol_summary,
                    modes,
                    pair_mac,
                    scene: None,
                    cea,
                    cache: None,
                }
            },
        )
}

/// Compares stored model `a` with `b`: an accepted report's verdict is its checks', its
/// pairing threshold is at most a given MAC tolerance, and a mode tolerance checks at least
/// one mode; a refusal names a `compare.` option.
pub fn check_compare(
    a: &Path,
    b: &Path,
    dir: &Path,
    o: &CompareOptions,
) -> Result<Outcome, String> {
    let rd = RunDir::create(dir).map_err(|e| e.to_string())?;
    match compare::compute(a, b, o, &rd, &Progress::quiet()) {
        Ok(r) => {
            if r.passed != r.checks.iter().all(|c| c.passed) {
                return Err("`passed` disagrees with the checks".into());
            }
            if o.tol_mac.is_some_and(|t| o.pair_mac() > t) {
                return Err("paired below a threshold above tol_mac".into());
            }
            if (o.tol_freq.is_some() || o.tol_mac.is_some()) && r.modes.is_empty() {
                return Err("a mode tolerance was given and no mode was compared".into());
            }
            Ok(Outcome::Accepted)
        }
        Err(e) => named(e.to_string(), "compare."),
    }
}
