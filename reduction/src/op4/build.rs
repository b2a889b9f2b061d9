//! Pieces shared by the OP4 readers (a matrix filled string by string) and writers (the
//! nonzero runs of a column).

use faer::Mat;

use crate::matrix::{Cplx, MatrixData, MatrixForm, NamedMatrix, Precision, Real};

/// Largest matrix (entries) the readers allocate: reduced models are stored dense, and a
/// garbled header must not make the reader allocate gigabytes.
pub(crate) const MAX_ENTRIES: usize = super::MAX_DENSE_ENTRIES;

/// OP4 matrix header: `NCOL NROW NF NTYPE NAME`.
#[derive(Debug, Clone)]
pub(crate) struct Header {
    pub ncols: usize,
    pub nrows: usize,
    /// Sparse strings carry two-word headers (`NROW < 0`, or `NROW ≥ 65536`).
    pub bigmat: bool,
    pub form: MatrixForm,
    pub precision: Precision,
    pub name: String,
}

impl Header {
    /// Checks the raw header integers; `Err` holds the reason.
    pub fn new(
        ncols: i64,
        nrows: i64,
        form: i64,
        ntype: i64,
        name: String,
    ) -> Result<Self, String> {
        let precision = Precision::from_code(ntype)
            .ok_or_else(|| format!("matrix type NTYPE = {ntype} is not 1, 2, 3 or 4"))?;
        if ncols < 0 {
            return Err(format!("negative column count NCOL = {ncols}"));
        }
        let form = i32::try_from(form)
            .map(MatrixForm::from_code)
            .map_err(|_| format!("matrix form NF = {form} out of range"))?;
        let (ncols, nrows_abs) = (ncols as u64, nrows.unsigned_abs());
        if ncols.saturating_mul(nrows_abs) > MAX_ENTRIES as u64 {
            return Err(format!(
                "{nrows_abs} x {ncols} matrix exceeds the {MAX_ENTRIES} entries read densely"
            ));
        }
        Ok(Self {
            ncols: ncols as usize,
            nrows: nrows_abs as usize,
            bigmat: !(0..65536).contains(&nrows),
            form,
            precision,
            name,
        })
    }

    /// Numbers per entry: 1 real, 2 complex.
    pub fn numbers_per_entry(&self) -> usize {
        if self.precision.is_complex() {
            2
        } else {
            1
        }
    }
}

/// A matrix being filled from OP4 strings.
pub(crate) struct Builder {
    header: Header,
    re: Mat<Real>,
    im: Option<Mat<Real>>,
}

impl Builder {
    pub fn new(header: Header) -> Self {
        let (m, n) = (header.nrows, header.ncols);
        let im = header.precision.is_complex().then(|| Mat::zeros(m, n));
        Self {
            re: Mat::zeros(m, n),
            im,
            header,
        }
    }

    /// Stores `numbers` (interleaved re, im for complex) down column `col` (0-based) from row
    /// `row` (0-based). Values are kept as read: single-precision ASCII files may hold more
    /// digits than an `f32` (64-bit-integer NASTRAN builds write type 1 with 8-byte reals).
    pub fn put(&mut self, col: usize, row: usize, numbers: &[Real]) -> Result<(), String> {
        let per = self.header.numbers_per_entry();
        if numbers.len() % per != 0 {
            return Err(format!(
                "odd number of values ({}) in a complex string",
                numbers.len()
            ));
        }
        let count = numbers.len() / per;
        if col >= self.header.ncols {
            return Err(format!(
                "column {} outside 1..={}",
                col + 1,
                self.header.ncols
            ));
        }
        if row + count > self.header.nrows {
            return Err(format!(
                "rows {}..={} of column {} outside 1..={}",
                row + 1,
                row + count,
                col + 1,
                self.header.nrows
            ));
        }
        for k in 0..count {
            self.re[(row + k, col)] = numbers[k * per];
            if let Some(im) = &mut self.im {
                im[(row + k, col)] = numbers[k * per + 1];
            }
        }
        Ok(())
    }

    /// Whether the matrix is complex (two numbers per entry).
    pub fn is_complex(&self) -> bool {
        self.im.is_some()
    }

    pub fn finish(self) -> NamedMatrix {
        let h = self.header;
        let data = match self.im {
            None => MatrixData::Real(self.re),
            Some(im) => {
                let re = self.re;
                MatrixData::Complex(Mat::from_fn(h.nrows, h.ncols, |i, j| {
                    Cplx::new(re[(i, j)], im[(i, j)])
                }))
            }
        };
        NamedMatrix {
            name: h.name,
            nrows: h.nrows,
            ncols: h.ncols,
            form: h.form,
            precision: h.precision,
            data,
        }
    }
}

/// A run of entries down one column: first row (0-based) and the numbers (interleaved re, im
/// for complex matrices).
pub(crate) struct Run {
    pub row: usize,
    pub numbers: Vec<Real>,
}

/// The runs of column `j`: one run from the first to the last nonzero (`dense`), or one run per
/// stretch of consecutive nonzeros, each at most `max_entries` long. Empty for a zero column.
pub(crate) fn column_runs(
    a: &NamedMatrix,
    j: usize,
    dense: bool,
    complex: bool,
    max_entries: usize,
) -> Vec<Run> {
    let nz = |i: usize| a.get(i, j) != Cplx::new(0.0, 0.0);
    let push = |numbers: &mut Vec<Real>, i: usize| {
        let z = a.get(i, j);
        numbers.push(z.re);
        if complex {
            numbers.push(z.im);
        }
    };
    let mut runs = Vec::new();
    if dense {
        let first = (0..a.nrows).find(|&i| nz(i));
        let last = (0..a.nrows).rev().find(|&i| nz(i));
        if let (Some(f), Some(l)) = (first, last) {
            let mut numbers = Vec::new();
            for i in f..=l {
                push(&mut numbers, i);
            }
            runs.push(Run { row: f, numbers });
        }
        return runs;
    }
    let mut i = 0;
    while i < a.nrows {
        if !nz(i) {
            i += 1;
            continue;
        }
        let start = i;
        let mut numbers = Vec::new();
        while i < a.nrows && nz(i) && i - start < max_entries {
            push(&mut numbers, i);
            i += 1;
        }
        runs.push(Run {
            row: start,
            numbers,
        });
    }
    runs
}
