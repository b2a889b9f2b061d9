//! Fuzz targets (issue 14): every reader of user files, fed mutated real files and arbitrary
//! bytes (`squeal_tests::fuzz`). For each case: no panic, no hang (watchdog), and either the
//! input is accepted — and then meets the reader's guarantees — or the error's text names the
//! input (its path, or the scene key / `--set` assignment).
//!
//! CI runs a bounded number of cases per target (about a minute for the binary in a debug
//! build); `SQUEAL_FUZZ_SECONDS=600 cargo test --release -p squeal-tests --test fuzz --
//! --test-threads 1 --nocapture` runs each target for ten minutes (README, "Fuzzing").
//! `regression_corpus_replays` replays `tests/data/fuzz/<target>/*`, the inputs that once failed.

use proptest::prelude::*;
use squeal_meshes::jacobian::hex_node_jacobians;
use squeal_meshes::parse_msh;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::accuracy::models;
use squeal_pipeline::stages::model::cache::key::hash128;
use squeal_pipeline::stages::model::gap_table::read_gaps;
use squeal_pipeline::stages::model::{self, ModelCache};
use squeal_pipeline::stages::transient;
use squeal_pipeline::{PipelineError, RunDir, Scene};
use squeal_reduction::{op4, punch};
use squeal_tests::fuzz::{fuzz, inputs, mutate::mutations, Input, Outcome};
use squeal_tests::workspace_root;
use std::path::{Path, PathBuf};

fn quiet() -> Progress {
    Progress::quiet()
}

/// Where reports, failing inputs and each target's scratch files go.
fn out(target: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("fuzz")
        .join(target);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn reports() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz")
}

fn seeds(paths: &[&str]) -> Vec<(String, Vec<u8>)> {
    paths
        .iter()
        .map(|p| {
            let bytes =
                std::fs::read(workspace_root().join(p)).unwrap_or_else(|e| panic!("{p}: {e}"));
            (p.rsplit('/').next().unwrap().to_string(), bytes)
        })
        .collect()
}

/// An error whose text names `input` is a rejection; any other is a failure.
fn named(msg: String, input: &str) -> Result<Outcome, String> {
    if msg.contains(input) {
        Ok(Outcome::Rejected)
    } else {
        Err(format!("the error does not name `{input}`: {msg}"))
    }
}

fn bytes(i: &Input) -> Vec<u8> {
    i.bytes.clone()
}

/// The seeds must be accepted as they are: a target whose seeds fail tests nothing deep.
fn accepted(s: &[(String, Vec<u8>)], check: impl Fn(&[u8]) -> Result<Outcome, String>) {
    for (name, b) in s {
        assert_eq!(check(b), Ok(Outcome::Accepted), "seed {name}");
    }
}

// ------------------------------------------------------------------------------ msh

const MSH: &str = "fuzz-input.msh";

/// A mesh read must have node indices in range and det J > 0 at every node of every cell.
fn check_msh(bytes: &[u8]) -> Result<Outcome, String> {
    let m = match parse_msh(bytes, MSH) {
        Ok(m) => m,
        Err(e) => return named(e.to_string(), MSH),
    };
    let n = m.nodes.len();
    for b in m
        .volumes
        .iter()
        .chain(m.faces.values().flat_map(|s| &s.blocks))
    {
        if b.conn.iter().any(|&i| i >= n) || b.conn.len() % b.kind.n_nodes() != 0 {
            return Err(format!(
                "block {:?}: node index out of range or ragged",
                b.name
            ));
        }
    }
    for b in &m.volumes {
        for cell in b.conn.chunks(b.kind.n_nodes()) {
            let x: Vec<[f64; 3]> = cell.iter().map(|&i| m.nodes[i]).collect();
            let (a, d) = hex_node_jacobians(&x)[0];
            if d.is_nan() || d <= 0.0 {
                return Err(format!("accepted a cell with det J = {d} at its node {a}"));
            }
        }
    }
    if m.node_sets.values().flatten().any(|&i| i >= n) {
        return Err("node set index out of range".into());
    }
    Ok(Outcome::Accepted)
}

const MSH_CASES: u32 = 3000;

