//! Reading ASCII (formatted) OP4 files.
//!
//! Layout, per matrix (as NASTRAN `OUTPUT4` writes it and pyyeti/pyNastran read it):
//! - header `NCOL NROW NF NTYPE` (4I8), `NAME` (A8), the value format (e.g. `1P,3E23.16`);
//! - per column record `ICOL IROW NW` (3I8):
//!   - `IROW > 0` (dense): `NW` numbers follow, from row `IROW` down;
//!   - `IROW = 0` (sparse): `NW` words of strings follow, each a header then its numbers:
//!     non-BIGMAT `IS = IROW + 65536 (L + 1)`, BIGMAT `L + 1, IROW`; `L` counts words (two
//!     per number in double precision types 2 and 4, one in types 1 and 3);
//! - the end record `NCOL + 1, 1, NW` and one number on one line.
//!
//! Numbers are fixed-width fields (the header's `Ew.d`), possibly with `D` exponents or
//! Fortran's `1.0+100` form for three-digit exponents.

use super::build::{Builder, Header};
use crate::matrix::{NamedMatrix, Real};
use crate::punch::number::parse_real;

/// Error of the text reader: line (1-based), matrix name, reason.
pub(crate) type TextError = (usize, String, String);

struct Lines<'a> {
    lines: Vec<&'a str>,
    next: usize,
}

impl<'a> Lines<'a> {
    /// Next line and its 1-based number.
    fn next_line(&mut self) -> Option<(usize, &'a str)> {
        let l = *self.lines.get(self.next)?;
        self.next += 1;
        Some((self.next, l.trim_end_matches(['\r', '\n'])))
    }

    /// The next line, not consumed.
    fn peek(&self) -> Option<&'a str> {
        self.lines.get(self.next).copied()
    }
}

/// Parses every matrix of an ASCII OP4 text.
pub(crate) fn read_text(text: &str) -> Result<Vec<NamedMatrix>, TextError> {
    let mut lines = Lines {
        lines: text.lines().collect(),
        next: 0,
    };
    let mut out = Vec::new();
    while let Some((ln, line)) = lines.next_line() {
        if line.trim().is_empty() {
            continue;
        }
        let (header, fmt) =
            parse_header(line).map_err(|e| (ln, field(line, 32, 40).trim().to_string(), e))?;
        let name = header.name.clone();
        let m = read_matrix(&mut lines, header, fmt).map_err(|(l, e)| (l, name, e))?;
        out.push(m);
    }
    Ok(out)
}

/// Fixed-width field `[a, b)` of a line (clipped to its length).
fn field(line: &str, a: usize, b: usize) -> &str {
    let b = b.min(line.len());
    if a >= b || !line.is_char_boundary(a) || !line.is_char_boundary(b) {
        return "";
    }
    &line[a..b]
}

fn int(s: &str, what: &str) -> Result<i64, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("{what} `{}` is not an integer", s.trim()))
}

/// Numbers per line and field width from a format such as `1P,5E16.9` or `3D23.16`.
#[derive(Clone, Copy)]
struct NumFormat {
    per_line: usize,
    width: usize,
}

fn parse_header(line: &str) -> Result<(Header, NumFormat), String> {
    let ncols = int(field(line, 0, 8), "NCOL")?;
    let nrows = int(field(line, 8, 16), "NROW")?;
    let form = int(field(line, 16, 24), "NF")?;
    let ntype = int(field(line, 24, 32), "NTYPE")?;
    let name = field(line, 32, 40).trim().to_string();
    let mut fmt = NumFormat {
        per_line: 5,
        width: 16,
    };
    let spec = field(line, 40, line.len()).trim().to_ascii_uppercase();
    let spec = spec.strip_prefix("1P,").unwrap_or(&spec);
    if let Some(p) = spec.find(['E', 'D']) {
        let per: Option<usize> = spec[..p].trim().parse().ok();
        let width: Option<usize> = spec[p + 1..].split('.').next().and_then(|w| w.parse().ok());
        match (per, width) {
            (Some(n), Some(w)) if (1..=100).contains(&n) && (2..=60).contains(&w) => {
                fmt = NumFormat {
                    per_line: n,
                    width: w,
                }
            }
            _ => return Err(format!("value format `{spec}` is not like `1P,3E23.16`")),
        }
    }
    Ok((Header::new(ncols, nrows, form, ntype, name)?, fmt))
}

