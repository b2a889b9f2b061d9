//! `squeal inspect`: a one-line summary of every matrix in an OP4 or punch (DMIG) file.

use std::fmt;
use std::path::Path;

use serde::Serialize;

use crate::matrix::{MatrixForm, NamedMatrix, Precision, Real};
use crate::{op4, punch, ReductionError};

/// Relative tolerance of the symmetry test: `max |A − Aᵀ| ≤ 1e-12 · max |A|`.
pub const SYMMETRY_RTOL: Real = 1e-12;

/// Summary of one matrix.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MatrixSummary {
    /// File format: `op4` or `dmig`.
    pub format: &'static str,
    /// Matrix name.
    pub name: String,
    /// Rows.
    pub nrows: usize,
    /// Columns.
    pub ncols: usize,
    /// Form stored in the file.
    pub form: MatrixForm,
    /// Type stored in the file.
    pub precision: Precision,
    /// Number of nonzero entries.
    pub nnz: usize,
    /// Frobenius norm.
    pub frobenius: Real,
    /// Sum of all entries (real part).
    pub sum: Real,
    /// Sum of all entries (imaginary part; 0 for real matrices).
    pub sum_imag: Real,
    /// Square and symmetric to [`SYMMETRY_RTOL`].
    pub symmetric: bool,
}

impl MatrixSummary {
    /// Summary of a matrix read from a file of the given format.
    pub fn of(m: &NamedMatrix, format: &'static str) -> Self {
        let (mut fro2, mut sum) = (0.0, num_complex::Complex::new(0.0, 0.0));
        for j in 0..m.ncols {
            for i in 0..m.nrows {
                let z = m.get(i, j);
                fro2 += z.norm_sqr();
                sum += z;
            }
        }
        Self {
            format,
            name: m.name.clone(),
            nrows: m.nrows,
            ncols: m.ncols,
            form: m.form,
            precision: m.precision,
            nnz: m.nnz(),
            frobenius: fro2.sqrt(),
            sum: sum.re,
            sum_imag: sum.im,
            symmetric: m.is_symmetric(SYMMETRY_RTOL),
        }
    }
}

/// Summaries of every matrix of an OP4 (binary or ASCII) or punch (DMIG) file. The format is
/// taken from the contents: binary OP4 records, else DMIG cards, else ASCII OP4.
pub fn inspect(path: impl AsRef<Path>) -> Result<Vec<MatrixSummary>, ReductionError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| ReductionError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let has_dmig = std::str::from_utf8(&bytes)
        .map(|t| {
            t.lines()
                .any(|l| l.trim_start().to_ascii_uppercase().starts_with("DMIG"))
        })
        .unwrap_or(false);
    if !op4::is_binary(&bytes) && has_dmig {
        let mats = punch::read(path)?;
        return Ok(mats
            .iter()
            .map(|d| MatrixSummary::of(&d.matrix, "dmig"))
            .collect());
    }
    let mats = op4::read(path)?;
    Ok(mats.iter().map(|m| MatrixSummary::of(m, "op4")).collect())
}

/// The summaries as an aligned table, one matrix per line.
pub struct SummaryTable<'a>(pub &'a [MatrixSummary]);

impl fmt::Display for SummaryTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let head = [
            "name",
            "format",
            "rows",
            "cols",
            "form",
            "type",
            "nnz",
            "frobenius",
            "sum",
            "symmetric",
        ];
        let rows: Vec<[String; 10]> = self
            .0
            .iter()
            .map(|s| {
                let sum = if s.sum_imag == 0.0 {
                    format!("{:.6e}", s.sum)
                } else {
                    format!("{:.6e}{:+.6e}i", s.sum, s.sum_imag)
                };
                [
                    s.name.clone(),
                    s.format.to_string(),
                    s.nrows.to_string(),
                    s.ncols.to_string(),
                    format!("{:?}", s.form).to_lowercase(),
                    format!("{:?}", s.precision).to_lowercase(),
                    s.nnz.to_string(),
                    format!("{:.6e}", s.frobenius),
                    sum,
                    if s.symmetric { "yes" } else { "no" }.to_string(),
                ]
            })
            .collect();
        let mut w = head.map(str::len);
        for r in &rows {
            for (k, c) in r.iter().enumerate() {
                w[k] = w[k].max(c.chars().count());
            }
        }
        let line = |f: &mut fmt::Formatter<'_>, cells: &[&str]| -> fmt::Result {
            let mut s = String::new();
            for (k, c) in cells.iter().enumerate() {
                // Text columns left-aligned, numbers right-aligned.
                if k < 2 || k == 4 || k == 5 || k == 9 {
                    s.push_str(&format!("{:<width$}", c, width = w[k]));
                } else {
                    s.push_str(&format!("{:>width$}", c, width = w[k]));
                }
                if k + 1 < cells.len() {
                    s.push_str("  ");
                }
            }
            writeln!(f, "{}", s.trim_end())
        };
        line(f, &head)?;
        for r in &rows {
            let cells: Vec<&str> = r.iter().map(String::as_str).collect();
            line(f, &cells)?;
        }
        Ok(())
    }
}