#[test]
fn fuzz_msh_v22_ascii() {
    let s = seeds(&[
        "meshes/tests/data/hex8_v22.msh",
        "meshes/tests/data/hex20_v22.msh",
    ]);
    fuzz(
        "msh_v22_ascii",
        reports(),
        inputs(s, 2048),
        MSH_CASES,
        bytes,
        |i| check_msh(&i.bytes),
    );
}

#[test]
fn fuzz_msh_v41_ascii() {
    let s = seeds(&[
        "meshes/tests/data/hex8_v41.msh",
        "meshes/tests/data/hex20_v41.msh",
    ]);
    fuzz(
        "msh_v41_ascii",
        reports(),
        inputs(s, 2048),
        MSH_CASES,
        bytes,
        |i| check_msh(&i.bytes),
    );
}

#[test]
fn fuzz_msh_v41_binary() {
    let s = seeds(&[
        "meshes/tests/data/hex8_v41_bin.msh",
        "meshes/tests/data/hex20_v41_bin.msh",
    ]);
    fuzz(
        "msh_v41_binary",
        reports(),
        inputs(s, 2048),
        MSH_CASES,
        bytes,
        |i| check_msh(&i.bytes),
    );
}

// ------------------------------------------------------------------------------ OP4, punch

const OP4: &str = "fuzz-input.op4";
const PCH: &str = "fuzz-input.pch";

fn check_op4(bytes: &[u8]) -> Result<Outcome, String> {
    match op4::read_bytes_named(bytes, OP4) {
        Ok(mats) => {
            for m in &mats {
                if m.nrows.saturating_mul(m.ncols) > op4::MAX_DENSE_ENTRIES {
                    return Err(format!("{} is {}x{}", m.name, m.nrows, m.ncols));
                }
                if m.nrows > 0 && m.ncols > 0 {
                    let _ = m.get(m.nrows - 1, m.ncols - 1);
                }
            }
            Ok(Outcome::Accepted)
        }
        Err(e) => named(e.to_string(), OP4),
    }
}

fn check_punch(bytes: &[u8]) -> Result<Outcome, String> {
    match punch::read_bytes_named(bytes, PCH) {
        Ok(ds) => {
            for d in &ds {
                if d.rows.len() != d.matrix.nrows || d.cols.len() != d.matrix.ncols {
                    return Err(format!(
                        "DMIG {}: DOF lists do not fit the matrix",
                        d.matrix.name
                    ));
                }
            }
            Ok(Outcome::Accepted)
        }
        Err(e) => named(e.to_string(), PCH),
    }
}

#[test]
fn fuzz_op4_ascii() {
    let s = seeds(&[
        "reduction/tests/data/op4/yeti_ascii_dense.op4",
        "reduction/tests/data/op4/yeti_ascii_nonbigmat.op4",
        "reduction/tests/data/op4/yeti_ascii_bigmat.op4",
        "reduction/tests/data/op4/pynastran_ascii_single.op4",
        "reduction/tests/data/op4/pynastran_ascii_sparse.op4",
        "examples/accuracy/belt.op4",
    ]);
    accepted(&s, check_op4);
    fuzz("op4_ascii", reports(), inputs(s, 2048), 3000, bytes, |i| {
        check_op4(&i.bytes)
    });
}

#[test]
fn fuzz_op4_binary() {
    let s = seeds(&[
        "reduction/tests/data/op4/yeti_bin_dense_le.op4",
        "reduction/tests/data/op4/yeti_bin_dense_be.op4",
        "reduction/tests/data/op4/yeti_bin_nonbigmat_le.op4",
        "reduction/tests/data/op4/yeti_bin_bigmat_be.op4",
    ]);
    accepted(&s, check_op4);
    fuzz("op4_binary", reports(), inputs(s, 2048), 3000, bytes, |i| {
        check_op4(&i.bytes)
    });
}

#[test]
fn fuzz_punch_dmig() {
    let s = seeds(&[
        "reduction/tests/data/punch/pynastran_small.pch",
        "reduction/tests/data/punch/pynastran_large.pch",
        "reduction/tests/data/punch/yeti_large.pch",
    ]);
    accepted(&s, check_punch);
    fuzz("punch_dmig", reports(), inputs(s, 2048), 3000, bytes, |i| {
        check_punch(&i.bytes)
    });
}

