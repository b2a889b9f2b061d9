//! In-memory named matrices: what OP4 and punch (DMIG) files hold.
//!
//! Reduced models are small (hundreds to a few thousand DOFs), so the matrices are stored dense.

use faer::Mat;
use num_complex::Complex;
use serde::{Deserialize, Serialize};

/// The workspace's real scalar (its one definition is `squeal_meshes::Real`).
pub use squeal_meshes::Real;
/// Complex scalar.
pub type Cplx = Complex<f64>;

/// NASTRAN matrix form (the `FORM`/`IFO` code of OP4 headers and DMIG cards).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MatrixForm {
    /// 1: square.
    Square,
    /// 2: rectangular.
    Rectangular,
    /// 3: diagonal.
    Diagonal,
    /// 4: lower triangular factor.
    LowerTriangular,
    /// 5: upper triangular factor.
    UpperTriangular,
    /// 6: symmetric (OP4 stores both triangles; DMIG one).
    Symmetric,
    /// 8: identity.
    Identity,
    /// 9: pseudo-identity (DMIG: rectangular with columns numbered 1..NCOL).
    PseudoIdentity,
    /// 10: Cholesky factor.
    CholeskyFactor,
    /// 11: trapezoidal factor.
    TrapezoidalFactor,
    /// 13: sparse lower triangular factor.
    SparseLowerTriangular,
    /// 15: sparse upper triangular factor.
    SparseUpperTriangular,
    /// Any other code found in a file, kept as is.
    Other(i32),
}

impl MatrixForm {
    /// The NASTRAN code.
    pub fn code(self) -> i32 {
        match self {
            Self::Square => 1,
            Self::Rectangular => 2,
            Self::Diagonal => 3,
            Self::LowerTriangular => 4,
            Self::UpperTriangular => 5,
            Self::Symmetric => 6,
            Self::Identity => 8,
            Self::PseudoIdentity => 9,
            Self::CholeskyFactor => 10,
            Self::TrapezoidalFactor => 11,
            Self::SparseLowerTriangular => 13,
            Self::SparseUpperTriangular => 15,
            Self::Other(c) => c,
        }
    }

    /// The form of a NASTRAN code (unknown codes become [`MatrixForm::Other`]).
    pub fn from_code(code: i32) -> Self {
        match code {
            1 => Self::Square,
            2 => Self::Rectangular,
            3 => Self::Diagonal,
            4 => Self::LowerTriangular,
            5 => Self::UpperTriangular,
            6 => Self::Symmetric,
            8 => Self::Identity,
            9 => Self::PseudoIdentity,
            10 => Self::CholeskyFactor,
            11 => Self::TrapezoidalFactor,
            13 => Self::SparseLowerTriangular,
            15 => Self::SparseUpperTriangular,
            c => Self::Other(c),
        }
    }
}

/// NASTRAN matrix type (`NTYPE`/`TIN`): real or complex, single or double precision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// 1: real, single precision.
    RealSingle,
    /// 2: real, double precision.
    RealDouble,
    /// 3: complex, single precision.
    ComplexSingle,
    /// 4: complex, double precision.
    ComplexDouble,
}

impl Precision {
    /// The NASTRAN code (1..=4).
    pub fn code(self) -> i32 {
        match self {
            Self::RealSingle => 1,
            Self::RealDouble => 2,
            Self::ComplexSingle => 3,
            Self::ComplexDouble => 4,
        }
    }

    /// The precision of a NASTRAN code, `None` outside 1..=4.
    pub fn from_code(code: i64) -> Option<Self> {
        match code {
            1 => Some(Self::RealSingle),
            2 => Some(Self::RealDouble),
            3 => Some(Self::ComplexSingle),
            4 => Some(Self::ComplexDouble),
            _ => None,
        }
    }

    /// True for types 3 and 4.
    pub fn is_complex(self) -> bool {
        matches!(self, Self::ComplexSingle | Self::ComplexDouble)
    }

    /// True for types 1 and 3.
    pub fn is_single(self) -> bool {
        matches!(self, Self::RealSingle | Self::ComplexSingle)
    }

    /// The type with the same precision and the given field (real or complex).
    pub fn with_complex(self, complex: bool) -> Self {
        match (self.is_single(), complex) {
            (true, false) => Self::RealSingle,
            (false, false) => Self::RealDouble,
            (true, true) => Self::ComplexSingle,
            (false, true) => Self::ComplexDouble,
        }
    }
}

/// Dense matrix values, real or complex.
#[derive(Debug, Clone, PartialEq)]
pub enum MatrixData {
    /// Real values.
    Real(Mat<Real>),
    /// Complex values.
    Complex(Mat<Cplx>),
}

/// A matrix with its NASTRAN name, form and precision.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedMatrix {
    /// Matrix name (NASTRAN: at most 8 characters, upper case in files).
    pub name: String,
    /// Number of rows.
    pub nrows: usize,
    /// Number of columns.
    pub ncols: usize,
    /// Matrix form.
    pub form: MatrixForm,
    /// Matrix type; its real/complex part agrees with `data`.
    pub precision: Precision,
    /// Values (shape `nrows` × `ncols`).
    pub data: MatrixData,
}

