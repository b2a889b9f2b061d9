//! Line-oriented input files with includes (Nastran `INCLUDE`, Abaqus `*INCLUDE`): a stack of
//! open files, each line tagged with its file and line number for error messages.
//!
//! Lines are text: valid UTF-8 is taken as it is, any other line is read as Latin-1 (decks
//! written on old systems carry Latin-1 comments). An included file's relative path is
//! resolved against the folder of the file that includes it. Includes nest up to
//! [`MAX_DEPTH`] files deep; a file including itself (directly or not) is an error.

use crate::MeshError;
use std::path::{Path, PathBuf};

/// Deepest include nesting accepted.
pub(crate) const MAX_DEPTH: usize = 32;

/// Where a line is: index into [`Deck::files`] and 1-based line number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Loc {
    pub file: u32,
    pub line: u32,
}

struct Open {
    file: u32,
    bytes: Vec<u8>,
    pos: usize,
    line: u32,
    dir: PathBuf,
    /// Canonical path, for the include-cycle check (None for in-memory input).
    canonical: Option<PathBuf>,
}

/// The files of one input deck, read line by line.
pub(crate) struct Deck {
    /// Display names of every file opened so far (errors name them).
    pub files: Vec<String>,
    stack: Vec<Open>,
}

impl Deck {
    /// A deck whose main file is `bytes` named `name`; includes resolve against `dir`.
    pub fn from_bytes(bytes: Vec<u8>, name: &str, dir: &Path) -> Deck {
        Deck {
            files: vec![name.to_string()],
            stack: vec![Open {
                file: 0,
                bytes,
                pos: 0,
                line: 0,
                dir: dir.to_path_buf(),
                canonical: None,
            }],
        }
    }

    /// A deck whose main file is `path`.
    pub fn open(path: &Path) -> Result<Deck, MeshError> {
        let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut d = Deck::from_bytes(bytes, &path.display().to_string(), &dir);
        d.stack[0].canonical = path.canonicalize().ok();
        Ok(d)
    }

    /// The next line (without its terminator) and where it is; None when every file is read.
    pub fn next_line(&mut self) -> Option<(Loc, String)> {
        loop {
            let top = self.stack.last_mut()?;
            if top.pos >= top.bytes.len() {
                self.stack.pop();
                continue;
            }
            let rest = &top.bytes[top.pos..];
            let (raw, used) = match rest.iter().position(|&b| b == b'\n') {
                Some(i) => (&rest[..i], i + 1),
                None => (rest, rest.len()),
            };
            let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
            let text = match std::str::from_utf8(raw) {
                Ok(s) => s.to_string(),
                Err(_) => raw.iter().map(|&b| b as char).collect(),
            };
            top.pos += used;
            top.line += 1;
            return Some((
                Loc {
                    file: top.file,
                    line: top.line,
                },
                text,
            ));
        }
    }

    /// Opens `name` (relative to the including file's folder) as the next lines, included at
    /// `at`.
    pub fn include(&mut self, name: &str, at: Loc) -> Result<(), MeshError> {
        let dir = self.stack.last().map(|o| o.dir.clone()).unwrap_or_default();
        let path = dir.join(name);
        if self.stack.len() >= MAX_DEPTH {
            return Err(self.err(
                at,
                format!("include `{name}`: more than {MAX_DEPTH} nested includes"),
            ));
        }
        let bytes = std::fs::read(&path).map_err(|e| {
            self.err(
                at,
                format!("include `{name}`: cannot read {}: {e}", path.display()),
            )
        })?;
        let canonical = path.canonicalize().ok();
        if let Some(c) = &canonical {
            if self.stack.iter().any(|o| o.canonical.as_ref() == Some(c)) {
                return Err(self.err(
                    at,
                    format!(
                        "include `{name}`: {} is already being read (an include cycle)",
                        path.display()
                    ),
                ));
            }
        }
        self.files.push(path.display().to_string());
        self.stack.push(Open {
            file: (self.files.len() - 1) as u32,
            bytes,
            pos: 0,
            line: 0,
            dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            canonical,
        });
        Ok(())
    }

    /// The main file's bytes.
    pub fn main_bytes(&self) -> &[u8] {
        self.stack.first().map(|o| &o.bytes[..]).unwrap_or(&[])
    }

    /// Stops reading every file (an end-of-data line).
    pub fn finish(&mut self) {
        self.stack.clear();
    }

    /// `file:line` of `at`.
    pub fn at(&self, at: Loc) -> String {
        format!("{}:{}", self.file(at), at.line)
    }

    /// Display name of the file of `at`.
    pub fn file(&self, at: Loc) -> &str {
        self.files
            .get(at.file as usize)
            .map(String::as_str)
            .unwrap_or("?")
    }

    /// An error at `at`.
    pub fn err(&self, at: Loc, message: impl Into<String>) -> MeshError {
        MeshError::Parse {
            file: self.file(at).to_string(),
            line: at.line as usize,
            message: message.into(),
        }
    }
}

/// A short, printable form of a piece of input for error messages (at most 40 characters).
pub(crate) fn shorten(s: &str) -> String {
    let s = s.trim();
    let mut out: String = s
        .chars()
        .take(40)
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    if s.chars().count() > 40 {
        out.push('…');
    }
    out
}