// ------------------------------------------------------------------------------ bdf, inp

const BDF: &str = "fuzz-input.bdf";
const INP: &str = "fuzz-input.inp";

fn industrial() -> PathBuf {
    workspace_root().join("meshes/tests/data/industrial")
}

/// A mesh read from a Nastran or Abaqus file: indices in range, finite coordinates, det J > 0
/// at every node of every cell (the readers' guarantee), sets and fixed DOFs on existing
/// nodes.
fn check_industrial(m: &squeal_meshes::Mesh) -> Result<Outcome, String> {
    let n = m.nodes.len();
    if m.nodes.iter().flatten().any(|x| !x.is_finite()) {
        return Err("accepted a non-finite coordinate".into());
    }
    if m.node_tags.len() != n {
        return Err("node tags do not fit the nodes".into());
    }
    for b in &m.volumes {
        if b.conn.iter().any(|&i| i >= n) || b.conn.len() != b.len() * b.kind.n_nodes() {
            return Err(format!(
                "block {:?}: node index out of range or ragged",
                b.name
            ));
        }
        for cell in b.conn.chunks(b.kind.n_nodes()) {
            let x: Vec<[f64; 3]> = cell.iter().map(|&i| m.nodes[i]).collect();
            let (a, d) = squeal_meshes::jacobian::node_jacobians(b.kind, &x)[0];
            if d.is_nan() || d <= 0.0 {
                return Err(format!(
                    "accepted a {} with det J = {d} at its node {a}",
                    b.kind
                ));
            }
        }
    }
    for f in m.faces.values() {
        if f.node_indices().any(|i| i >= n) {
            return Err("face node index out of range".into());
        }
    }
    if m.node_sets.values().flatten().any(|&i| i >= n)
        || m.fixed.iter().any(|&(i, k)| i >= n || k > 2)
    {
        return Err("node set or fixed DOF out of range".into());
    }
    Ok(Outcome::Accepted)
}

/// An error names the input, or one of the unmutated files it includes.
fn named_in_deck(msg: String, input: &str) -> Result<Outcome, String> {
    if msg.contains(input) || msg.contains("meshes/tests/data/industrial") {
        Ok(Outcome::Rejected)
    } else {
        Err(format!("the error does not name `{input}`: {msg}"))
    }
}

fn check_bdf(bytes: &[u8]) -> Result<Outcome, String> {
    let opts = squeal_meshes::BdfOptions::default();
    match squeal_meshes::parse_bdf(bytes, BDF, &industrial(), &opts) {
        Ok((m, _)) => check_industrial(&m),
        Err(e) => named_in_deck(e.to_string(), BDF),
    }
}

fn check_inp(bytes: &[u8]) -> Result<Outcome, String> {
    let opts = squeal_meshes::InpOptions::default();
    match squeal_meshes::parse_inp(bytes, INP, &industrial(), &opts) {
        Ok((m, _)) => check_industrial(&m),
        Err(e) => named_in_deck(e.to_string(), INP),
    }
}

const READER_CASES: u32 = 1500;

#[test]
fn fuzz_nastran_bulk_data() {
    let s = seeds(&[
        "meshes/tests/data/industrial/mixed.bdf",
        "meshes/tests/data/industrial/mixed_grids.bdf",
        "meshes/tests/data/industrial/mixed_free.bdf",
        "meshes/tests/data/industrial/bracket_hex20.bdf",
        "meshes/tests/data/industrial/bracket_ortho.bdf",
    ]);
    // The grid and free-field files alone have no solids: rejected (naming the input).
    for (name, b) in &s {
        let want = if name.starts_with("mixed_") {
            Outcome::Rejected
        } else {
            Outcome::Accepted
        };
        assert_eq!(check_bdf(b), Ok(want), "seed {name}");
    }
    fuzz(
        "nastran_bdf",
        reports(),
        inputs(s, 2048),
        READER_CASES,
        bytes,
        |i| check_bdf(&i.bytes),
    );
}

