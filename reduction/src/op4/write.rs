//! Writing OP4 files, ASCII or binary, dense or sparse (non-BIGMAT / BIGMAT strings).
//!
//! The layouts are those the readers document (`text_read.rs`, `binary_read.rs`); binary files
//! use 4-byte record markers and 4-byte integers, as NASTRAN does on 32-bit-integer builds.

use std::fmt::Write as _;

use super::build::{column_runs, Run};
use super::{Op4WriteOptions, Sparsity, WritePrecision};
use crate::matrix::{check_name, NamedMatrix, Precision, Real};
use crate::ReductionError;

/// Longest non-BIGMAT string, in words: `IS = IROW + 65536 (L + 1)` must fit an `i32`.
const MAX_STRING_WORDS: usize = 32766;

/// What the header says and how values are stored, for one matrix.
struct Plan {
    precision: Precision,
    bigmat: bool,
    dense: bool,
    /// Numbers per entry (1 real, 2 complex).
    per: usize,
    /// Words per number (1 single, 2 double).
    wpn: usize,
}

fn plan(a: &NamedMatrix, opts: &Op4WriteOptions) -> Result<Plan, ReductionError> {
    let unwritable = |detail: String| ReductionError::Unwritable {
        matrix: a.name.clone(),
        detail,
    };
    check_name(&a.name).map_err(unwritable)?;
    let shape_ok = match &a.data {
        crate::matrix::MatrixData::Real(m) => m.nrows() == a.nrows && m.ncols() == a.ncols,
        crate::matrix::MatrixData::Complex(m) => m.nrows() == a.nrows && m.ncols() == a.ncols,
    };
    if !shape_ok || a.nrows > i32::MAX as usize / 2 || a.ncols >= i32::MAX as usize {
        return Err(unwritable(format!(
            "inconsistent or too large shape {} x {}",
            a.nrows, a.ncols
        )));
    }
    let precision = match opts.precision {
        WritePrecision::AsMatrix => a.precision,
        WritePrecision::Single => Precision::RealSingle,
        WritePrecision::Double => Precision::RealDouble,
    }
    .with_complex(a.is_complex());
    // NASTRAN switches to BIGMAT strings above 65535 rows.
    let bigmat =
        opts.sparse == Sparsity::Bigmat || (opts.sparse == Sparsity::NonBigmat && a.nrows >= 65536);
    Ok(Plan {
        precision,
        bigmat,
        dense: opts.sparse == Sparsity::Dense,
        per: if precision.is_complex() { 2 } else { 1 },
        wpn: if precision.is_single() { 1 } else { 2 },
    })
}

fn runs(a: &NamedMatrix, j: usize, p: &Plan) -> Vec<Run> {
    let max_entries = if p.bigmat {
        usize::MAX
    } else {
        MAX_STRING_WORDS / (p.per * p.wpn)
    };
    column_runs(a, j, p.dense, p.per == 2, max_entries)
}

fn nrows_field(a: &NamedMatrix, p: &Plan) -> i64 {
    if p.bigmat {
        -(a.nrows as i64)
    } else {
        a.nrows as i64
    }
}

/// Words of a sparse column record: string headers plus values.
fn sparse_words(runs: &[Run], p: &Plan) -> usize {
    let head = if p.bigmat { 2 } else { 1 };
    runs.iter().map(|r| head + r.numbers.len() * p.wpn).sum()
}

fn string_header(r: &Run, p: &Plan) -> (i64, i64) {
    let l = (r.numbers.len() * p.wpn) as i64;
    (l + 1, r.row as i64 + 1)
}

