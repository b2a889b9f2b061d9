//! Running the gmsh program on a `.geo` text.
//!
//! gmsh is found, in this order: the environment variable `SQUEAL_GMSH` (a program path); a
//! project virtual environment `.venv/bin/gmsh` in the current directory or one above it, or
//! above the running executable (run as `.venv/bin/python .venv/bin/gmsh`, because pip's
//! launcher starts with `#!/usr/bin/env python`); `gmsh` on `PATH`.

use crate::{MeshError, Real};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// How gmsh meshes a `.geo` file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GmshOptions {
    /// Element order: 1 → hex8, 2 → hex20 (incomplete second order) (default: 2).
    pub order: u8,
    /// `.geo` parameters to override, passed as `-setnumber NAME VALUE` (default: none).
    pub set_numbers: BTreeMap<String, Real>,
    /// Write msh 4.1 binary instead of ASCII (default: false).
    pub binary: bool,
    /// Asked every 20 ms while gmsh runs; when set gmsh is killed, its partial output removed
    /// and the run returns [`MeshError::Interrupted`] (default: never; not serialised).
    #[serde(skip)]
    pub interrupt: crate::Interrupt,
}

impl Default for GmshOptions {
    fn default() -> Self {
        GmshOptions {
            order: 2,
            set_numbers: BTreeMap::new(),
            binary: false,
            interrupt: crate::Interrupt::never(),
        }
    }
}

impl GmshOptions {
    /// Checks every field; the error names the field and its value.
    pub fn validate(&self) -> Result<(), MeshError> {
        if !(1..=2).contains(&self.order) {
            return Err(MeshError::InvalidGmshOption {
                field: "order",
                value: self.order.to_string(),
                reason: "must be 1 (hex8) or 2 (hex20)".into(),
            });
        }
        for (name, v) in &self.set_numbers {
            let ok_name = name
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !ok_name || !v.is_finite() {
                return Err(MeshError::InvalidGmshOption {
                    field: "set_numbers",
                    value: format!("{name} = {v}"),
                    reason: "needs an identifier name and a finite value".into(),
                });
            }
        }
        Ok(())
    }
}

/// What a gmsh run did (written to summaries).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GmshRun {
    /// The command line, for reproducing the run.
    pub command: String,
    /// The `.geo` file written beside the mesh.
    pub geo_path: PathBuf,
    /// The mesh written.
    pub msh_path: PathBuf,
    /// gmsh's version as it reports it (e.g. "4.15.2"), when it does.
    pub version: Option<String>,
    /// Wall time of the gmsh process, seconds.
    pub elapsed_s: f64,
    /// gmsh's standard output.
    pub stdout: String,
    /// gmsh's standard error (warnings).
    pub stderr: String,
}

/// A way to start gmsh: a program and the arguments that come before gmsh's own.
#[derive(Debug, Clone, PartialEq)]
pub struct GmshProgram {
    pub program: PathBuf,
    pub prefix_args: Vec<OsString>,
}

impl GmshProgram {
    fn command(&self) -> Command {
        let mut c = Command::new(&self.program);
        c.args(&self.prefix_args);
        c
    }
}