#[test]
fn fuzz_abaqus_input() {
    let s = seeds(&[
        "meshes/tests/data/industrial/assembly.inp",
        "meshes/tests/data/industrial/bracket_hex20.inp",
        "meshes/tests/data/industrial/bracket_ortho.inp",
    ]);
    accepted(&s, check_inp);
    fuzz(
        "abaqus_inp",
        reports(),
        inputs(s, 2048),
        READER_CASES,
        bytes,
        |i| check_inp(&i.bytes),
    );
}

// ------------------------------------------------------------------------------ scene + --set

/// Keys the overrides aim at (real ones, array indices, nonsense).
const KEYS: [&str; 16] = [
    "friction.law.mu0",
    "friction.vtol",
    "rotor.origin",
    "rotor.axis",
    "rotor.rpm",
    "model.p0",
    "model.gaps",
    "components.0.geometry.n_circ",
    "components.0.geometry.origin.1",
    "components.9.name",
    "contact.0.p0",
    "transient.rtol1",
    "transient.maxord",
    "cea.steady.tol",
    "loads.pmax",
    "a.b.0.c",
];
const VALUES: [&str; 14] = [
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "1e308",
    "1e-320",
    "[nan, 0.0, 0.0]",
    "[1, 2]",
    "\"x\"",
    "true",
    "{ a = 1 }",
    "",
    "99999999999999999999",
];

#[derive(Clone)]
struct SceneCase {
    text: Input,
    set: Vec<String>,
}

impl std::fmt::Debug for SceneCase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?} with --set {:?}", self.text, self.set)
    }
}

fn assignment() -> impl Strategy<Value = String> {
    prop_oneof![
        8 => (0..KEYS.len(), 0..VALUES.len()).prop_map(|(k, v)| format!("{}={}", KEYS[k], VALUES[v])),
        1 => "[a-z0-9.=\\[\\]\"]{0,12}",
    ]
}

/// Every float in an accepted scene is finite.
fn non_finite(v: &toml::Value, key: &str) -> Option<String> {
    match v {
        toml::Value::Float(x) if !x.is_finite() => Some(format!("{key} = {x}")),
        toml::Value::Table(t) => t
            .iter()
            .find_map(|(k, x)| non_finite(x, &format!("{key}.{k}"))),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, x)| non_finite(x, &format!("{key}.{i}"))),
        _ => None,
    }
}

fn check_scene(dir: &Path, c: &SceneCase) -> Result<Outcome, String> {
    let path = dir.join("fuzz-scene.toml");
    std::fs::write(&path, &c.text.bytes).unwrap();
    match Scene::load(&path, &c.set) {
        Ok(s) => {
            let doc: toml::Value = toml::from_str(&s.resolved_toml())
                .map_err(|e| format!("the resolved scene does not parse: {e}"))?;
            match non_finite(&doc, "") {
                Some(k) => Err(format!("accepted a non-finite number: {k}")),
                None => Ok(Outcome::Accepted),
            }
        }
        // Named by the scene key, or by the `--set` assignment.
        Err(PipelineError::Scene { field, .. }) if !field.is_empty() => Ok(Outcome::Rejected),
        Err(PipelineError::Override { .. }) => Ok(Outcome::Rejected),
        Err(e) => named(e.to_string(), &path.display().to_string()),
    }
}

#[test]
fn fuzz_scene_toml_with_overrides() {
    let s = seeds(&[
        "examples/transient/tiny-brake.toml",
        "examples/sample-brake/base.toml",
        "examples/accuracy/belt.toml",
        "examples/cea/tiny-brake-cea.toml",
        "examples/verification/fv52-hex20.toml",
    ]);
    let dir = out("scene");
    let plain = |b: &[u8]| {
        let text = Input {
            bytes: b.to_vec(),
            how: String::new(),
        };
        check_scene(
            &dir,
            &SceneCase {
                text,
                set: Vec::new(),
            },
        )
    };
    accepted(&s, plain);
    let strategy = (
        inputs(s, 1024),
        proptest::collection::vec(assignment(), 0..4),
    )
        .prop_map(|(text, set)| SceneCase { text, set });
    fuzz(
        "scene_toml",
        reports(),
        strategy,
        1500,
        |c: &SceneCase| c.text.bytes.clone(),
        |c| check_scene(&dir, c),
    );
}

