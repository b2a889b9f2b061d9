//! The crate's layering, checked on its source text (issue 21):
//! - the modules under `src/stages/transient/` import one another one way (no import circle),
//!   and no file there is over 400 lines (STYLE.md: "Layers and observers");
//! - the verdict imports nothing above it;
//! - the layers below the verbs (`scene`, `model`, `problem`, `verdict`) import no verb, a verb
//!   of the problem's level (`modes`, `cea`, `transient`, ...) imports no other verb, and the
//!   verbs above them (`sweep`, `reproduce`, ...) import no verb of their own level.
//!
//! An import is a path in code (not in comments or `#[cfg(test)]` modules) that names a
//! module of the folder: `super::x`, `crate::stages::transient::x`, or a child module named
//! at the start of a path in a `mod.rs`. A path that names an item of a folder's `mod.rs`
//! (`super::Item`) is an import of that `mod.rs`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Longest file allowed in the folder.
const MAX_LINES: usize = 400;

/// A module of the folder: its path below `transient` (empty for `transient/mod.rs`).
type Module = Vec<String>;

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src/stages/transient")
}

/// Every `.rs` file below `dir` with its module path.
fn modules(dir: &Path, prefix: &Module, out: &mut BTreeMap<Module, PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        let name = p.file_stem().unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            let mut m = prefix.clone();
            m.push(name);
            modules(&p, &m, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            let mut m = prefix.clone();
            if name != "mod" {
                m.push(name);
            }
            out.insert(m, p);
        }
    }
}

