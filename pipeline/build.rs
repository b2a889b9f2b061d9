//! The build id of the model cache (`stages/model/cache/key.rs`): a hash of the sources of
//! every crate whose code turns a scene into a reduced model, and of the build profile. The
//! same sources give the same id in the `squeal` command, the tests and the Python module, so
//! they share cached models; any change to those sources starts a fresh cache.

use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs" || x == "geo") {
            out.push(p);
        }
    }
}

fn main() {
    let here = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap_or_else(|_| ".".into()));
    let root = here.parent().map(Path::to_path_buf).unwrap_or(here.clone());
    let mut files = Vec::new();
    for krate in ["fe", "meshes", "reduction", "contact", "pipeline"] {
        let src = root.join(krate).join("src");
        println!("cargo:rerun-if-changed={}", src.display());
        sources(&src, &mut files);
    }
    files.sort();
    // FNV-1a 64 over (relative path, contents) of every source file.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for f in &files {
        eat(f
            .strip_prefix(&root)
            .unwrap_or(f)
            .to_string_lossy()
            .as_bytes());
        eat(&std::fs::read(f).unwrap_or_default());
    }
    eat(std::env::var("PROFILE").unwrap_or_default().as_bytes());
    eat(std::env::var("OPT_LEVEL").unwrap_or_default().as_bytes());
    println!("cargo:rustc-env=SQUEAL_BUILD_ID={h:016x}");
}