/// Fortran `1P,Ew.d`: one digit before the point, `d` after, exponent `E±dd` (or `±ddd`).
pub(crate) fn fortran_e(v: Real, width: usize, decimals: usize) -> String {
    let s = format!("{:.*e}", decimals, v);
    let (mant, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let e: i32 = exp.parse().unwrap_or(0);
    let sign = if e < 0 { '-' } else { '+' };
    let exp = if e.abs() < 100 {
        format!("E{sign}{:02}", e.abs())
    } else {
        format!("{sign}{:03}", e.abs())
    };
    format!("{:>width$}", format!("{mant}{exp}"))
}

/// ASCII OP4 text of the matrices.
pub(crate) fn write_text(
    mats: &[&NamedMatrix],
    opts: &Op4WriteOptions,
) -> Result<String, ReductionError> {
    let mut s = String::new();
    for a in mats {
        let p = plan(a, opts)?;
        // 17 significant digits for both precisions (as NASTRAN writes single-precision
        // ASCII files too): the f32 or f64 value is recovered exactly.
        let (per_line, width, decimals, spec) = (3, 23, 16, "1P,3E23.16");
        let round = |x: Real| {
            if p.precision.is_single() {
                x as f32 as Real
            } else {
                x
            }
        };
        let put = |s: &mut String, numbers: &[Real]| {
            for chunk in numbers.chunks(per_line) {
                for &x in chunk {
                    s.push_str(&fortran_e(round(x), width, decimals));
                }
                s.push('\n');
            }
        };
        let name = a.name.to_ascii_uppercase();
        let _ = writeln!(
            s,
            "{:8}{:8}{:8}{:8}{:<8}{spec}",
            a.ncols,
            nrows_field(a, &p),
            a.form.code(),
            p.precision.code(),
            name
        );
        for j in 0..a.ncols {
            let rs = runs(a, j, &p);
            if rs.is_empty() {
                continue;
            }
            if p.dense {
                let r = &rs[0];
                let _ = writeln!(s, "{:8}{:8}{:8}", j + 1, r.row + 1, r.numbers.len());
                put(&mut s, &r.numbers);
                continue;
            }
            let _ = writeln!(s, "{:8}{:8}{:8}", j + 1, 0, sparse_words(&rs, &p));
            for r in &rs {
                let (l1, row) = string_header(r, &p);
                if p.bigmat {
                    let _ = writeln!(s, "{l1:8}{row:8}");
                } else {
                    let _ = writeln!(s, "{:8}", row + 65536 * l1);
                }
                put(&mut s, &r.numbers);
            }
        }
        let _ = writeln!(s, "{:8}{:8}{:8}", a.ncols + 1, 1, 1);
        put(&mut s, &[1.0]);
    }
    Ok(s)
}

/// Binary OP4 bytes of the matrices.
pub(crate) fn write_binary(
    mats: &[&NamedMatrix],
    opts: &Op4WriteOptions,
) -> Result<Vec<u8>, ReductionError> {
    let big = opts.big_endian;
    let i32b = |v: i64| -> [u8; 4] {
        let v = v as i32;
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let mut out = Vec::new();
    let record = |out: &mut Vec<u8>, payload: &[u8]| {
        out.extend_from_slice(&i32b(payload.len() as i64));
        out.extend_from_slice(payload);
        out.extend_from_slice(&i32b(payload.len() as i64));
    };
    for a in mats {
        let p = plan(a, opts)?;
        let push_values = |buf: &mut Vec<u8>, numbers: &[Real]| {
            for &x in numbers {
                if p.precision.is_single() {
                    let f = x as f32;
                    buf.extend_from_slice(&if big {
                        f.to_be_bytes()
                    } else {
                        f.to_le_bytes()
                    });
                } else {
                    buf.extend_from_slice(&if big {
                        x.to_be_bytes()
                    } else {
                        x.to_le_bytes()
                    });
                }
            }
        };
        let mut head = Vec::with_capacity(24);
        for v in [
            a.ncols as i64,
            nrows_field(a, &p),
            a.form.code() as i64,
            p.precision.code() as i64,
        ] {
            head.extend_from_slice(&i32b(v));
        }
        head.extend_from_slice(format!("{:<8}", a.name.to_ascii_uppercase()).as_bytes());
        record(&mut out, &head);
        for j in 0..a.ncols {
            let rs = runs(a, j, &p);
            if rs.is_empty() {
                continue;
            }
            let mut buf = Vec::new();
            if p.dense {
                let r = &rs[0];
                for v in [
                    j as i64 + 1,
                    r.row as i64 + 1,
                    (r.numbers.len() * p.wpn) as i64,
                ] {
                    buf.extend_from_slice(&i32b(v));
                }
                push_values(&mut buf, &r.numbers);
            } else {
                for v in [j as i64 + 1, 0, sparse_words(&rs, &p) as i64] {
                    buf.extend_from_slice(&i32b(v));
                }
                for r in &rs {
                    let (l1, row) = string_header(r, &p);
                    if p.bigmat {
                        buf.extend_from_slice(&i32b(l1));
                        buf.extend_from_slice(&i32b(row));
                    } else {
                        buf.extend_from_slice(&i32b(row + 65536 * l1));
                    }
                    push_values(&mut buf, &r.numbers);
                }
            }
            record(&mut out, &buf);
        }
        let mut buf = Vec::new();
        for v in [a.ncols as i64 + 1, 1, p.wpn as i64] {
            buf.extend_from_slice(&i32b(v));
        }
        push_values(&mut buf, &[1.0]);
        record(&mut out, &buf);
    }
    Ok(out)
}