/// Finds gmsh (see the module documentation for the search order).
pub fn find_gmsh() -> Result<GmshProgram, MeshError> {
    if let Some(p) = std::env::var_os("SQUEAL_GMSH").filter(|p| !p.is_empty()) {
        let p = PathBuf::from(p);
        if p.is_file() {
            return Ok(GmshProgram {
                program: p,
                prefix_args: Vec::new(),
            });
        }
        return Err(MeshError::GmshNotFound {
            searched: format!("SQUEAL_GMSH = {} is not a file", p.display()),
        });
    }
    let mut starts = Vec::new();
    if let Ok(d) = std::env::current_dir() {
        starts.push(d);
    }
    if let Some(d) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(Path::to_path_buf))
    {
        starts.push(d);
    }
    for start in &starts {
        for dir in start.ancestors() {
            let bin = dir.join(".venv").join("bin");
            let (python, gmsh) = (bin.join("python"), bin.join("gmsh"));
            if python.is_file() && gmsh.is_file() {
                return Ok(GmshProgram {
                    program: python,
                    prefix_args: vec![gmsh.into_os_string()],
                });
            }
        }
    }
    if let Some(path) = std::env::var_os("PATH") {
        for dir in std::env::split_paths(&path) {
            for name in ["gmsh", "gmsh.exe"] {
                let p = dir.join(name);
                if p.is_file() {
                    return Ok(GmshProgram {
                        program: p,
                        prefix_args: Vec::new(),
                    });
                }
            }
        }
    }
    Err(MeshError::GmshNotFound {
        searched: "SQUEAL_GMSH is unset, no .venv/bin/gmsh above the current directory or the executable, no gmsh on PATH".into(),
    })
}

/// Writes `geo_text` beside `out_msh` (same name, extension `.geo`), meshes it in 3D with
/// gmsh and writes msh 4.1 to `out_msh` (through a `.msh.tmp` file renamed on success).
/// gmsh's exit status is 0 even after errors in the `.geo`, so any `Error` line it prints
/// fails the run too.
pub fn mesh_geo(geo_text: &str, out_msh: &Path, opts: &GmshOptions) -> Result<GmshRun, MeshError> {
    opts.validate()?;
    let geo_path = out_msh.with_extension("geo");
    if let Some(dir) = out_msh.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    }
    std::fs::write(&geo_path, geo_text).map_err(io_err(&geo_path))?;
    run_gmsh(&geo_path, out_msh, opts)
}

/// Meshes the user's `.geo` file `geo_path` in place (gmsh resolves its `Include` and `Merge`
/// paths against the file's folder) and writes msh 4.1 to `out_msh` (through a `.msh.tmp`
/// file renamed on success). The element order is `opts.order`, whatever the file sets
/// (`-order` on gmsh's command line wins over `Mesh.ElementOrder`). A missing file is an error
/// naming it; gmsh's `Error` lines fail the run as in [`mesh_geo`].
pub fn mesh_geo_file(
    geo_path: &Path,
    out_msh: &Path,
    opts: &GmshOptions,
) -> Result<GmshRun, MeshError> {
    opts.validate()?;
    if !geo_path.is_file() {
        return Err(MeshError::Io {
            path: geo_path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such .geo file"),
        });
    }
    if let Some(dir) = out_msh.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    }
    run_gmsh(geo_path, out_msh, opts)
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> MeshError {
    let path = path.to_path_buf();
    move |source| MeshError::Io { path, source }
}

/// Runs gmsh on the `.geo` file `geo_path`, writing `out_msh`.
fn run_gmsh(geo_path: &Path, out_msh: &Path, opts: &GmshOptions) -> Result<GmshRun, MeshError> {
    let gmsh = find_gmsh()?;
    let io = io_err;
    let geo_path = geo_path.to_path_buf();
    let mut tmp = out_msh.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let _ = std::fs::remove_file(&tmp);

    let mut args: Vec<OsString> = vec![
        geo_path.clone().into_os_string(),
        "-3".into(),
        "-format".into(),
        "msh41".into(),
    ];
    if opts.binary {
        args.push("-bin".into());
    }
    args.extend(["-order".into(), opts.order.to_string().into()]);
    if opts.order == 2 {
        args.extend(["-string".into(), "Mesh.SecondOrderIncomplete=1;".into()]);
    }
    for (name, v) in &opts.set_numbers {
        args.extend(["-setnumber".into(), name.into(), format!("{v:?}").into()]);
    }
    args.extend(["-o".into(), tmp.clone().into_os_string()]);
    let command = display_command(&gmsh, &args);

    let start = Instant::now();
    let output = run_until_done(&gmsh, &args, &command, &opts.interrupt).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })?;
    let elapsed_s = start.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    let errors: Vec<&str> = stdout
        .lines()
        .chain(stderr.lines())
        .filter(|l| l.starts_with("Error"))
        .collect();
    let failed = |message: String| MeshError::GmshFailed {
        command: command.clone(),
        status: output.status.to_string(),
        message,
    };
    if !output.status.success() || !errors.is_empty() {
        let _ = std::fs::remove_file(&tmp);
        let message = if errors.is_empty() {
            tail(&stderr, &stdout)
        } else {
            errors.join("\n")
        };
        return Err(failed(message));
    }
    if !tmp.is_file() {
        return Err(failed(format!(
            "gmsh wrote no mesh to {}: {}",
            tmp.display(),
            tail(&stderr, &stdout)
        )));
    }
    std::fs::rename(&tmp, out_msh).map_err(io(out_msh))?;
    Ok(GmshRun {
        command,
        geo_path,
        msh_path: out_msh.to_path_buf(),
        version: parse_version(&stdout),
        elapsed_s,
        stdout,
        stderr,
    })
}