impl NamedMatrix {
    /// A real double-precision matrix; the form is `Symmetric` if `a` is square and exactly
    /// symmetric, `Square` if square, `Rectangular` otherwise.
    pub fn real(name: impl Into<String>, a: Mat<Real>) -> Self {
        let form = auto_form(a.nrows(), a.ncols(), |i, j| a[(i, j)] == a[(j, i)]);
        Self {
            name: name.into(),
            nrows: a.nrows(),
            ncols: a.ncols(),
            form,
            precision: Precision::RealDouble,
            data: MatrixData::Real(a),
        }
    }

    /// A complex double-precision matrix; the form is chosen as in [`NamedMatrix::real`].
    pub fn complex(name: impl Into<String>, a: Mat<Cplx>) -> Self {
        let form = auto_form(a.nrows(), a.ncols(), |i, j| a[(i, j)] == a[(j, i)]);
        Self {
            name: name.into(),
            nrows: a.nrows(),
            ncols: a.ncols(),
            form,
            precision: Precision::ComplexDouble,
            data: MatrixData::Complex(a),
        }
    }

    /// The same matrix with another form.
    pub fn with_form(mut self, form: MatrixForm) -> Self {
        self.form = form;
        self
    }

    /// The same matrix with another precision (real/complex follows the data).
    pub fn with_precision(mut self, precision: Precision) -> Self {
        self.precision = precision.with_complex(self.is_complex());
        self
    }

    /// True if the values are complex.
    pub fn is_complex(&self) -> bool {
        matches!(self.data, MatrixData::Complex(_))
    }

    /// Entry (i, j) as a complex number (imaginary part 0 for real matrices).
    pub fn get(&self, i: usize, j: usize) -> Cplx {
        match &self.data {
            MatrixData::Real(a) => Cplx::new(a[(i, j)], 0.0),
            MatrixData::Complex(a) => a[(i, j)],
        }
    }

    /// The real values, if the matrix is real.
    pub fn as_real(&self) -> Option<&Mat<Real>> {
        match &self.data {
            MatrixData::Real(a) => Some(a),
            MatrixData::Complex(_) => None,
        }
    }

    /// The complex values, if the matrix is complex.
    pub fn as_complex(&self) -> Option<&Mat<Cplx>> {
        match &self.data {
            MatrixData::Real(_) => None,
            MatrixData::Complex(a) => Some(a),
        }
    }

    /// Number of nonzero entries.
    pub fn nnz(&self) -> usize {
        let mut n = 0;
        for j in 0..self.ncols {
            for i in 0..self.nrows {
                if self.get(i, j) != Cplx::new(0.0, 0.0) {
                    n += 1;
                }
            }
        }
        n
    }

    /// Largest entry modulus (0 for an empty matrix).
    pub fn max_abs(&self) -> Real {
        let mut m: Real = 0.0;
        for j in 0..self.ncols {
            for i in 0..self.nrows {
                m = m.max(self.get(i, j).norm());
            }
        }
        m
    }

    /// Largest entry modulus of `self − other`, `None` if the shapes differ.
    pub fn max_abs_diff(&self, other: &NamedMatrix) -> Option<Real> {
        if self.nrows != other.nrows || self.ncols != other.ncols {
            return None;
        }
        let mut m: Real = 0.0;
        for j in 0..self.ncols {
            for i in 0..self.nrows {
                m = m.max((self.get(i, j) - other.get(i, j)).norm());
            }
        }
        Some(m)
    }

    /// True if square and `max |A − Aᵀ| ≤ rel_tol · max |A|` (an all-zero square matrix is
    /// symmetric).
    pub fn is_symmetric(&self, rel_tol: Real) -> bool {
        if self.nrows != self.ncols {
            return false;
        }
        let scale = self.max_abs();
        for j in 0..self.ncols {
            for i in (j + 1)..self.nrows {
                if (self.get(i, j) - self.get(j, i)).norm() > rel_tol * scale {
                    return false;
                }
            }
        }
        true
    }
}

/// Symmetric / square / rectangular from the shape and an exact symmetry test.
fn auto_form(nrows: usize, ncols: usize, sym: impl Fn(usize, usize) -> bool) -> MatrixForm {
    if nrows != ncols {
        return MatrixForm::Rectangular;
    }
    for j in 0..ncols {
        for i in (j + 1)..nrows {
            if !sym(i, j) {
                return MatrixForm::Square;
            }
        }
    }
    MatrixForm::Symmetric
}

/// Checks a name for OP4 and DMIG: 1 to 8 ASCII letters, digits or `_`, starting with a letter.
pub(crate) fn check_name(name: &str) -> Result<(), String> {
    let ok_chars = name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    let starts = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
    if name.is_empty() || name.len() > 8 || !ok_chars || !starts {
        return Err(format!(
            "name `{name}` is not a NASTRAN name (1–8 letters, digits or `_`, starting with a letter)"
        ));
    }
    Ok(())
}