/// Three integers of a column record: fixed 8-character fields, else blank-separated.
fn record3(line: &str) -> Result<(i64, i64, i64), String> {
    let fixed = (
        int(field(line, 0, 8), ""),
        int(field(line, 8, 16), ""),
        int(field(line, 16, 24), ""),
    );
    if let (Ok(a), Ok(b), Ok(c)) = fixed {
        if line.trim_end().len() <= 24 {
            return Ok((a, b, c));
        }
    }
    let v: Vec<&str> = line.split_whitespace().collect();
    if v.len() != 3 {
        return Err(format!(
            "expected a column record `ICOL IROW NW`, found `{line}`"
        ));
    }
    Ok((int(v[0], "ICOL")?, int(v[1], "IROW")?, int(v[2], "NW")?))
}

type LineResult<T> = Result<T, (usize, String)>;

fn read_matrix(lines: &mut Lines, header: Header, fmt: NumFormat) -> LineResult<NamedMatrix> {
    let words_per_number: i64 = if header.precision.is_single() { 1 } else { 2 };
    let bigmat = header.bigmat;
    let ncols = header.ncols as i64;
    let mut b = Builder::new(header);
    loop {
        let (ln, line) = lines
            .next_line()
            .ok_or((lines.next, "file ends inside the matrix".to_string()))?;
        let (icol, irow, nw) = record3(line).map_err(|e| (ln, e))?;
        if icol < 1 || irow < 0 || nw < 0 {
            return Err((ln, format!("bad column record {icol} {irow} {nw}")));
        }
        if icol > ncols {
            // End record: one number follows (its NW is 1, or 2 words for double precision
            // with some writers); skip its line, as NASTRAN readers do.
            if nw > 0 {
                lines.next_line();
            }
            return Ok(b.finish());
        }
        let col = (icol - 1) as usize;
        if irow > 0 {
            let v = read_numbers(lines, nw as usize, fmt)?;
            b.put(col, (irow - 1) as usize, &v).map_err(|e| (ln, e))?;
            continue;
        }
        // A column of strings: as the format says (each header's L counts its own words), else
        // as pyNastran writes it (see `pynastran_column`); the first reader's error is reported.
        let start = lines.next;
        let strings = match sparse_column(lines, bigmat, words_per_number, nw, fmt) {
            Ok(v) => v,
            Err(first) => {
                lines.next = start;
                if bigmat {
                    return Err(first);
                }
                pynastran_column(lines, b.is_complex(), nw, fmt).map_err(|_| first)?
            }
        };
        for (row, v) in strings {
            b.put(col, row, &v).map_err(|e| (ln, e))?;
        }
    }
}

/// The strings of one sparse column (after its record `ICOL 0 NW`), by the format: each string
/// header's L counts the words of its own numbers, and the column's NW words are all read.
/// Returns (first row, numbers) per string.
fn sparse_column(
    lines: &mut Lines,
    bigmat: bool,
    words_per_number: i64,
    nw: i64,
    fmt: NumFormat,
) -> LineResult<Vec<(usize, Vec<Real>)>> {
    let mut out = Vec::new();
    let mut left = nw;
    while left > 0 {
        let (ln, line) = lines
            .next_line()
            .ok_or((lines.next, "file ends inside a column".to_string()))?;
        let ints: Vec<&str> = line.split_whitespace().collect();
        let (l, row, head) = match (bigmat, ints.as_slice()) {
            (true, [l1, r]) => (
                int(l1, "L+1").map_err(|e| (ln, e))? - 1,
                int(r, "IROW").map_err(|e| (ln, e))?,
                2,
            ),
            (false, [is]) => {
                let is = int(is, "IS").map_err(|e| (ln, e))?;
                let l = (is >> 16) - 1;
                (l, is - ((l + 1) << 16), 1)
            }
            _ => return Err((ln, format!("expected a string header, found `{line}`"))),
        };
        if l < 0 || row < 1 || l % words_per_number != 0 || l + head > left {
            return Err((
                ln,
                format!("bad string header: L = {l}, IROW = {row}, {left} words left"),
            ));
        }
        let v = read_numbers(lines, (l / words_per_number) as usize, fmt)?;
        out.push(((row - 1) as usize, v));
        left -= l + head;
    }
    Ok(out)
}