// ------------------------------------------------------------------------------ stored model

/// The belt model (3 DOFs, one gap) and a scene reading it, in `dir`.
fn belt_fixture(dir: &Path) -> PathBuf {
    models::belt().write(dir, "m").unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        format!(
            "[model]\nfrom = \"op4\"\nmatrices = \"m.op4\"\ndofmap = \"m.dofmap.json\"\n\
             gaps = \"m.gaps.csv\"\n\n[friction]\nlaw = {{ kind = \"linear_speed\", mu0 = 0.5, \
             slope = -0.05 }}\n\n[rotor]\nrpm = {}\n\n[loads]\npmax = 0.05\ntload = 0.0\n\n\
             [transient]\ntfinal = 0.01\nnrstrt = 0\n\n[output]\nhistory = false\n",
            models::RPM
        ),
    )
    .unwrap();
    scene
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// A gap table read has only valid gaps.
fn check_gap_table(dir: &Path, bytes: &[u8]) -> Result<Outcome, String> {
    let json = bytes
        .iter()
        .find(|b| !b.is_ascii_whitespace())
        .is_some_and(|&b| b == b'[' || b == b'{');
    let path = dir.join(if json {
        "fuzz.gaps.json"
    } else {
        "fuzz.gaps.csv"
    });
    std::fs::write(&path, bytes).unwrap();
    match read_gaps(&path) {
        Ok(gaps) => {
            // A pad grid may carry several gaps; the same (pad grid, rotor grid, normal) twice
            // is one constraint written twice, which the reader must reject.
            let twice = |a: &squeal_contact::Gap, b: &squeal_contact::Gap| {
                let (na, nb) = (norm(a.normal), norm(b.normal));
                let apart = (0..3)
                    .map(|k| (a.normal[k] / na - b.normal[k] / nb).powi(2))
                    .sum::<f64>()
                    .sqrt();
                a.pad_node == b.pad_node && a.rotor_node == b.rotor_node && apart <= 1e-12
            };
            for (i, g) in gaps.iter().enumerate() {
                let len = g.normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                let ok = g.coords.iter().all(|x| x.is_finite())
                    && (len - 1.0).abs() < 1e-6
                    && g.area.is_finite()
                    && g.area > 0.0
                    && g.p0.is_finite()
                    && g.p0 >= 0.0
                    && g.temperature.is_finite()
                    && g.pad_node != g.rotor_node
                    && !gaps[..i].iter().any(|f| twice(f, g));
                if !ok {
                    return Err(format!("accepted an invalid gap: {g:?}"));
                }
            }
            Ok(Outcome::Accepted)
        }
        Err(e) => named(e.to_string(), &path.display().to_string()),
    }
}

#[test]
fn fuzz_gap_table() {
    let dir = out("gap_table");
    let scene = belt_fixture(&dir);
    let m = model::build(
        &Scene::load(&scene, &[]).unwrap(),
        &RunDir::create(&dir.join("run")).unwrap(),
        &quiet(),
    )
    .unwrap();
    let mut s = seeds(&[
        "examples/accuracy/belt.gaps.csv",
        "examples/accuracy/coupling.gaps.csv",
    ]);
    s.push((
        "four gaps, columns reordered".into(),
        b"temperature,p0,area,nz,ny,nx,z,y,x,rotor_grid,pad_grid\n\
          0,1,0.25,0,0,1,0,1,2,101,1\n20,1,0.25,0,0,1,0.5,1,2,102,2\n\
          0,1,0.5,0,0.6,0.8,1,1,2,103,3\n0,0,0.25,0,0,-1,1.5,1,2,104,4\n"
            .to_vec(),
    ));
    s.push((
        "gaps.json list".into(),
        serde_json::to_vec_pretty(&m.gap_geometry.gaps).unwrap(),
    ));
    s.push((
        "gaps.json set".into(),
        serde_json::to_vec_pretty(&m.gap_geometry).unwrap(),
    ));
    accepted(&s, |b| check_gap_table(&dir, b));
    fuzz("gap_table", reports(), inputs(s, 1024), 1500, bytes, |i| {
        check_gap_table(&dir, &i.bytes)
    });
}

