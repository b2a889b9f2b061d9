//! Abaqus input lines into keyword blocks: a keyword line with its parameters, then its data
//! lines.
//!
//! Rules (Abaqus Keywords Reference, "Input syntax rules"): a line starting with `**` is a
//! comment; a line starting with `*` is a keyword line, `*KEYWORD, PARAM=value, FLAG`, and a
//! keyword line ending with a comma goes on on the next line; keywords, parameters and their
//! values are case-insensitive (names are compared without case; the spelling of a name's
//! first definition is kept); other lines are data lines of comma-separated items (a line
//! ending with a comma marks an item list that goes on, e.g. an element with more than 15
//! nodes). Blank lines are skipped. `*INCLUDE, INPUT=file` reads that file in place, relative
//! to the folder of the including file.

use crate::deck::{shorten, Deck, Loc};
use crate::MeshError;

/// One data line: its items (trimmed) and whether it ended with a comma.
#[derive(Debug, Clone)]
pub(crate) struct DataLine {
    pub at: Loc,
    pub items: Vec<String>,
    pub open: bool,
}

/// A keyword with its parameters and data lines.
#[derive(Debug, Clone)]
pub(crate) struct Block {
    /// Upper case, single spaces (`SOLID SECTION`).
    pub keyword: String,
    /// (upper-case name, value as written, quotes kept: see [`name_key`]).
    pub params: Vec<(String, Option<String>)>,
    pub at: Loc,
    pub data: Vec<DataLine>,
}

impl Block {
    /// The value of parameter `name` (upper case), if given with a value.
    pub fn param(&self, name: &str) -> Option<&str> {
        self.params
            .iter()
            .find(|(n, _)| n == name)
            .and_then(|(_, v)| v.as_deref())
    }

    /// True when parameter `name` is present (with or without a value).
    pub fn flag(&self, name: &str) -> bool {
        self.params.iter().any(|(n, _)| n == name)
    }
}

/// Reads every keyword block of `deck`, following `*INCLUDE`; `f` gets each complete block.
pub(crate) fn read_blocks(
    deck: &mut Deck,
    mut f: impl FnMut(&Deck, Block) -> Result<(), MeshError>,
) -> Result<(), MeshError> {
    let mut pending: Option<Block> = None;
    while let Some((at, raw)) = deck.next_line() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if let Some(rest) = line.strip_prefix('*') {
            if let Some(b) = pending.take() {
                f(deck, b)?;
            }
            // Keyword-line continuation: a trailing comma.
            let mut text = rest.to_string();
            while text.trim_end().ends_with(',') {
                match deck.next_line() {
                    Some((_, l)) if !l.trim().starts_with('*') => {
                        text.push_str(l.trim());
                    }
                    _ => {
                        return Err(deck.err(
                            at,
                            format!(
                                "keyword line `*{}` ends with a comma but no continuation \
                                 line follows",
                                shorten(rest)
                            ),
                        ))
                    }
                }
            }
            let block = parse_keyword(deck, &text, at)?;
            if block.keyword == "INCLUDE" {
                let Some(name) = block.param("INPUT") else {
                    return Err(deck.err(at, "*INCLUDE without INPUT=file"));
                };
                let name = unquote(name).to_string();
                deck.include(&name, at)?;
                continue;
            }
            pending = Some(block);
            continue;
        }
        let Some(b) = pending.as_mut() else {
            return Err(deck.err(
                at,
                format!("data line `{}` before any keyword line", shorten(line)),
            ));
        };
        let open = line.ends_with(',');
        let body = if open { &line[..line.len() - 1] } else { line };
        let items = body.split(',').map(|s| s.trim().to_string()).collect();
        b.data.push(DataLine { at, items, open });
    }
    if let Some(b) = pending.take() {
        f(deck, b)?;
    }
    Ok(())
}

