//! What a user's `.geo` file lets gmsh's `-setnumber NAME VALUE` change.
//!
//! gmsh sets `NAME` before it reads the file and ignores a name the file never reads; a plain
//! assignment `NAME = 1;` in the file then overwrites the command line's value. Only the
//! constants of a `DefineConstant[ NAME = value, … ]` keep it (checked with gmsh 4.15:
//! `a = 1; DefineConstant[b = 2];` with `-setnumber a 5 -setnumber b 7` gives a = 1, b = 7).
//! [`defined_constants`] lists those names, in the file and in the files it `Include`s, so
//! that a misspelt `set_numbers` key is an error instead of a mesh with the defaults.

use crate::MeshError;
use std::collections::BTreeSet;
use std::path::Path;

/// Largest depth of nested `Include`s followed (deeper ones are not read).
const MAX_INCLUDE_DEPTH: usize = 16;

/// The names of every `DefineConstant[…]` entry of the `.geo` file `path` and of the files it
/// includes (relative paths resolved against the including file's folder; an include that
/// cannot be read is skipped: gmsh reports it when it runs). A missing `path` is an error
/// naming it.
pub fn defined_constants(path: &Path) -> Result<BTreeSet<String>, MeshError> {
    let mut names = BTreeSet::new();
    let text = std::fs::read_to_string(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    collect(
        &text,
        path.parent().unwrap_or(Path::new(".")),
        0,
        &mut names,
    );
    Ok(names)
}

fn collect(text: &str, dir: &Path, depth: usize, names: &mut BTreeSet<String>) {
    let code = strip_comments(text);
    let blanked = blank_strings(&code);
    let mut rest = blanked.as_str();
    while let Some(i) = rest.find("DefineConstant") {
        let after = rest[i + "DefineConstant".len()..].trim_start();
        let Some(body) = after.strip_prefix('[') else {
            rest = &rest[i + 1..];
            continue;
        };
        let (inside, tail) = bracketed(body);
        for entry in top_level_split(inside) {
            if let Some((name, _)) = entry.split_once('=') {
                let name = name.trim();
                if is_identifier(name) {
                    names.insert(name.to_string());
                }
            }
        }
        rest = tail;
    }
    if depth >= MAX_INCLUDE_DEPTH {
        return;
    }
    let mut rest = code.as_str();
    while let Some(i) = rest.find("Include") {
        let after = rest[i + "Include".len()..].trim_start();
        rest = &rest[i + 1..];
        let Some(quoted) = after.strip_prefix('"') else {
            continue;
        };
        let Some(end) = quoted.find('"') else {
            continue;
        };
        let file = dir.join(&quoted[..end]);
        if let Ok(t) = std::fs::read_to_string(&file) {
            collect(&t, file.parent().unwrap_or(dir), depth + 1, names);
        }
    }
}

/// The text up to the `]` closing an opening `[` already consumed, and what follows it.
fn bracketed(s: &str) -> (&str, &str) {
    let mut level = 0usize;
    let mut in_string = false;
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_string = !in_string,
            '[' | '{' | '(' if !in_string => level += 1,
            ']' if !in_string && level == 0 => return (&s[..i], &s[i + 1..]),
            ']' | '}' | ')' if !in_string => level = level.saturating_sub(1),
            _ => {}
        }
    }
    (s, "")
}

/// `s` split at the commas outside braces, brackets, parentheses and strings.
fn top_level_split(s: &str) -> Vec<&str> {
    let (mut out, mut level, mut start, mut in_string) = (Vec::new(), 0usize, 0, false);
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_string = !in_string,
            '[' | '{' | '(' if !in_string => level += 1,
            ']' | '}' | ')' if !in_string => level = level.saturating_sub(1),
            ',' if !in_string && level == 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

fn is_identifier(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The contents of every string literal replaced by spaces (the quotes kept).
fn blank_strings(code: &str) -> String {
    let mut in_string = false;
    code.chars()
        .map(|c| {
            if c == '"' {
                in_string = !in_string;
                c
            } else if in_string {
                ' '
            } else {
                c
            }
        })
        .collect()
}

/// `//` line comments and `/* */` block comments removed (not inside strings).
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let mut in_string = false;
    while let Some(c) = chars.next() {
        if in_string {
            in_string = c != '"';
            out.push(c);
            continue;
        }
        match (c, chars.peek()) {
            ('"', _) => {
                in_string = true;
                out.push(c);
            }
            ('/', Some('/')) => {
                for d in chars.by_ref() {
                    if d == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            ('/', Some('*')) => {
                chars.next();
                let mut prev = ' ';
                for d in chars.by_ref() {
                    if prev == '*' && d == '/' {
                        break;
                    }
                    prev = d;
                }
                out.push(' ');
            }
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names of single-value, braced (with attributes) and multi-line entries; comments,
    /// plain assignments and strings are not constants; includes are followed.
    #[test]
    fn constants_of_a_file_and_its_includes() {
        let dir = std::env::temp_dir().join(format!("squeal-geo-consts-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(
            dir.join("sub/inc.geo"),
            "DefineConstant[ from_include = 3 ];\n",
        )
        .unwrap();
        let main = dir.join("main.geo");
        std::fs::write(
            &main,
            "// DefineConstant[ commented = 1 ];\n/* DefineConstant[ blocked = 1 ]; */\n\
             a = 1;\nDefineConstant[ L = 0.2, W = {0.04, Min 0.01, Max 1, Name \"W, m\"},\n  \
             nl = 10 ];\nInclude \"sub/inc.geo\";\nPrintf(\"DefineConstant[ s = 1 ]\");\n",
        )
        .unwrap();
        let names: Vec<String> = defined_constants(&main).unwrap().into_iter().collect();
        assert_eq!(names, ["L", "W", "from_include", "nl"]);
        let e = defined_constants(&dir.join("missing.geo")).unwrap_err();
        assert!(e.to_string().contains("missing.geo"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