/// Runs gmsh to its end, its output read on two threads, polling `interrupt` every 20 ms:
/// when it is set the child is killed and reaped, and the run is
/// [`MeshError::Interrupted`].
fn run_until_done(
    gmsh: &GmshProgram,
    args: &[OsString],
    command: &str,
    interrupt: &crate::Interrupt,
) -> Result<std::process::Output, MeshError> {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = gmsh
        .command()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| MeshError::GmshFailed {
            command: command.to_string(),
            status: "not started".into(),
            message: e.to_string(),
        })?;
    let reader = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let out = reader(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let err = reader(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let failed = |e: std::io::Error| MeshError::GmshFailed {
        command: command.to_string(),
        status: "lost".into(),
        message: e.to_string(),
    };
    let status = loop {
        if let Some(s) = child.try_wait().map_err(failed)? {
            break s;
        }
        if interrupt.is_set() {
            let _ = child.kill();
            let _ = child.wait();
            return Err(MeshError::Interrupted {
                command: command.to_string(),
            });
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Ok(std::process::Output {
        status,
        stdout: out.join().unwrap_or_default(),
        stderr: err.join().unwrap_or_default(),
    })
}

/// The version from gmsh's banner `Info : Running '...' [Gmsh 4.15.2, 1 node, ...]`.
fn parse_version(stdout: &str) -> Option<String> {
    let i = stdout.find("[Gmsh ")?;
    let rest = &stdout[i + 6..];
    let end = rest.find([',', ']'])?;
    Some(rest[..end].trim().to_string())
}

/// The last lines gmsh printed, for an error message.
fn tail(stderr: &str, stdout: &str) -> String {
    let text = if stderr.trim().is_empty() {
        stdout
    } else {
        stderr
    };
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(8)..].join("\n")
}

fn display_command(gmsh: &GmshProgram, args: &[OsString]) -> String {
    std::iter::once(gmsh.program.as_os_str())
        .chain(gmsh.prefix_args.iter().map(OsString::as_os_str))
        .chain(args.iter().map(OsString::as_os_str))
        .map(|a| {
            let s = a.to_string_lossy();
            if s.contains([' ', '"', ';']) {
                format!("'{s}'")
            } else {
                s.into_owned()
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn version_from_banner() {
        let out = "Info    : Running 'gmsh a.geo -3' [Gmsh 4.15.2, 1 node, max. 1 thread]\n";
        assert_eq!(parse_version(out).as_deref(), Some("4.15.2"));
        assert_eq!(parse_version("nothing"), None);
    }

    #[test]
    fn options_validate() {
        GmshOptions::default().validate().unwrap();
        let o = GmshOptions {
            order: 3,
            ..Default::default()
        };
        assert!(o.validate().unwrap_err().to_string().contains("order"));
        let mut o = GmshOptions::default();
        o.set_numbers.insert("r out".into(), 1.0);
        assert!(o.validate().unwrap_err().to_string().contains("r out"));
    }
}