/// A model read from a mutated DOF map has consistent sizes; errors name one of its files.
fn check_dofmap(dir: &Path, scene: &Path, bytes: &[u8]) -> Result<Outcome, String> {
    std::fs::write(dir.join("m.dofmap.json"), bytes).unwrap();
    let s = Scene::load(scene, &[]).map_err(|e| e.to_string())?;
    match model::build(&s, &RunDir::create(&dir.join("run")).unwrap(), &quiet()) {
        Ok(m) => {
            let n = m.n();
            if m.dofs.len() != n || m.m.nrows() != n || m.gap_geometry.check_dofs(n).is_err() {
                return Err(format!("accepted a model of inconsistent size {n}"));
            }
            Ok(Outcome::Accepted)
        }
        Err(e) => {
            let msg = e.to_string();
            let files = ["m.dofmap.json", "m.op4", "m.gaps.csv"];
            if files
                .iter()
                .any(|f| msg.contains(&dir.join(f).display().to_string()))
            {
                Ok(Outcome::Rejected)
            } else {
                Err(format!("the error names none of the model's files: {msg}"))
            }
        }
    }
}

#[test]
fn fuzz_dofmap_json() {
    let dir = out("dofmap");
    let scene = belt_fixture(&dir);
    let s = vec![
        ("belt dofmap".to_string(), std::fs::read(dir.join("m.dofmap.json")).unwrap()),
        (
            "with a modal coordinate".to_string(),
            br#"{"dofs":[{"component":"pad","kind":"grid","grid":1,"comp":2},
                {"component":"pad","kind":"modal","index":0},
                {"component":"rotor","shared_with":["pad"],"kind":"grid","grid":100001,"comp":3}]}"#
                .to_vec(),
        ),
    ];
    accepted(&s, |b| check_dofmap(&dir, &scene, b));
    fuzz("dofmap_json", reports(), inputs(s, 512), 600, bytes, |i| {
        check_dofmap(&dir, &scene, &i.bytes)
    });
}

// ------------------------------------------------------------------------------ restart

/// A run resumed from a mutated restart file finishes, or its error names the file.
fn check_restart(dir: &Path, scene: &Path, bytes: &[u8]) -> Result<Outcome, String> {
    let p = dir.join("fuzz.restart.json");
    std::fs::write(&p, bytes).unwrap();
    let set = [
        format!("transient.restart=\"{}\"", p.display()),
        "transient.tfinal=0.0105".to_string(),
        "transient.max_steps=40".to_string(),
    ];
    let s = Scene::load(scene, &set).map_err(|e| e.to_string())?;
    let run = RunDir::create(&dir.join("resumed")).unwrap();
    match transient::run(&s, &run, &quiet(), None) {
        Ok(_) => Ok(Outcome::Accepted),
        Err(e) => named(e.to_string(), &p.display().to_string()),
    }
}

#[test]
fn fuzz_restart_json() {
    let dir = out("restart");
    let scene = belt_fixture(&dir);
    let mut s = Vec::new();
    for tf in ["0.002", "0.01"] {
        let sc = Scene::load(&scene, &[format!("transient.tfinal={tf}")]).unwrap();
        let run = RunDir::create(&dir.join(format!("seed-{tf}"))).unwrap();
        transient::run(&sc, &run, &quiet(), None).unwrap();
        s.push((
            format!("restart at t = {tf}"),
            std::fs::read(run.path("restart.json")).unwrap(),
        ));
    }
    accepted(&s, |b| check_restart(&dir, &scene, b));
    fuzz("restart_json", reports(), inputs(s, 512), 200, bytes, |i| {
        check_restart(&dir, &scene, &i.bytes)
    });
}

// ------------------------------------------------------------------------------ cache entries

#[derive(Clone)]
struct CacheCase {
    file: usize,
    rehash: bool,
    bytes: Vec<u8>,
    how: String,
}