/// The code of a file: comment lines and a trailing `#[cfg(test)]` module removed.
fn code(text: &str) -> String {
    let end = text.find("#[cfg(test)]").unwrap_or(text.len());
    text[..end]
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .map(|l| l.split(" // ").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The identifier paths `a::b::c` in `code`, each as its segments, with the segment before
/// the path start (to tell `x::` at a path's start from `y::x::`).
fn paths(code: &str) -> Vec<Vec<String>> {
    let b = code.as_bytes();
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if ident(b[i]) && (i == 0 || !(ident(b[i - 1]) || b[i - 1] == b':')) {
            let mut segs = Vec::new();
            let mut j = i;
            loop {
                let s = j;
                while j < b.len() && ident(b[j]) {
                    j += 1;
                }
                segs.push(code[s..j].to_string());
                if code[j..].starts_with("::") && j + 2 < b.len() && ident(b[j + 2]) {
                    j += 2;
                } else if code[j..].starts_with("::{") {
                    // A use group: each member continues this prefix.
                    let close = code[j..].find('}').map_or(b.len(), |k| j + k);
                    for member in code[j + 3..close].split(',') {
                        let m: Vec<String> = member
                            .trim()
                            .split("::")
                            .map(|s| s.split_whitespace().next().unwrap_or("").into())
                            .filter(|s: &String| !s.is_empty())
                            .collect();
                        let mut p = segs.clone();
                        p.extend(m);
                        out.push(p);
                    }
                    j = close;
                    break;
                } else {
                    break;
                }
            }
            if segs.len() > 1 {
                out.push(segs);
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    out
}

/// The module a path from `from` names (None: outside the folder, or `from` itself).
fn resolve(
    from: &Module,
    is_mod_rs: bool,
    path: &[String],
    all: &BTreeMap<Module, PathBuf>,
) -> Option<Module> {
    // The module the path is relative to, and the rest of the path.
    let here: Module = from.clone();
    let (mut base, rest): (Module, &[String]) = match path.first().map(String::as_str) {
        Some("crate") => {
            let prefix = ["stages", "transient"];
            if path.len() < 3 || path[1] != prefix[0] || path[2] != prefix[1] {
                return None;
            }
            (Vec::new(), &path[3..])
        }
        Some("super") => {
            let mut b = here.clone();
            let mut k = 0;
            while path.get(k).is_some_and(|s| s == "super") {
                // `super` in a `mod.rs` is the folder's parent; in `x.rs`, the folder.
                if b.is_empty() {
                    return None;
                }
                b.pop();
                k += 1;
            }
            (b, &path[k..])
        }
        Some("self") => (here.clone(), &path[1..]),
        Some(first) if is_mod_rs => {
            let mut child = here.clone();
            child.push(first.to_string());
            if !all.contains_key(&child) {
                return None;
            }
            (here.clone(), path)
        }
        _ => return None,
    };
    let _ = is_mod_rs;
    for seg in rest {
        let mut next = base.clone();
        next.push(seg.clone());
        if all.contains_key(&next) {
            base = next;
        } else {
            break;
        }
    }
    (base != *from).then_some(base)
}

fn name(m: &Module) -> String {
    match m.is_empty() {
        true => "transient".into(),
        false => m.join("/"),
    }
}

/// The import graph of the folder.
fn graph() -> (
    BTreeMap<Module, BTreeSet<Module>>,
    BTreeMap<Module, PathBuf>,
) {
    let mut all = BTreeMap::new();
    modules(&folder(), &Vec::new(), &mut all);
    let mut g = BTreeMap::new();
    for (m, p) in &all {
        let is_mod_rs = p.file_name().is_some_and(|f| f == "mod.rs");
        let text = std::fs::read_to_string(p).unwrap();
        let edges: BTreeSet<Module> = paths(&code(&text))
            .iter()
            .filter_map(|path| resolve(m, is_mod_rs, path, &all))
            .collect();
        g.insert(m.clone(), edges);
    }
    (g, all)
}

/// A cycle of `g`, if there is one (depth-first search).
fn cycle(g: &BTreeMap<Module, BTreeSet<Module>>) -> Option<Vec<Module>> {
    fn visit(
        m: &Module,
        g: &BTreeMap<Module, BTreeSet<Module>>,
        state: &mut BTreeMap<Module, u8>,
        stack: &mut Vec<Module>,
    ) -> Option<Vec<Module>> {
        state.insert(m.clone(), 1);
        stack.push(m.clone());
        for n in g.get(m).into_iter().flatten() {
            match state.get(n).copied().unwrap_or(0) {
                1 => {
                    let at = stack.iter().position(|s| s == n).unwrap();
                    let mut c = stack[at..].to_vec();
                    c.push(n.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(n, g, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(m.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in g.keys() {
        if state.get(m).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(m, g, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

/// The graph printed (`cargo test --test layers -- --nocapture`): each module, its lines and
/// what it imports.
fn print(g: &BTreeMap<Module, BTreeSet<Module>>, all: &BTreeMap<Module, PathBuf>) {
    for (m, edges) in g {
        let lines = std::fs::read_to_string(&all[m]).unwrap().lines().count();
        let to: Vec<String> = edges.iter().map(name).collect();
        eprintln!("{:<28} {lines:>4}  -> {}", name(m), to.join(", "));
    }
}

#[test]
fn transient_modules_import_one_way() {
    let (g, all) = graph();
    print(&g, &all);
    assert!(g.len() > 5, "{} modules found", g.len());
    if let Some(c) = cycle(&g) {
        let names: Vec<String> = c.iter().map(name).collect();
        panic!("import circle: {}", names.join(" -> "));
    }
}

#[test]
fn transient_files_are_at_most_400_lines() {
    let (_, all) = graph();
    let long: Vec<String> = all
        .values()
        .filter_map(|p| {
            let n = std::fs::read_to_string(p).unwrap().lines().count();
            (n > MAX_LINES).then(|| format!("{} ({n} lines)", p.display()))
        })
        .collect();
    assert!(long.is_empty(), "over {MAX_LINES} lines: {long:?}");
}

/// The checker itself: paths, groups and relative modules resolve as the compiler would.
#[test]
fn the_checker_finds_imports_and_circles() {
    let p = paths("use super::driver::{Sink, StepView};\nlet x = crate::stages::transient::roots::estimate(a);");
    assert!(p.contains(&vec!["super".into(), "driver".into(), "Sink".into()]));
    assert!(p.contains(&vec![
        "crate".into(),
        "stages".into(),
        "transient".into(),
        "roots".into(),
        "estimate".into()
    ]));
    let mut all = BTreeMap::new();
    for m in [vec![], vec!["a".to_string()], vec!["b".to_string()]] {
        all.insert(m, PathBuf::new());
    }
    let a = vec!["a".to_string()];
    let path = |s: &str| s.split("::").map(String::from).collect::<Vec<_>>();
    assert_eq!(
        resolve(&a, false, &path("super::b::X"), &all),
        Some(vec!["b".into()])
    );
    assert_eq!(resolve(&a, false, &path("super::Item"), &all), Some(vec![]));
    assert_eq!(resolve(&vec![], true, &path("a::f"), &all), Some(a.clone()));
    assert_eq!(resolve(&a, false, &path("squeal_solver::bdf"), &all), None);
    let mut g = BTreeMap::new();
    g.insert(a.clone(), BTreeSet::from([vec!["b".to_string()]]));
    g.insert(vec!["b".to_string()], BTreeSet::from([a.clone()]));
    assert!(cycle(&g).is_some());
    g.insert(vec!["b".to_string()], BTreeSet::new());
    assert!(cycle(&g).is_none());
}

/// The verdict is pure (issue 21, item 2): the files under `src/verdict/` name nothing of the
/// crate outside that folder (no scene, sink, run folder or pipeline error) and touch no file.
#[test]
fn the_verdict_imports_nothing_above_it() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/verdict");
    let mut all = BTreeMap::new();
    modules(&dir, &Vec::new(), &mut all);
    assert!(all.len() > 5, "{} verdict modules found", all.len());
    let forbidden = ["Sink", "Scene", "RunDir", "PipelineError", "fs"];
    let mut bad = Vec::new();
    for p in all.values() {
        let text = std::fs::read_to_string(p).unwrap();
        for path in paths(&code(&text)) {
            let outside = path[0] == "crate" && path.get(1).is_none_or(|s| s != "verdict");
            if outside || path.iter().any(|s| forbidden.contains(&s.as_str())) {
                bad.push(format!("{}: {}", p.display(), path.join("::")));
            }
        }
    }
    assert!(bad.is_empty(), "the verdict imports from above it: {bad:?}");
}

/// One `Real` for the workspace (issue 21, item 5): `squeal_meshes::Real` is the only
/// `type Real` in the crates' sources; every other crate uses or re-exports it.
#[test]
fn the_workspace_defines_real_once() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut files = Vec::new();
    for krate in [
        "fe",
        "meshes",
        "reduction",
        "contact",
        "solver",
        "pipeline",
        "cli",
        "python",
    ] {
        let mut all = BTreeMap::new();
        modules(&root.join(krate), &Vec::new(), &mut all);
        files.extend(all.into_values());
    }
    assert!(files.len() > 100, "{} sources found", files.len());
    let defs: Vec<String> = files
        .iter()
        .filter(|p| {
            let text = std::fs::read_to_string(p).unwrap();
            code(&text).lines().any(|l| {
                let l = l.trim_start();
                l.starts_with("type Real ")
                    || l.contains(" type Real ")
                    || l.contains(" type Real=")
            })
        })
        .map(|p| p.strip_prefix(root).unwrap().display().to_string())
        .collect();
    assert_eq!(
        defs,
        ["meshes/src/mesh.rs"],
        "type Real defined in {defs:?}"
    );
}

/// The verbs sitting on the problem layer, and those above them (issue 21, item 3).
const VERBS: [&str; 7] = [
    "mesh",
    "modes",
    "reduce",
    "cea",
    "transient",
    "limit_cycle",
    "plotit",
];
const ABOVE: [&str; 5] = ["sweep", "reproduce", "compare", "accuracy", "propensity"];
/// The layers below the verbs.
const BELOW: [&str; 4] = ["scene", "model", "problem", "verdict"];

/// The absolute module path (below `crate`) a path in module `here` names, if it is one of the
/// crate's (`crate::`, `super::`, `self::`); None for another crate's or a local name.
fn absolute(here: &[String], path: &[String]) -> Option<Vec<String>> {
    match path.first()?.as_str() {
        "crate" => Some(path[1..].to_vec()),
        "self" => Some(here.iter().chain(&path[1..]).cloned().collect()),
        "super" => {
            let mut base = here.to_vec();
            let mut k = 0;
            while path.get(k).is_some_and(|s| s == "super") {
                base.pop()?;
                k += 1;
            }
            base.extend(path[k..].iter().cloned());
            Some(base)
        }
        _ => None,
    }
}

/// The verbs (modules of `stages`) each of the crate's top modules names, by file: the module
/// path of every `.rs` file below `src/<top>` with the verbs its code names.
fn verbs_named(top: &str) -> Vec<(String, BTreeSet<String>)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut all = BTreeMap::new();
    let dir = src.join(top);
    let module: Module = top.split('/').map(String::from).collect();
    if dir.is_dir() {
        modules(&dir, &module, &mut all);
    } else {
        all.insert(module, src.join(format!("{top}.rs")));
    }
    all.iter()
        .map(|(m, p)| {
            let text = std::fs::read_to_string(p).unwrap();
            let verbs = paths(&code(&text))
                .iter()
                .filter_map(|path| absolute(m, path))
                .filter(|a| a.len() >= 2 && a[0] == "stages")
                .map(|a| a[1].clone())
                .collect();
            (p.display().to_string(), verbs)
        })
        .collect()
}

#[test]
fn no_verb_imports_a_verb_of_its_level() {
    let mut bad = Vec::new();
    for top in BELOW {
        for (file, verbs) in verbs_named(top) {
            if !verbs.is_empty() {
                bad.push(format!("{file} (below the verbs) names {verbs:?}"));
            }
        }
    }
    for top in VERBS.iter().map(|v| format!("stages/{v}")) {
        let me = top.trim_start_matches("stages/").to_string();
        for (file, verbs) in verbs_named(&top) {
            let others: Vec<&String> = verbs.iter().filter(|v| **v != me).collect();
            if !others.is_empty() {
                bad.push(format!("{file} (a verb) names {others:?}"));
            }
        }
    }
    for top in ABOVE.iter().map(|v| format!("stages/{v}")) {
        let me = top.trim_start_matches("stages/").to_string();
        for (file, verbs) in verbs_named(&top) {
            let level: Vec<&String> = verbs
                .iter()
                .filter(|v| **v != me && !VERBS.contains(&v.as_str()))
                .collect();
            if !level.is_empty() {
                bad.push(format!("{file} (above the verbs) names {level:?}"));
            }
        }
    }
    assert!(bad.is_empty(), "imports against the layers: {bad:#?}");
    // Every verb module is in one level (a new one must be placed).
    let stages = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/stages");
    for e in std::fs::read_dir(stages).unwrap() {
        let name = e
            .unwrap()
            .path()
            .file_stem()
            .unwrap()
            .to_string_lossy()
            .to_string();
        assert!(
            name == "mod" || VERBS.contains(&name.as_str()) || ABOVE.contains(&name.as_str()),
            "stages/{name} is in no level"
        );
    }
}

/// The checker resolves `crate::`, `super::` and `self::` paths as the compiler does.
#[test]
fn absolute_paths_resolve_as_the_compiler_does() {
    let here: Vec<String> = ["stages", "cea", "energy"].map(String::from).to_vec();
    let path = |s: &str| s.split("::").map(String::from).collect::<Vec<_>>();
    let abs = |s: &str| absolute(&here, &path(s)).map(|a| a.join("::"));
    assert_eq!(
        abs("super::super::transient::run").as_deref(),
        Some("stages::transient::run")
    );
    assert_eq!(
        abs("super::params::Base").as_deref(),
        Some("stages::cea::params::Base")
    );
    assert_eq!(
        abs("crate::problem::system").as_deref(),
        Some("problem::system")
    );
    assert_eq!(abs("self::x").as_deref(), Some("stages::cea::energy::x"));
    assert_eq!(abs("squeal_solver::cea"), None);
    assert_eq!(abs("super::super::super::super::x"), None);
    let named = verbs_named("stages/sweep");
    assert!(
        named.iter().any(|(_, v)| v.contains("cea")),
        "the sweep runs the CEA: {named:?}"
    );
    // A file module's `super` is `stages`: the mesh verb names the model builder's mesh.
    let named = verbs_named("stages/mesh");
    assert_eq!(named.len(), 1, "{named:?}");
}