/// Whether a line holds only integers (a column record or a string header).
fn integers(line: &str) -> Option<Vec<i64>> {
    let v: Option<Vec<i64>> = line.split_whitespace().map(|t| t.parse().ok()).collect();
    v.filter(|v| !v.is_empty())
}

/// The strings of one sparse column as pyNastran (1.4) writes ASCII sparse OP4: every non-BIGMAT
/// string header `IS = IROW + 65536 (L + 1)` carries the column's word count (`L + 1` = the
/// column record's NW) rather than its string's, and NW = 2 × (numbers in the column) + 1
/// whatever the precision. A string's numbers are the number lines up to the next integer line,
/// as pyNastran reads them. Accepted only when the file is consistent with that writer: every
/// header's L + 1 = NW and NW = 2 × numbers + 1; the column ends at the next column record.
fn pynastran_column(
    lines: &mut Lines,
    complex: bool,
    nw: i64,
    fmt: NumFormat,
) -> LineResult<Vec<(usize, Vec<Real>)>> {
    let mut out = Vec::new();
    let mut count: i64 = 0;
    while let Some(next) = lines.peek() {
        let Some(ints) = integers(next) else {
            break;
        };
        if ints.len() == 3 {
            break;
        }
        let (ln, _) = lines.next_line().ok_or((lines.next, String::new()))?;
        let [is] = ints[..] else {
            return Err((ln, format!("expected a string header, found `{next}`")));
        };
        let l = (is >> 16) - 1;
        let row = is - ((l + 1) << 16);
        if l + 1 != nw || row < 1 {
            return Err((
                ln,
                format!("string header L = {l}, IROW = {row} with NW = {nw}"),
            ));
        }
        let mut v = Vec::new();
        while lines.peek().is_some_and(|l| integers(l).is_none()) {
            let (ln, line) = lines.next_line().ok_or((lines.next, String::new()))?;
            for i in 0..fmt.per_line {
                let f = field(line, i * fmt.width, (i + 1) * fmt.width);
                if f.trim().is_empty() {
                    break;
                }
                let x =
                    parse_real(f).ok_or_else(|| (ln, format!("`{}` is not a number", f.trim())))?;
                v.push(x);
            }
            if v.len() as i64 > l {
                return Err((ln, format!("more than L = {l} numbers in a string")));
            }
        }
        if v.is_empty() || (complex && v.len() % 2 != 0) {
            return Err((ln, format!("a string of {} numbers", v.len())));
        }
        count += v.len() as i64;
        out.push(((row - 1) as usize, v));
    }
    if out.is_empty() || nw != 2 * count + 1 {
        return Err((lines.next, format!("NW = {nw} for {count} numbers")));
    }
    Ok(out)
}

/// Reads `n` fixed-width numbers, `fmt.per_line` to a line.
fn read_numbers(lines: &mut Lines, n: usize, fmt: NumFormat) -> LineResult<Vec<Real>> {
    let mut v = Vec::with_capacity(n.min(1 << 16));
    while v.len() < n {
        let (ln, line) = lines.next_line().ok_or((
            lines.next,
            format!("file ends with {} of {n} numbers read", v.len()),
        ))?;
        let k = fmt.per_line.min(n - v.len());
        for i in 0..k {
            let f = field(line, i * fmt.width, (i + 1) * fmt.width);
            let x = parse_real(f).ok_or_else(|| {
                (
                    ln,
                    format!(
                        "`{}` is not a number (field {} of the line)",
                        f.trim(),
                        i + 1
                    ),
                )
            })?;
            v.push(x);
        }
    }
    Ok(v)
}
