//! Reading binary OP4 files: Fortran unformatted sequential records.
//!
//! Each record is framed by its byte length (a 4-byte marker, or 8-byte with some compilers)
//! before and after. Records, per matrix:
//! - header `NCOL NROW NF NTYPE NAME` — 4 integers and 8 characters (24 bytes), or in files
//!   written with 64-bit integers 4 × 8 bytes and 16 characters (48 bytes);
//! - per column `ICOL IROW NW` then `NW` words (a word is the integer size): dense
//!   (`IROW > 0`) values, or sparse (`IROW = 0`) strings with the headers of the text format;
//! - the end record `NCOL + 1, 1, NW` and one value.
//!
//! Values are `f32` for types 1 and 3 and `f64` for 2 and 4 — except in 64-bit-integer files,
//! where every value is an `f64`. The byte order comes from the first record marker, which must
//! be 24 or 48.

use super::build::{Builder, Header};
use crate::matrix::{NamedMatrix, Real};

/// Error of the binary reader: byte offset, matrix name, reason.
pub(crate) type BinError = (usize, String, String);

#[derive(Clone, Copy, Debug)]
pub(crate) struct Layout {
    pub big_endian: bool,
    pub marker: usize,
    pub int: usize,
}

/// Detects a binary OP4 from its first record; `None` if the bytes do not start like one.
pub(crate) fn detect(bytes: &[u8]) -> Option<Layout> {
    for marker in [4usize, 8] {
        for big_endian in [false, true] {
            let Some(len) = uint(bytes, 0, marker, big_endian) else {
                continue;
            };
            if len != 24 && len != 48 {
                continue;
            }
            let len = len as usize;
            if uint(bytes, marker + len, marker, big_endian) == Some(len as u64) {
                let int = if len == 24 { 4 } else { 8 };
                return Some(Layout {
                    big_endian,
                    marker,
                    int,
                });
            }
        }
    }
    None
}

fn uint(b: &[u8], at: usize, size: usize, big: bool) -> Option<u64> {
    let s = b.get(at..at.checked_add(size)?)?;
    let mut v: u64 = 0;
    for k in 0..size {
        let byte = if big { s[k] } else { s[size - 1 - k] };
        v = (v << 8) | byte as u64;
    }
    Some(v)
}

fn sint(b: &[u8], at: usize, size: usize, big: bool) -> Option<i64> {
    let u = uint(b, at, size, big)?;
    Some(if size == 4 {
        u as u32 as i32 as i64
    } else {
        u as i64
    })
}

/// A record payload with its byte offset, or an error at a byte offset.
type RecordResult<'a> = Result<Option<(usize, &'a [u8])>, (usize, String)>;

struct Records<'a> {
    bytes: &'a [u8],
    pos: usize,
    lay: Layout,
}

impl<'a> Records<'a> {
    /// Next record payload and its byte offset; `Ok(None)` at the end of the file.
    fn next(&mut self) -> RecordResult<'a> {
        let at = self.pos;
        if at == self.bytes.len() {
            return Ok(None);
        }
        let m = self.lay.marker;
        let len = uint(self.bytes, at, m, self.lay.big_endian)
            .ok_or((at, "truncated record marker".to_string()))? as usize;
        let end = at
            .checked_add(m)
            .and_then(|x| x.checked_add(len))
            .filter(|&e| e + m <= self.bytes.len())
            .ok_or((
                at,
                format!("record of {len} bytes runs past the end of the file"),
            ))?;
        let trail = uint(self.bytes, end, m, self.lay.big_endian).unwrap_or(u64::MAX);
        if trail != len as u64 {
            return Err((
                end,
                format!("record markers disagree: {len} before, {trail} after"),
            ));
        }
        self.pos = end + m;
        Ok(Some((at + m, &self.bytes[at + m..end])))
    }
}

