//! Line and field reading over the raw bytes of a `.msh` file, with line numbers for errors.
//!
//! The file is kept as bytes because 4.1 binary files interleave text lines and binary blocks.

use crate::MeshError;
use std::str::SplitAsciiWhitespace;

/// A cursor over the file's bytes that hands out text lines and tracks the line number.
pub(crate) struct Lines<'a> {
    pub bytes: &'a [u8],
    /// Byte offset of the next unread byte.
    pub pos: usize,
    /// 1-based number of the last line returned (0 before the first).
    pub line: usize,
    pub file: &'a str,
}

impl<'a> Lines<'a> {
    pub fn new(bytes: &'a [u8], file: &'a str) -> Self {
        Lines {
            bytes,
            pos: 0,
            line: 0,
            file,
        }
    }

    /// Next raw line without its line terminator, or None at the end of the file.
    fn next_raw(&mut self) -> Option<&'a [u8]> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let (line, used) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        self.pos += used;
        self.line += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some(line)
    }

    /// Next line as text (None at end of file); invalid UTF-8 is an error.
    pub fn next_line(&mut self) -> Result<Option<&'a str>, MeshError> {
        match self.next_raw() {
            None => Ok(None),
            Some(raw) => std::str::from_utf8(raw)
                .map(Some)
                .map_err(|_| self.err("not a text line (invalid UTF-8)")),
        }
    }

    /// Next non-blank line, or None at the end of the file.
    pub fn next_nonblank(&mut self) -> Result<Option<&'a str>, MeshError> {
        while let Some(l) = self.next_line()? {
            if !l.trim().is_empty() {
                return Ok(Some(l));
            }
        }
        Ok(None)
    }

    /// Next non-blank line of section `section`; the end of the file is an error.
    pub fn expect_line(&mut self, section: &str) -> Result<&'a str, MeshError> {
        self.next_nonblank()?.ok_or_else(|| {
            self.err(format!(
                "file ends inside section ${section} (truncated file?)"
            ))
        })
    }

    /// Next non-blank line of `section` that must be an entry, not a `$` line.
    pub fn entry_line(&mut self, section: &str) -> Result<&'a str, MeshError> {
        let l = self.expect_line(section)?;
        if l.trim_start().starts_with('$') {
            return Err(self.err(format!(
                "found `{}` inside ${section}: the section has fewer entries than its counts say",
                shorten(l)
            )));
        }
        Ok(l)
    }

    /// Fields of the next entry line of `section`.
    pub fn fields(&mut self, section: &str) -> Result<Fields<'a>, MeshError> {
        let l = self.entry_line(section)?;
        Ok(Fields {
            it: l.split_ascii_whitespace(),
            line: self.line,
            file: self.file,
        })
    }

    /// Fields of a line already taken with [`Lines::expect_line`].
    pub fn fields_of(&self, l: &'a str, line: usize) -> Fields<'a> {
        Fields {
            it: l.split_ascii_whitespace(),
            line,
            file: self.file,
        }
    }

    /// Reads the `$End<section>` line (blank lines before it are skipped).
    pub fn expect_end(&mut self, section: &str) -> Result<(), MeshError> {
        let l = self.expect_line(section)?;
        if l.trim() != format!("$End{section}") {
            return Err(self.err(format!(
                "expected `$End{section}`, found `{}` (more entries than the section's count?)",
                shorten(l)
            )));
        }
        Ok(())
    }

    /// Skips an unknown section up to and including its `$End<section>` line.
    pub fn skip_section(&mut self, section: &str) -> Result<(), MeshError> {
        let start = self.line;
        let end = format!("$End{section}");
        while let Some(raw) = self.next_raw() {
            if raw.strip_suffix(b"\r").unwrap_or(raw).trim_ascii() == end.as_bytes() {
                return Ok(());
            }
        }
        Err(MeshError::parse(
            self.file,
            start,
            format!("section ${section} has no `{end}` (truncated file?)"),
        ))
    }

    /// Moves the cursor to `pos` (after a binary block), counting the newlines skipped.
    pub fn advance_to(&mut self, pos: usize) {
        let pos = pos.min(self.bytes.len());
        self.line += self.bytes[self.pos..pos]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.pos = pos;
    }

    /// An error at the current line.
    pub fn err(&self, message: impl Into<String>) -> MeshError {
        MeshError::parse(self.file, self.line, message)
    }
}

/// Whitespace-separated fields of one line, parsed with errors naming the field and the line.
pub(crate) struct Fields<'a> {
    it: SplitAsciiWhitespace<'a>,
    pub line: usize,
    pub file: &'a str,
}

impl<'a> Fields<'a> {
    fn next_tok(&mut self, what: &str) -> Result<&'a str, MeshError> {
        self.it
            .next()
            .ok_or_else(|| MeshError::parse(self.file, self.line, format!("missing {what}")))
    }

    fn bad(&self, what: &str, tok: &str, expected: &str) -> MeshError {
        MeshError::parse(
            self.file,
            self.line,
            format!("bad {what} `{}` (expected {expected})", shorten(tok)),
        )
    }

    /// A non-negative integer (counts, tags).
    pub fn u64(&mut self, what: &str) -> Result<u64, MeshError> {
        let t = self.next_tok(what)?;
        t.parse::<u64>()
            .map_err(|_| self.bad(what, t, "a non-negative integer"))
    }

    /// A count, as usize.
    pub fn count(&mut self, what: &str) -> Result<usize, MeshError> {
        let t = self.next_tok(what)?;
        t.parse::<usize>()
            .map_err(|_| self.bad(what, t, "a non-negative integer"))
    }

    /// A signed integer (entity and physical tags, which may be negative for orientation).
    pub fn i64(&mut self, what: &str) -> Result<i64, MeshError> {
        let t = self.next_tok(what)?;
        t.parse::<i64>()
            .map_err(|_| self.bad(what, t, "an integer"))
    }

    /// A finite real number.
    pub fn f64(&mut self, what: &str) -> Result<f64, MeshError> {
        let t = self.next_tok(what)?;
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.bad(what, t, "a finite real number")),
        }
    }

    /// The remaining text of the line (not consumed field by field).
    pub fn rest(self) -> SplitAsciiWhitespace<'a> {
        self.it
    }
}

/// A line cut to 60 characters for error messages.
pub(crate) fn shorten(s: &str) -> String {
    let s = s.trim();
    match s.char_indices().nth(60) {
        Some((i, _)) => format!("{}...", &s[..i]),
        None => s.to_string(),
    }
}

/// Capacity to reserve for `count` items of at least `min_bytes` each in the `remaining` bytes:
/// a garbled count must not allocate more than the file could hold.
pub(crate) fn capped(count: usize, min_bytes: usize, remaining: usize) -> usize {
    count.min(remaining / min_bytes.max(1) + 1)
}