/// `KEYWORD, P1=v1, P2` (text after the `*`).
fn parse_keyword(deck: &Deck, text: &str, at: Loc) -> Result<Block, MeshError> {
    let parts = split_quoted(text).map_err(|m| deck.err(at, m))?;
    let keyword = parts[0]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_uppercase();
    if keyword.is_empty() || !keyword.starts_with(|c: char| c.is_ascii_alphabetic()) {
        return Err(deck.err(at, format!("`*{}` is not a keyword line", shorten(text))));
    }
    let mut params = Vec::new();
    for p in &parts[1..] {
        if p.trim().is_empty() {
            continue;
        }
        let (name, value) = match p.split_once('=') {
            Some((n, v)) => (n, Some(v.trim().to_string())),
            None => (p.as_str(), None),
        };
        let name = name
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .to_ascii_uppercase();
        if name.is_empty() {
            return Err(deck.err(
                at,
                format!("*{keyword}: a parameter `{}` without a name", shorten(p)),
            ));
        }
        params.push((name, value));
    }
    Ok(Block {
        keyword,
        params,
        at,
        data: Vec::new(),
    })
}

/// Splits at commas outside double quotes.
fn split_quoted(text: &str) -> Result<Vec<String>, String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    for c in text.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                out.last_mut().unwrap_or(&mut String::new()).push(c);
            }
            ',' if !quoted => out.push(String::new()),
            _ => {
                if let Some(s) = out.last_mut() {
                    s.push(c);
                }
            }
        }
    }
    if quoted {
        return Err(format!("`*{}`: unbalanced double quote", shorten(text)));
    }
    Ok(out)
}

fn unquote(v: &str) -> &str {
    v.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(v)
}

/// A name as Abaqus compares it: upper case unless quoted (then as written, quotes removed).
pub(crate) fn name_key(s: &str) -> String {
    let t = s.trim();
    match t.strip_prefix('"').and_then(|x| x.strip_suffix('"')) {
        Some(q) => q.to_string(),
        None => t.to_ascii_uppercase(),
    }
}

/// A name as written, without quotes.
pub(crate) fn name_text(s: &str) -> String {
    unquote(s.trim()).to_string()
}

/// An Abaqus integer label (a positive integer).
pub(crate) fn label(s: &str) -> Option<u64> {
    let t = s.trim();
    if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    t.parse().ok().filter(|&v| v > 0)
}

/// An Abaqus real: Fortran-style (`1.`, `.5`, `1.5E3`, `1.5D3`); only finite values.
pub(crate) fn real(s: &str) -> Option<f64> {
    let t = s.trim().to_ascii_uppercase().replace('D', "E");
    if t.is_empty()
        || !t
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'E' | b'+' | b'-'))
        || !t
            .split('E')
            .next()
            .is_some_and(|m| m.bytes().any(|b| b.is_ascii_digit()))
    {
        return None;
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn blocks(text: &str) -> Vec<Block> {
        let mut d = Deck::from_bytes(text.as_bytes().to_vec(), "t.inp", Path::new("."));
        let mut out = Vec::new();
        read_blocks(&mut d, |_, b| {
            out.push(b);
            Ok(())
        })
        .unwrap();
        out
    }

    #[test]
    fn keywords_parameters_and_continuations() {
        let b = blocks(
            "** comment\n*Heading\n title\n*Element, type=c3d20r,\n elset=\"My Set\"\n\
             1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,\n 16, 17, 18, 19, 20\n\
             *solid  section, ELSET=a, material=STEEL\n,\n",
        );
        assert_eq!(b.len(), 3);
        assert_eq!(b[1].keyword, "ELEMENT");
        assert_eq!(b[1].param("TYPE"), Some("c3d20r"));
        assert_eq!(b[1].param("ELSET"), Some("\"My Set\""));
        assert_eq!(b[1].data.len(), 2);
        assert!(b[1].data[0].open);
        assert_eq!(b[1].data[0].items.len(), 16);
        assert_eq!(b[2].keyword, "SOLID SECTION");
        assert_eq!(name_key("steel"), "STEEL");
        assert_eq!(name_key("\"Steel\""), "Steel");
        assert_eq!(real("2.1E5"), Some(2.1e5));
        assert_eq!(real("1."), Some(1.0));
        assert_eq!(real("nan"), None);
        assert_eq!(label("12"), Some(12));
        assert_eq!(label("-1"), None);
    }
}