/// Parses every matrix of a binary OP4 file.
pub(crate) fn read_binary(bytes: &[u8], lay: Layout) -> Result<Vec<NamedMatrix>, BinError> {
    let mut rec = Records { bytes, pos: 0, lay };
    let mut out = Vec::new();
    let (n, big) = (lay.int, lay.big_endian);
    while let Some((at, p)) = rec.next().map_err(|(o, e)| (o, String::new(), e))? {
        if p.len() != 6 * n {
            return Err((
                at,
                String::new(),
                format!("header record has {} bytes, expected {}", p.len(), 6 * n),
            ));
        }
        let i = |k: usize| sint(p, k * n, n, big).unwrap_or(0);
        let name: String = String::from_utf8_lossy(&p[4 * n..6 * n])
            .chars()
            .filter(|c| !c.is_whitespace() && *c != '\0')
            .collect();
        let header =
            Header::new(i(0), i(1), i(2), i(3), name.clone()).map_err(|e| (at, name.clone(), e))?;
        let m = read_matrix(&mut rec, header).map_err(|(o, e)| (o, name, e))?;
        out.push(m);
    }
    Ok(out)
}

fn read_matrix(rec: &mut Records, header: Header) -> Result<NamedMatrix, (usize, String)> {
    let (n, big) = (rec.lay.int, rec.lay.big_endian);
    // Bytes per value: f64 in 64-bit-integer files and for double types.
    let vbytes = if n == 8 || !header.precision.is_single() {
        8
    } else {
        4
    };
    let bigmat = header.bigmat;
    let ncols = header.ncols as i64;
    let mut b = Builder::new(header);
    loop {
        let (at, p) = rec
            .next()?
            .ok_or((rec.pos, "file ends inside the matrix".to_string()))?;
        if p.len() < 3 * n {
            return Err((at, format!("column record of {} bytes", p.len())));
        }
        let i = |k: usize| sint(p, k * n, n, big).unwrap_or(0);
        let (icol, irow, nw) = (i(0), i(1), i(2));
        if icol < 1
            || irow < 0
            || nw < 0
            || (nw as u64).saturating_mul(n as u64) > (p.len() - 3 * n) as u64
        {
            return Err((
                at,
                format!(
                    "bad column record ICOL {icol} IROW {irow} NW {nw} ({} bytes)",
                    p.len()
                ),
            ));
        }
        if icol > ncols {
            return Ok(b.finish());
        }
        let col = (icol - 1) as usize;
        let data = &p[3 * n..3 * n + nw as usize * n];
        if irow > 0 {
            let v = values(data, vbytes, big).map_err(|e| (at, e))?;
            b.put(col, (irow - 1) as usize, &v).map_err(|e| (at, e))?;
            continue;
        }
        let mut pos = 0;
        while pos < data.len() {
            let head = if bigmat { 2 } else { 1 };
            if pos + head * n > data.len() {
                return Err((at, "string header past the end of the record".to_string()));
            }
            let w = |k: usize| sint(data, pos + k * n, n, big).unwrap_or(0);
            let (l, row) = if bigmat {
                (w(0) - 1, w(1))
            } else {
                let is = w(0);
                let l = (is >> 16) - 1;
                (l, is - ((l + 1) << 16))
            };
            pos += head * n;
            let nbytes = (l.max(0) as u64).saturating_mul(n as u64);
            if l < 0 || row < 1 || nbytes > (data.len() - pos) as u64 || nbytes % vbytes as u64 != 0
            {
                return Err((at, format!("bad string header: L = {l}, IROW = {row}")));
            }
            let v = values(&data[pos..pos + nbytes as usize], vbytes, big).map_err(|e| (at, e))?;
            b.put(col, (row - 1) as usize, &v).map_err(|e| (at, e))?;
            pos += nbytes as usize;
        }
    }
}

fn values(data: &[u8], vbytes: usize, big: bool) -> Result<Vec<Real>, String> {
    if data.len() % vbytes != 0 {
        return Err(format!(
            "{} data bytes are not whole {vbytes}-byte values",
            data.len()
        ));
    }
    let mut v = Vec::with_capacity(data.len() / vbytes);
    for k in 0..data.len() / vbytes {
        let u = uint(data, k * vbytes, vbytes, big).unwrap_or(0);
        let x = if vbytes == 4 {
            f32::from_bits(u as u32) as Real
        } else {
            f64::from_bits(u)
        };
        if !x.is_finite() {
            return Err(format!(
                "non-finite value {x} (value {} of the string)",
                k + 1
            ));
        }
        v.push(x);
    }
    Ok(v)
}
