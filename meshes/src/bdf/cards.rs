//! Bulk data cards from physical lines: comments, continuations, `INCLUDE`, `BEGIN BULK`,
//! `ENDDATA`, and the case control's `SPC = n` before `BEGIN BULK`.
//!
//! A `$` starts a comment anywhere on a line. When the main file has a `BEGIN BULK` line, the
//! lines before it are executive and case control: only `SPC = n` is read there (the
//! constraint set the deck's subcases select); else the whole file is bulk data (an include
//! file, or a deck without controls). `ENDDATA` ends the input. `INCLUDE 'file'` (the quoted
//! name may go on over several lines) reads that file in place, relative to the folder of
//! the file that includes it.

use super::fields::{self, Head};
use crate::deck::{shorten, Deck, Loc};
use crate::MeshError;

/// One bulk data card: its name and data fields (continuations appended in order; field `i`
/// is Nastran's field `i % 8 + 2` of the `i / 8`-th logical line).
#[derive(Debug, Clone)]
pub(crate) struct Card {
    pub name: String,
    pub at: Loc,
    pub fields: Vec<String>,
    /// Physical line of each field (errors name it).
    pub lines: Vec<u32>,
}

/// What the lines before `BEGIN BULK` said.
#[derive(Debug, Default)]
pub(crate) struct CaseControl {
    /// The `SPC = n` set ids, with where they are.
    pub spc: Vec<(u64, Loc)>,
}

/// Reads every card of `deck`; `f` gets each complete card.
pub(crate) fn read_cards(
    deck: &mut Deck,
    mut f: impl FnMut(&Deck, Card) -> Result<(), MeshError>,
) -> Result<CaseControl, MeshError> {
    let case = read_controls(deck)?;
    let mut pending: Option<Card> = None;
    while let Some((at, raw)) = deck.next_line() {
        let line = match raw.find('$') {
            Some(i) => &raw[..i],
            None => &raw[..],
        };
        if line.trim().is_empty() {
            continue;
        }
        let upper = line.trim_start().to_ascii_uppercase();
        if upper.starts_with("INCLUDE") && !upper[7..].starts_with(|c: char| c.is_alphanumeric()) {
            let name = include_name(deck, line.trim_start()[7..].trim(), at)?;
            if let Some(card) = pending.take() {
                f(deck, card)?;
            }
            deck.include(&name, at)?;
            continue;
        }
        if upper.trim_end() == "ENDDATA" || upper.starts_with("ENDDATA ") {
            break;
        }
        if upper.starts_with("BEGIN ") && upper.contains("BULK") {
            return Err(deck.err(
                at,
                format!(
                    "`{}`: a second BEGIN BULK (partitioned superelement bulk data is not read)",
                    shorten(line)
                ),
            ));
        }
        let split = fields::split(line).map_err(|m| deck.err(at, m))?;
        match split.head {
            Head::Card { name, .. } => {
                if let Some(card) = pending.take() {
                    f(deck, card)?;
                }
                let n = split.data.len();
                pending = Some(Card {
                    name,
                    at,
                    fields: split.data,
                    lines: vec![at.line; n],
                });
            }
            Head::Continuation { .. } => {
                let Some(card) = pending.as_mut() else {
                    return Err(deck.err(
                        at,
                        format!(
                            "`{}` is a continuation line with no card before it",
                            shorten(line)
                        ),
                    ));
                };
                // A large-field card's lines hold 4 data fields; a continuation in small
                // field after a large line completes its logical line first.
                card.lines
                    .extend(std::iter::repeat_n(at.line, split.data.len()));
                card.fields.extend(split.data);
            }
        }
    }
    if let Some(card) = pending.take() {
        f(deck, card)?;
    }
    deck.finish();
    Ok(case)
}

/// The file name of an `INCLUDE` whose text after the keyword is `rest`: quoted (possibly
/// over several lines) or a bare word.
fn include_name(deck: &mut Deck, rest: &str, at: Loc) -> Result<String, MeshError> {
    let Some(quoted) = rest.strip_prefix('\'') else {
        let name = rest.split_whitespace().next().unwrap_or("");
        if name.is_empty() {
            return Err(deck.err(at, "INCLUDE without a file name"));
        }
        return Ok(name.to_string());
    };
    let mut name = String::new();
    let mut part = quoted.to_string();
    for _ in 0..64 {
        if let Some(end) = part.find('\'') {
            name.push_str(part[..end].trim());
            if name.is_empty() {
                return Err(deck.err(at, "INCLUDE '' names no file"));
            }
            return Ok(name);
        }
        name.push_str(part.trim());
        match deck.next_line() {
            Some((_, l)) => part = l,
            None => break,
        }
    }
    Err(deck.err(at, "INCLUDE: the quoted file name has no closing quote"))
}

/// Reads the executive and case control up to `BEGIN BULK` when the main file has that line;
/// otherwise leaves the deck where it was.
fn read_controls(deck: &mut Deck) -> Result<CaseControl, MeshError> {
    let mut case = CaseControl::default();
    let Some(n) = begin_bulk_line(deck.main_bytes()) else {
        return Ok(case);
    };
    for _ in 0..n {
        let Some((at, raw)) = deck.next_line() else {
            break;
        };
        let text = raw
            .split('$')
            .next()
            .unwrap_or("")
            .trim()
            .to_ascii_uppercase();
        if text.starts_with("BEGIN") {
            if text.split_whitespace().collect::<Vec<_>>() != ["BEGIN", "BULK"] {
                return Err(deck.err(
                    at,
                    format!(
                        "`{}`: only `BEGIN BULK` is read (partitioned superelement bulk data \
                         is not)",
                        shorten(&raw)
                    ),
                ));
            }
            continue;
        }
        let Some(rest) = text.strip_prefix("SPC") else {
            continue;
        };
        let Some(value) = rest.trim_start().strip_prefix('=') else {
            continue;
        };
        let value = value.trim();
        match fields::int(value) {
            Some(id) if id > 0 => case.spc.push((id as u64, at)),
            _ => {
                return Err(deck.err(
                    at,
                    format!("case control `SPC = {value}`: not a positive set id"),
                ))
            }
        }
    }
    Ok(case)
}

/// The number of lines up to and including the first `BEGIN … BULK` line of `bytes`, if any.
fn begin_bulk_line(bytes: &[u8]) -> Option<usize> {
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let text = String::from_utf8_lossy(raw);
        let t = text
            .split('$')
            .next()
            .unwrap_or("")
            .trim()
            .to_ascii_uppercase();
        if t.starts_with("BEGIN") && t.contains("BULK") {
            return Some(i + 1);
        }
    }
    None
}
