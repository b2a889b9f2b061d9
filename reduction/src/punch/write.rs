//! Writing DMIG matrices as punch text: the header card in small field, column cards in small
//! (8-character) or large (`DMIG*`, 16-character) field. Values take the shortest NASTRAN real
//! that round-trips, else as many digits as the field holds (8: ~5, 16: ~11 significant).

use std::fmt::Write as _;

use super::number::format_real;
use super::{DmigMatrix, PunchWriteOptions};
use crate::matrix::{check_name, Cplx, MatrixForm};
use crate::ReductionError;

pub(crate) fn write_text(
    mats: &[&DmigMatrix],
    opts: &PunchWriteOptions,
) -> Result<String, ReductionError> {
    let mut s = String::new();
    for d in mats {
        write_one(&mut s, d, opts)?;
    }
    Ok(s)
}

fn write_one(
    s: &mut String,
    d: &DmigMatrix,
    opts: &PunchWriteOptions,
) -> Result<(), ReductionError> {
    let a = &d.matrix;
    let bad = |detail: String| ReductionError::Unwritable {
        matrix: a.name.clone(),
        detail,
    };
    check_name(&a.name).map_err(bad)?;
    if d.rows.len() != a.nrows || d.cols.len() != a.ncols {
        return Err(bad(format!(
            "{} row and {} column DOFs for a {} x {} matrix",
            d.rows.len(),
            d.cols.len(),
            a.nrows,
            a.ncols
        )));
    }
    let ifo = match a.form {
        MatrixForm::Symmetric | MatrixForm::Square if d.rows != d.cols => {
            return Err(bad(
                "a square or symmetric DMIG needs identical row and column DOFs".into(),
            ))
        }
        MatrixForm::Symmetric => {
            if let Some((i, j)) = first_asymmetry(d) {
                return Err(bad(format!(
                    "form symmetric but entry ({}, {}) differs from ({}, {})",
                    i + 1,
                    j + 1,
                    j + 1,
                    i + 1
                )));
            }
            6
        }
        MatrixForm::Square => 1,
        MatrixForm::Rectangular => 2,
        MatrixForm::PseudoIdentity => 9,
        f => {
            return Err(bad(format!(
                "form {} cannot be written as DMIG (IFO 1, 2, 6 or 9)",
                f.code()
            )))
        }
    };
    let width = if opts.large_field { 16 } else { 8 };
    let max_id = if opts.large_field {
        9_999_999_999_999_999u64
    } else {
        99_999_999
    };
    for &(g, c) in d.rows.iter().chain(&d.cols) {
        if g == 0 || g > max_id || c > 6 {
            return Err(bad(format!(
                "DOF ({g}, {c}) is not a grid id 1..={max_id} with component 0..6"
            )));
        }
    }
    let complex = a.is_complex();
    let exp = if a.precision.is_single() { 'E' } else { 'D' };
    let num = |v: f64| {
        format_real(v, width, exp).ok_or_else(|| bad(format!("value {v} cannot be written")))
    };
    let name = a.name.to_ascii_uppercase();
    let _ = writeln!(
        s,
        "{:<8}{:<8}{:>8}{:>8}{:>8}{:>8}{:>8}{:8}{:>8}",
        "DMIG",
        name,
        0,
        ifo,
        a.precision.code(),
        0,
        0,
        "",
        a.ncols
    );
    for j in 0..a.ncols {
        let rows: Vec<usize> = (if ifo == 6 { j } else { 0 }..a.nrows)
            .filter(|&i| a.get(i, j) != Cplx::new(0.0, 0.0))
            .collect();
        if rows.is_empty() {
            continue;
        }
        // Fields 2..: NAME GJ CJ blank, then (GI, CI, A, B) groups.
        let mut fields = vec![
            name.clone(),
            d.cols[j].0.to_string(),
            d.cols[j].1.to_string(),
            String::new(),
        ];
        for i in rows {
            let z = a.get(i, j);
            fields.push(d.rows[i].0.to_string());
            fields.push(d.rows[i].1.to_string());
            fields.push(num(z.re)?);
            fields.push(if complex { num(z.im)? } else { String::new() });
        }
        let per_line = if opts.large_field { 4 } else { 8 };
        for (k, chunk) in fields.chunks(per_line).enumerate() {
            let first = match (k, opts.large_field) {
                (0, true) => "DMIG*",
                (0, false) => "DMIG",
                (_, true) => "*",
                (_, false) => "+",
            };
            let mut line = format!("{first:<8}");
            for (f, v) in chunk.iter().enumerate() {
                if k == 0 && f == 0 {
                    let _ = write!(line, "{v:<width$}");
                } else {
                    let _ = write!(line, "{v:>width$}");
                }
            }
            let _ = writeln!(s, "{}", line.trim_end());
        }
    }
    Ok(())
}

fn first_asymmetry(d: &DmigMatrix) -> Option<(usize, usize)> {
    let a = &d.matrix;
    (0..a.ncols)
        .flat_map(|j| (j + 1..a.nrows).map(move |i| (i, j)))
        .find(|&(i, j)| a.get(i, j) != a.get(j, i))
}
