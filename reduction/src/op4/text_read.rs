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
            b.put(col, (row - 1) as usize, &v).map_err(|e| (ln, e))?;
            left -= l + head;
        }
    }
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