impl std::fmt::Debug for CacheCase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (rehashed: {})", self.how, self.rehash)
    }
}

const ENTRY_FILES: [&str; 5] = [
    "reduced.op4",
    "dofmap.json",
    "gaps.json",
    "grids.json",
    "entry.json",
];

/// A mutated entry (hashes in entry.json updated or not) is read, or refused naming the entry.
fn check_cache(
    entry: &Path,
    originals: &[Vec<u8>],
    cache: &ModelCache,
    scene: &Scene,
    c: &CacheCase,
) -> Result<Outcome, String> {
    let name = ENTRY_FILES[c.file];
    std::fs::write(entry.join(name), &c.bytes).unwrap();
    if c.rehash && name != "entry.json" {
        let mut meta: serde_json::Value = serde_json::from_slice(&originals[4]).unwrap();
        meta["files"][name] = serde_json::json!({
            "bytes": c.bytes.len(),
            "hash": format!("{:032x}", hash128(&c.bytes)),
        });
        std::fs::write(
            entry.join("entry.json"),
            serde_json::to_vec_pretty(&meta).unwrap(),
        )
        .unwrap();
    }
    let r = cache.read(scene);
    for (f, b) in ENTRY_FILES.iter().zip(originals) {
        std::fs::write(entry.join(f), b).unwrap();
    }
    match r {
        Ok(Some(m)) => {
            if m.gap_geometry.check_dofs(m.n()).is_err() || m.m.nrows() != m.n() {
                return Err("accepted an inconsistent cached model".into());
            }
            Ok(Outcome::Accepted)
        }
        Ok(None) => Err("the entry was not found".into()),
        Err(e) => named(e.to_string(), &entry.display().to_string()),
    }
}

#[test]
fn fuzz_cache_entry() {
    let dir = out("cache_entry");
    let text = std::fs::read_to_string(workspace_root().join("examples/transient/tiny-brake.toml"))
        .unwrap();
    std::fs::write(dir.join("tiny.toml"), text).unwrap();
    let scene = Scene::load(&dir.join("tiny.toml"), &[]).unwrap();
    let cache = ModelCache::new(dir.join("cache"));
    let (_, used) = cache
        .get_or_build(&scene, &RunDir::create(&dir.join("run")).unwrap(), &quiet())
        .unwrap();
    let entry = PathBuf::from(used.entry);
    let originals: Vec<Vec<u8>> = ENTRY_FILES
        .iter()
        .map(|f| std::fs::read(entry.join(f)).unwrap())
        .collect();
    assert!(cache.read(&scene).unwrap().is_some());
    let o = originals.clone();
    let strategy =
        (0..ENTRY_FILES.len(), any::<bool>(), mutations()).prop_map(move |(file, rehash, ms)| {
            let mut bytes = o[file].clone();
            for m in &ms {
                m.apply(&mut bytes);
            }
            CacheCase {
                file,
                rehash,
                bytes,
                how: format!("{} with {ms:?}", ENTRY_FILES[file]),
            }
        });
    fuzz(
        "cache_entry",
        reports(),
        strategy,
        200,
        |c: &CacheCase| c.bytes.clone(),
        |c| check_cache(&entry, &originals, &cache, &scene, c),
    );
}

// ------------------------------------------------------------------------------ corpus

/// Inputs that once failed a target, replayed: `tests/data/fuzz/<target>/<file>`.
// ------------------------------------------------------ in-memory surfaces (issue 26)

/// `Scene::with_arrays` (Python's `Scene.from_arrays`) on the belt model mutated entry by
/// entry, resized, with scene texts: built models are finite, symmetric, with usable gaps.
#[test]
fn fuzz_scene_from_arrays() {
    use squeal_tests::fuzz::api;
    let dir = out("arrays");
    let belt = api::ArraysCase {
        k: (0..9).map(|i| models::belt().k[(i / 3, i % 3)]).collect(),
        m: (0..9).map(|i| models::belt().m[(i / 3, i % 3)]).collect(),
        n_k: 3,
        n_m: 3,
        dofs: vec![(1, 2, true), (1, 3, true), (100_001, 3, true)],
        gaps: vec![[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 10.0]],
        toml: "[cea]\n".into(),
    };
    assert_eq!(api::check_arrays(&dir, &belt), Ok(Outcome::Accepted));
    fuzz(
        "scene_from_arrays",
        reports(),
        api::arrays_case(),
        400,
        |c: &api::ArraysCase| format!("{c:?}").into_bytes(),
        |c| api::check_arrays(&dir, c),
    );
}

