//! Typed access to a card's fields: integers, ids, reals, with errors naming the file, line,
//! card, entity id and field.

use super::cards::Card;
use super::fields;
use crate::deck::{shorten, Deck, Loc};
use crate::MeshError;

/// A card being read, with the deck for error messages.
pub(crate) struct Fields<'a> {
    pub deck: &'a Deck,
    pub card: &'a Card,
}

impl<'a> Fields<'a> {
    pub fn new(deck: &'a Deck, card: &'a Card) -> Self {
        Fields { deck, card }
    }

    /// Text of data field `i` ("" beyond the last).
    pub fn text(&self, i: usize) -> &'a str {
        self.card.fields.get(i).map(String::as_str).unwrap_or("")
    }

    /// Number of data fields up to the last non-blank one.
    pub fn len(&self) -> usize {
        self.card
            .fields
            .iter()
            .rposition(|f| !f.is_empty())
            .map_or(0, |i| i + 1)
    }

    /// Where field `i` is.
    pub fn at(&self, i: usize) -> Loc {
        Loc {
            file: self.card.at.file,
            line: self.card.lines.get(i).copied().unwrap_or(self.card.at.line),
        }
    }

    /// The card's name and its first field (the entity's id), e.g. `CHEXA 12`.
    pub fn entity(&self) -> String {
        let id = self.text(0);
        if id.is_empty() {
            self.card.name.clone()
        } else {
            format!("{} {}", self.card.name, shorten(id))
        }
    }

    /// An error about field `i` (`what`: its name in the card's description, e.g. `G3`).
    pub fn err(&self, i: usize, what: &str, message: impl std::fmt::Display) -> MeshError {
        let t = self.text(i);
        let value = if t.is_empty() {
            "blank".to_string()
        } else {
            format!("`{}`", shorten(t))
        };
        self.deck.err(
            self.at(i),
            format!("{}: {what} = {value}: {message}", self.entity()),
        )
    }

    /// An error about the whole card.
    pub fn card_err(&self, message: impl std::fmt::Display) -> MeshError {
        self.deck
            .err(self.card.at, format!("{}: {message}", self.entity()))
    }

    /// Integer field `i` (None when blank).
    pub fn int(&self, i: usize, what: &str) -> Result<Option<i64>, MeshError> {
        let t = self.text(i);
        if t.is_empty() {
            return Ok(None);
        }
        fields::int(t)
            .map(Some)
            .ok_or_else(|| self.err(i, what, "not an integer"))
    }

    /// Integer field `i` that must be ≥ 0 (blank: `default`).
    pub fn nonneg(&self, i: usize, what: &str, default: u64) -> Result<u64, MeshError> {
        match self.int(i, what)? {
            None => Ok(default),
            Some(v) if v >= 0 => Ok(v as u64),
            Some(_) => Err(self.err(i, what, "must be ≥ 0")),
        }
    }

    /// A required id (integer > 0).
    pub fn id(&self, i: usize, what: &str) -> Result<u64, MeshError> {
        match self.int(i, what)? {
            Some(v) if v > 0 => Ok(v as u64),
            Some(_) => Err(self.err(i, what, "must be a positive id")),
            None => Err(self.err(i, what, "is required")),
        }
    }

    /// An optional id (blank: None; else integer > 0).
    pub fn opt_id(&self, i: usize, what: &str) -> Result<Option<u64>, MeshError> {
        match self.int(i, what)? {
            Some(v) if v > 0 => Ok(Some(v as u64)),
            Some(_) => Err(self.err(i, what, "must be a positive id")),
            None => Ok(None),
        }
    }

    /// Real field `i` (None when blank).
    pub fn real(&self, i: usize, what: &str) -> Result<Option<f64>, MeshError> {
        let t = self.text(i);
        if t.is_empty() {
            return Ok(None);
        }
        fields::real(t)
            .map(Some)
            .ok_or_else(|| self.err(i, what, "not a finite real number"))
    }

    /// Real field `i`, blank = `default`.
    pub fn real_or(&self, i: usize, what: &str, default: f64) -> Result<f64, MeshError> {
        Ok(self.real(i, what)?.unwrap_or(default))
    }

    /// A component code (digits 1–6, each at most once; `0` or blank: none) as a sorted list.
    pub fn components(&self, i: usize, what: &str) -> Result<Vec<u8>, MeshError> {
        let t = self.text(i);
        if t.is_empty() || t == "0" {
            return Ok(Vec::new());
        }
        let mut out = Vec::new();
        for b in t.bytes() {
            if !(b'1'..=b'6').contains(&b) || out.contains(&(b - b'0')) {
                return Err(self.err(i, what, "not a component code (digits 1 to 6, each once)"));
            }
            out.push(b - b'0');
        }
        out.sort_unstable();
        Ok(out)
    }

    /// Ids from field `from` on, each `(first, last, field)`: a single id has first = last,
    /// `A THRU B` gives the range (kept as a range: its ids are looked up among those that
    /// exist, not listed one by one).
    pub fn id_ranges(&self, from: usize, what: &str) -> Result<Vec<(u64, u64, usize)>, MeshError> {
        let mut out = Vec::new();
        let mut i = from;
        let n = self.len();
        while i < n {
            if self.text(i).is_empty() {
                i += 1;
                continue;
            }
            let a = self.id(i, what)?;
            if self.text(i + 1).eq_ignore_ascii_case("THRU") {
                let b = self.id(i + 2, what)?;
                if b < a {
                    return Err(self.err(i + 2, what, format!("`{a} THRU {b}` is an empty range")));
                }
                out.push((a, b, i));
                i += 3;
            } else {
                out.push((a, a, i));
                i += 1;
            }
        }
        Ok(out)
    }
}