/// Scene documents as values (Python's `Scene.from_dict`): example scenes with values
/// replaced by any TOML value, keys removed or added.
#[test]
fn fuzz_scene_from_dict() {
    use squeal_tests::fuzz::api;
    let dir = out("dict");
    let docs: Vec<toml::Value> = [
        "examples/transient/tiny-brake.toml",
        "examples/accuracy/belt.toml",
        "examples/cea/tiny-brake-cea.toml",
    ]
    .iter()
    .map(|p| toml::from_str(&std::fs::read_to_string(workspace_root().join(p)).unwrap()).unwrap())
    .collect();
    for d in &docs {
        let c = api::DocCase { doc: d.clone() };
        let r = api::check_doc(&workspace_root().join("examples/accuracy"), &c);
        assert!(r.is_ok(), "{r:?}");
    }
    fuzz(
        "scene_from_dict",
        reports(),
        api::doc_case(docs),
        1500,
        |c: &api::DocCase| toml::to_string(&c.doc).unwrap_or_default().into_bytes(),
        |c| api::check_doc(&dir, c),
    );
}

/// `squeal compare` options on the belt model against a copy with KR[0,0] raised 5 %.
#[test]
fn fuzz_compare_options() {
    use squeal_tests::fuzz::api;
    let dir = out("compare");
    let write = |name: &str, scale: f64| {
        let mut m = models::belt();
        m.k[(0, 0)] *= scale;
        let d = dir.join(name);
        m.write(&d, "reduced").unwrap();
        std::fs::copy(d.join("reduced.dofmap.json"), d.join("dofmap.json")).unwrap();
        d
    };
    let (a, b) = (write("a", 1.0), write("b", 1.05));
    let ok = squeal_pipeline::stages::compare::CompareOptions {
        tol_mac: Some(0.9),
        ..Default::default()
    };
    assert_eq!(
        api::check_compare(&a, &b, &dir.join("run"), &ok),
        Ok(Outcome::Accepted)
    );
    fuzz(
        "compare_options",
        reports(),
        api::compare_options(),
        300,
        |o| format!("{o:?}").into_bytes(),
        |o| api::check_compare(&a, &b, &dir.join("run"), o),
    );
}

#[test]
fn regression_corpus_replays() {
    let corpus = workspace_root().join("tests/data/fuzz");
    let mut n = 0;
    let stored = out("corpus-stored");
    let scene = belt_fixture(&stored);
    for target in std::fs::read_dir(&corpus).unwrap() {
        let target = target.unwrap().path();
        if !target.is_dir() {
            continue;
        }
        let name = target.file_name().unwrap().to_string_lossy().into_owned();
        for f in std::fs::read_dir(&target).unwrap() {
            let f = f.unwrap().path();
            let b = std::fs::read(&f).unwrap();
            let r = match name.as_str() {
                "msh" => check_msh(&b),
                "op4" => check_op4(&b),
                "punch" => check_punch(&b),
                "bdf" => check_bdf(&b),
                "inp" => check_inp(&b),
                "scene" => check_scene(
                    &out("corpus-scene"),
                    &SceneCase {
                        text: Input {
                            bytes: b,
                            how: String::new(),
                        },
                        set: Vec::new(),
                    },
                ),
                "gap_table" => check_gap_table(&stored, &b),
                "dofmap" => check_dofmap(&stored, &scene, &b),
                "restart" => check_restart(&stored, &scene, &b),
                other => panic!(
                    "no target `{other}` for the corpus folder {}",
                    target.display()
                ),
            };
            r.unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            n += 1;
        }
    }
    eprintln!("regression corpus: {n} inputs replayed");
}
