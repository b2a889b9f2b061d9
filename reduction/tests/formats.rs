//! OP4 and punch (DMIG) formats: files written by pyyeti and pyNastran read back to the values
//! they were written from (`tests/data`, made by `scripts/make_interop_data.py`), squeal →
//! file → squeal round trips for every write option, files squeal writes read by pyyeti and
//! pyNastran (`scripts/check_squeal_files.py`), and garbled files giving `Err`, never a panic.

use std::path::{Path, PathBuf};

use faer::Mat;
use num_complex::Complex;
use serde_json::{json, Value};
use squeal_reduction::inspect::{inspect, SummaryTable};
use squeal_reduction::op4::{self, Op4WriteOptions, Sparsity, WritePrecision};
use squeal_reduction::punch::{self, DmigMatrix, Dof, PunchWriteOptions};
use squeal_reduction::{MatrixData, MatrixForm, NamedMatrix, Precision, ReductionError};

type C = Complex<f64>;

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn load_json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The ground-truth matrices of `truth.json` (values from a seeded RNG, written by
/// `make_interop_data.py`; column-major, exact float reprs).
struct Truth {
    m: NamedMatrix,
    rows: Vec<Dof>,
    cols: Vec<Dof>,
}

fn truth(name: &str) -> Truth {
    let t = &load_json(&data_dir().join("truth.json"))[name];
    let (m, n) = (
        t["nrows"].as_u64().unwrap() as usize,
        t["ncols"].as_u64().unwrap() as usize,
    );
    let re: Vec<f64> = t["re"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let mat = match t.get("im") {
        Some(im) => {
            let im: Vec<f64> = im
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            NamedMatrix::complex(
                name,
                Mat::from_fn(m, n, |i, j| C::new(re[j * m + i], im[j * m + i])),
            )
        }
        None => NamedMatrix::real(name, Mat::from_fn(m, n, |i, j| re[j * m + i])),
    };
    let dofs = |k: &str| -> Vec<Dof> {
        t.get(k)
            .map(|v| {
                v.as_array()
                    .unwrap()
                    .iter()
                    .map(|d| (d[0].as_u64().unwrap(), d[1].as_u64().unwrap() as u8))
                    .collect()
            })
            .unwrap_or_default()
    };
    Truth {
        m: mat,
        rows: dofs("rows"),
        cols: dofs("cols"),
    }
}

/// `truth` rounded to single precision (what a type 1/3 file holds).
fn to_single(a: &NamedMatrix) -> NamedMatrix {
    let r = |x: f64| x as f32 as f64;
    let mut b = a.clone();
    b.data = match &a.data {
        MatrixData::Real(m) => {
            MatrixData::Real(Mat::from_fn(a.nrows, a.ncols, |i, j| r(m[(i, j)])))
        }
        MatrixData::Complex(m) => MatrixData::Complex(Mat::from_fn(a.nrows, a.ncols, |i, j| {
            C::new(r(m[(i, j)].re), r(m[(i, j)].im))
        })),
    };
    b
}

/// Asserts `got` equals `want`: exactly if `single` (both rounded to f32), else to 1e-12
/// relative to the largest entry.
fn assert_values(got: &NamedMatrix, want: &NamedMatrix, single: bool, ctx: &str) {
    assert_eq!(
        (got.nrows, got.ncols),
        (want.nrows, want.ncols),
        "{ctx}: shape"
    );
    assert_eq!(got.is_complex(), want.is_complex(), "{ctx}: real/complex");
    let diff = got
        .max_abs_diff(&if single {
            to_single(want)
        } else {
            want.clone()
        })
        .unwrap();
    let tol = if single { 0.0 } else { 1e-12 * want.max_abs() };
    assert!(diff <= tol, "{ctx}: max |difference| {diff:e} > {tol:e}");
}

#[test]
fn interop_files_match_truth() {
    let manifest = load_json(&data_dir().join("manifest.json"));
    let files = manifest["files"].as_array().unwrap();
    assert!(files.len() >= 10, "manifest lists {} files", files.len());
    for f in files {
        let rel = f["file"].as_str().unwrap();
        let path = data_dir().join(rel);
        let single = f["single"].as_bool().unwrap();
        type RowsCols = (Vec<Dof>, Vec<Dof>);
        let (mats, dofs): (Vec<NamedMatrix>, Vec<RowsCols>) = if f["format"] == "op4" {
            let m = op4::read(&path).unwrap_or_else(|e| panic!("{e}"));
            let n = m.len();
            (m, vec![(vec![], vec![]); n])
        } else {
            punch::read(&path)
                .unwrap_or_else(|e| panic!("{e}"))
                .into_iter()
                .map(|d| (d.matrix, (d.rows, d.cols)))
                .unzip()
        };
        let want = f["matrices"].as_array().unwrap();
        assert_eq!(mats.len(), want.len(), "{rel}: number of matrices");
        for w in want {
            let name = w["name"].as_str().unwrap();
            let ctx = format!("{rel} {name}");
            // Writers order matrices differently (pyNastran sorts by name): look up by name.
            let k = mats
                .iter()
                .position(|m| m.name == name)
                .unwrap_or_else(|| panic!("{ctx}: missing"));
            let got = &mats[k];
            assert_eq!(
                got.form.code() as i64,
                w["form"].as_i64().unwrap(),
                "{ctx}: form"
            );
            assert_eq!(
                got.precision.code() as i64,
                w["type"].as_i64().unwrap(),
                "{ctx}: type"
            );
            let t = truth(name);
            assert_values(got, &t.m, single, &ctx);
            if f["format"] == "punch" {
                assert_eq!(dofs[k].0, t.rows, "{ctx}: row DOFs");
                assert_eq!(dofs[k].1, t.cols, "{ctx}: column DOFs");
            }
        }
    }
}

/// Test matrices for round trips: the truth matrices plus edge cases.
fn round_trip_set() -> Vec<NamedMatrix> {
    let mut v: Vec<NamedMatrix> = ["KSYM", "RECT", "CPLX"]
        .iter()
        .map(|n| truth(n).m)
        .collect();
    v.push(NamedMatrix::real("ZERO", Mat::zeros(3, 2)));
    v.push(
        NamedMatrix::real("ONE", Mat::from_fn(1, 1, |_, _| -2.5)).with_form(MatrixForm::Identity),
    );
    v.push(NamedMatrix::real("NOCOLS", Mat::zeros(4, 0)));
    // 70 000 rows: non-BIGMAT strings are not allowed above 65 535 rows (NASTRAN switches).
    v.push(NamedMatrix::real(
        "TALL",
        Mat::from_fn(70_000, 2, |i, j| {
            if (i / 9000 + j) % 2 == 0 {
                (i as f64).sin() + 1.5
            } else {
                0.0
            }
        }),
    ));
    v
}

#[test]
fn op4_round_trips_every_option() {
    let mats = round_trip_set();
    let refs: Vec<&NamedMatrix> = mats.iter().collect();
    for binary in [false, true] {
        for sparse in [Sparsity::Dense, Sparsity::NonBigmat, Sparsity::Bigmat] {
            for precision in [
                WritePrecision::AsMatrix,
                WritePrecision::Single,
                WritePrecision::Double,
            ] {
                for big_endian in [false, true] {
                    if big_endian && !binary {
                        continue;
                    }
                    let opts = Op4WriteOptions {
                        binary,
                        sparse,
                        precision,
                        big_endian,
                    };
                    let bytes = op4::write_bytes(&refs, &opts).unwrap();
                    assert_eq!(op4::is_binary(&bytes), binary);
                    let back = op4::read_bytes(&bytes).unwrap_or_else(|e| panic!("{opts:?}: {e}"));
                    assert_eq!(back.len(), mats.len());
                    let single = precision == WritePrecision::Single;
                    for (a, b) in mats.iter().zip(&back) {
                        let ctx = format!("{opts:?} {}", a.name);
                        assert_eq!(a.name, b.name, "{ctx}");
                        assert_eq!(a.form, b.form, "{ctx}");
                        assert_eq!(b.precision.is_single(), single, "{ctx}");
                        assert_eq!(b.precision.is_complex(), a.is_complex(), "{ctx}");
                        let want = if single { to_single(a) } else { a.clone() };
                        // Round trips are exact: ASCII files carry 17 significant digits.
                        assert_eq!(want.max_abs_diff(b), Some(0.0), "{ctx}");
                    }
                }
            }
        }
    }
}

/// Re-frames a binary OP4 written with 4-byte record markers with 8-byte markers.
fn with_8_byte_markers(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut p = 0;
    while p < bytes.len() {
        let n = u32::from_le_bytes(bytes[p..p + 4].try_into().unwrap()) as usize;
        out.extend_from_slice(&(n as u64).to_le_bytes());
        out.extend_from_slice(&bytes[p + 4..p + 4 + n]);
        out.extend_from_slice(&(n as u64).to_le_bytes());
        p += n + 8;
    }
    out
}

#[test]
fn op4_binary_8_byte_markers_and_64_bit_integers() {
    let k = truth("KSYM").m;
    let bytes = op4::write_bytes(&[&k], &Op4WriteOptions::default()).unwrap();
    let back = op4::read_bytes(&with_8_byte_markers(&bytes)).unwrap();
    assert_eq!(back[0].max_abs_diff(&k), Some(0.0));

    // A 64-bit-integer file (as NASTRAN writes on ILP64 builds, pyyeti's `bit64`): header of
    // 4 × i64 + 16 characters (48 bytes), words of 8 bytes, every value an f64 even for type 1.
    let rec = |out: &mut Vec<u8>, payload: &[u8]| {
        out.extend_from_slice(&(payload.len() as u32).to_be_bytes());
        out.extend_from_slice(payload);
        out.extend_from_slice(&(payload.len() as u32).to_be_bytes());
    };
    let words = |v: &[i64]| v.iter().flat_map(|x| x.to_be_bytes()).collect::<Vec<u8>>();
    let mut f = Vec::new();
    let mut head = words(&[2, -3, 2, 1]);
    head.extend_from_slice(b"M64             ");
    rec(&mut f, &head);
    let mut col = words(&[1, 2, 2]); // dense: rows 2..3 of column 1
    col.extend(
        1.25f64
            .to_be_bytes()
            .into_iter()
            .chain((-3.0f64).to_be_bytes()),
    );
    rec(&mut f, &col);
    let mut col = words(&[2, 0, 3]); // BIGMAT string: L + 1 = 2, IROW = 1, one value
    col.extend(words(&[2, 1]).into_iter().chain(0.5f64.to_be_bytes()));
    rec(&mut f, &col);
    let mut end = words(&[3, 1, 1]);
    end.extend(1.0f64.to_be_bytes());
    rec(&mut f, &end);
    let m = &op4::read_bytes(&f).unwrap()[0];
    assert_eq!(
        (m.name.as_str(), m.nrows, m.ncols, m.precision),
        ("M64", 3, 2, Precision::RealSingle)
    );
    let want = [[0.0, 0.5], [1.25, 0.0], [-3.0, 0.0]];
    for i in 0..3 {
        for j in 0..2 {
            assert_eq!(m.get(i, j), C::new(want[i][j], 0.0), "({i}, {j})");
        }
    }
}

#[test]
fn op4_ascii_d_exponents_and_fortran_three_digit_exponents() {
    // NASTRAN writes `D` exponents with FORMAT 1P,5D16.9 and drops the `E` of three-digit
    // exponents (Fortran Ew.d): `1.0+100`.
    let text = format!(
        "{:8}{:8}{:8}{:8}{:<8}1P,2D16.9\n{:8}{:8}{:8}\n{:>16}{:>16}\n{:8}{:8}{:8}\n{:>16}\n",
        1, 2, 2, 2, "A", 1, 1, 2, "1.250000000D+02", "1.000000000+100", 2, 1, 1, "1.000000000D+00"
    );
    let m = &op4::read_bytes(text.as_bytes()).unwrap()[0];
    assert_eq!(m.get(0, 0).re, 125.0);
    assert_eq!(m.get(1, 0).re, 1e100);
    let tiny = NamedMatrix::real(
        "T",
        Mat::from_fn(2, 1, |i, _| if i == 0 { 1e-300 } else { -7e123 }),
    );
    for binary in [false, true] {
        let opts = Op4WriteOptions {
            binary,
            ..Default::default()
        };
        let back = op4::read_bytes(&op4::write_bytes(&[&tiny], &opts).unwrap()).unwrap();
        assert_eq!(back[0].max_abs_diff(&tiny), Some(0.0));
    }
}

fn dmig(name: &str) -> DmigMatrix {
    let t = truth(name);
    let form = MatrixForm::from_code(match name {
        "KDMIG" => 6,
        "RDMIG" => 2,
        _ => 1,
    });
    DmigMatrix {
        matrix: t.m.with_form(form),
        rows: t.rows,
        cols: t.cols,
    }
}

#[test]
fn punch_round_trips() {
    // Values k/8 and k/16 fit 8 and 16 characters exactly: round trips are exact.
    let all: Vec<DmigMatrix> = ["KDMIG", "RDMIG", "SDMIG", "CDMIG"]
        .iter()
        .map(|n| dmig(n))
        .collect();
    for large_field in [false, true] {
        let set: Vec<&DmigMatrix> = all
            .iter()
            .filter(|d| large_field || ["KDMIG", "SDMIG"].contains(&d.matrix.name.as_str()))
            .collect();
        let opts = PunchWriteOptions { large_field };
        let text = punch::write_string(&set, &opts).unwrap();
        let back = punch::read_str(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(back.len(), set.len());
        for (a, b) in set.iter().zip(&back) {
            assert_eq!(a.rows, b.rows);
            assert_eq!(a.cols, b.cols);
            assert_eq!(a.matrix.form, b.matrix.form);
            assert_eq!(
                a.matrix.max_abs_diff(&b.matrix),
                Some(0.0),
                "{} large={large_field}",
                a.matrix.name
            );
        }
    }
    // Arbitrary doubles keep what the field holds: 16 characters keep ≥ 10 significant digits
    // (`-1.234567890D+00`), 8 keep ≥ 3 (`-1.23-99`), i.e. relative errors ≤ 5e-10 and 5e-3.
    let k = truth("KSYM");
    let n = k.m.nrows;
    let dofs: Vec<Dof> = (0..n as u64)
        .map(|g| (g / 6 + 1, (g % 6 + 1) as u8))
        .collect();
    let d = DmigMatrix {
        matrix: k.m.clone(),
        rows: dofs.clone(),
        cols: dofs,
    };
    for (large_field, rel) in [(true, 5e-10), (false, 5e-3)] {
        let text = punch::write_string(&[&d], &PunchWriteOptions { large_field }).unwrap();
        let b = &punch::read_str(&text).unwrap()[0].matrix;
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (k.m.get(i, j).re, b.get(i, j).re);
                assert!((x - y).abs() <= rel * x.abs(), "({i},{j}) {x} vs {y}");
            }
        }
    }
}

#[test]
fn punch_nastran_syntax() {
    // Free field, compressed reals, a scalar point, POLAR = 1 (amplitude, phase in degrees) and
    // IFO 9 — forms described in the NASTRAN Quick Reference Guide, DMIG entry.
    let text = "$ comment\nBEGIN BULK\nDMIG,A,0,6,2,0\nDMIG,A,10,1,,10,1,1.-3,,10,2,-.5+2\n\
                DMIG,A,10,2,,10,2,2.5D0\nDMIG,A,10,2,,7,0,4\nGRID,1,,0.,0.,0.\n\
                DMIG,P,0,2,3,0,1\nDMIG,P,5,0,,6,3,2.,90.\n\
                DMIG,N,0,9,1,0,0,,3\nDMIG,N,2,0,,4,1,3.5\nENDDATA\n";
    let mats = punch::read_str(text).unwrap();
    let a = &mats[0];
    assert_eq!(a.rows, vec![(7, 0), (10, 1), (10, 2)]);
    assert_eq!(a.matrix.form, MatrixForm::Symmetric);
    let g = |i: usize, j: usize| a.matrix.get(i, j).re;
    assert_eq!(
        (g(1, 1), g(2, 1), g(1, 2), g(2, 2), g(0, 2), g(2, 0)),
        (1e-3, -50.0, -50.0, 2.5, 4.0, 4.0)
    );
    let p = &mats[1];
    assert_eq!(
        (p.rows.clone(), p.cols.clone()),
        (vec![(6, 3)], vec![(5, 0)])
    );
    let z = p.matrix.get(0, 0);
    assert!((z - C::new(0.0, 2.0)).norm() < 1e-6, "{z}");
    assert_eq!(p.matrix.precision, Precision::ComplexSingle);
    let n = &mats[2];
    assert_eq!(n.cols, vec![(1, 0), (2, 0), (3, 0)]);
    assert_eq!(
        (n.matrix.get(0, 1).re, n.matrix.form),
        (3.5, MatrixForm::PseudoIdentity)
    );
}

#[test]
fn punch_errors_name_file_line_and_matrix() {
    // Both triangles of a symmetric matrix with different values.
    let text = "DMIG,K,0,6,2,0\nDMIG,K,1,1,,1,2,1.0\nDMIG,K,1,2,,1,1,2.0\n";
    let dir = std::env::temp_dir().join(format!("squeal-punch-err-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.pch");
    std::fs::write(&path, text).unwrap();
    let e = punch::read(&path).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, ReductionError::Punch { line: 3, .. }), "{msg}");
    assert!(
        msg.contains("bad.pch") && msg.contains("`K`") && msg.contains("both triangles"),
        "{msg}"
    );
    // The same value twice is accepted (NASTRAN tolerates a consistent duplicate).
    assert!(punch::read_str("DMIG,K,0,6,2,0\nDMIG,K,1,1,,1,2,1.0\nDMIG,K,1,2,,1,1,1.0\n").is_ok());
    for (bad, what) in [
        ("DMIG,K,0,6,2,0\nDMIG,K,1,1,,1,2,abc\n", "not a finite real"),
        ("DMIG,K,0,7,2,0\n", "IFO"),
        ("DMIG,K,1,1,,1,2,1.0\n", "header"),
        ("DMIG,K,0,6,2,0\nDMIG,K,1,9,,1,2,1.0\n", "component"),
        ("DMIG,K,0,2,1,0\nDMIG,K,1,1,,1,2,1.0,5.0\n", "imaginary"),
    ] {
        let msg = punch::read_str(bad).unwrap_err().to_string();
        assert!(msg.contains(what) && msg.contains("<text>:"), "{msg}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn writers_reject_what_the_formats_cannot_hold() {
    let long = NamedMatrix::real("TOOLONGNAME", Mat::zeros(1, 1));
    assert!(op4::write_bytes(&[&long], &Op4WriteOptions::default()).is_err());
    let mut d = dmig("SDMIG");
    d.matrix = d.matrix.with_form(MatrixForm::Symmetric); // not symmetric
    assert!(punch::write_string(&[&d], &PunchWriteOptions::default()).is_err());
    let mut d = dmig("KDMIG");
    d.rows.pop();
    assert!(punch::write_string(&[&d], &PunchWriteOptions::default()).is_err());
}

/// Deterministic pseudo-random numbers (64-bit LCG, Knuth's MMIX constants).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
}

#[test]
fn truncated_and_garbled_files_give_err_not_panic() {
    let mut samples: Vec<(bool, Vec<u8>)> = Vec::new();
    for f in load_json(&data_dir().join("manifest.json"))["files"]
        .as_array()
        .unwrap()
    {
        let bytes = std::fs::read(data_dir().join(f["file"].as_str().unwrap())).unwrap();
        samples.push((f["format"] == "op4", bytes));
    }
    let mut rng = Lcg(7);
    let mut errs = 0;
    for (is_op4, bytes) in &samples {
        let parse = |b: &[u8]| -> bool {
            if *is_op4 {
                op4::read_bytes(b).is_err()
            } else {
                std::str::from_utf8(b)
                    .map(|t| punch::read_str(t).is_err())
                    .unwrap_or(true)
            }
        };
        for cut in (0..bytes.len()).step_by(17) {
            errs += parse(&bytes[..cut]) as usize;
        }
        for _ in 0..150 {
            let mut b = bytes.clone();
            for _ in 0..1 + rng.next() % 4 {
                let at = rng.next() as usize % b.len();
                b[at] = match rng.next() % 4 {
                    0 => rng.next() as u8,
                    1 => b'-',
                    2 => b'9',
                    _ => 0xff,
                };
            }
            errs += parse(&b) as usize;
        }
    }
    // Most cuts and garbles are detected (some land in values and stay valid).
    assert!(errs > samples.len() * 40, "only {errs} errors");
}

#[test]
fn inspect_summarises_files() {
    let s = inspect(data_dir().join("op4/yeti_bin_dense_be.op4")).unwrap();
    let names: Vec<&str> = s.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, ["KSYM", "RECT", "CPLX"]);
    for x in &s {
        let t = truth(&x.name).m;
        let (mut fro, mut sum, mut nnz) = (0.0, C::new(0.0, 0.0), 0);
        for j in 0..t.ncols {
            for i in 0..t.nrows {
                let z = t.get(i, j);
                fro += z.norm_sqr();
                sum += z;
                nnz += (z != C::new(0.0, 0.0)) as usize;
            }
        }
        assert_eq!(
            (x.nrows, x.ncols, x.nnz),
            (t.nrows, t.ncols, nnz),
            "{}",
            x.name
        );
        assert!((x.frobenius - fro.sqrt()).abs() <= 1e-14 * fro.sqrt());
        assert!((C::new(x.sum, x.sum_imag) - sum).norm() <= 1e-14 * fro.sqrt());
        assert_eq!(x.symmetric, x.name == "KSYM");
    }
    let p = inspect(data_dir().join("punch/yeti_large.pch")).unwrap();
    assert_eq!(p.len(), 4);
    assert!(p[0].symmetric && p[0].format == "dmig");
    let table = SummaryTable(&s).to_string();
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines.len(), 4);
    assert!(lines[0].starts_with("name") && lines[1].starts_with("KSYM"));
    // Aligned: the `rows` column ends at the same place on every line.
    let end = lines[0].find("rows").unwrap() + 4;
    assert!(lines
        .iter()
        .all(|l| l[..end].ends_with(|c: char| c.is_ascii_alphanumeric())));
    let j = serde_json::to_value(&s).unwrap();
    assert_eq!(j[0]["form"], json!("symmetric"));
}

/// Files squeal writes, read by pyyeti and pyNastran (`scripts/check_squeal_files.py`).
#[test]
fn squeal_files_read_by_pyyeti_and_pynastran() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let python = root.join(".venv/bin/python");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/check_squeal_files.py");
    let have = std::process::Command::new(&python)
        .args(["-c", "import pyNastran, pyyeti"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    assert!(
        have,
        "{} with pyNastran and pyyeti is needed: run the README test command `bash scripts/test.sh` \
         (it installs them), or `.venv/bin/pip install pyNastran pyyeti`",
        python.display()
    );
    let dir = std::env::temp_dir().join(format!("squeal-formats-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mats: Vec<NamedMatrix> = ["KSYM", "RECT", "CPLX"]
        .iter()
        .map(|n| truth(n).m)
        .collect();
    let refs: Vec<&NamedMatrix> = mats.iter().collect();
    let mut files = Vec::new();
    let entry = |m: &NamedMatrix| {
        let (mut re, mut im) = (Vec::new(), Vec::new());
        for j in 0..m.ncols {
            for i in 0..m.nrows {
                re.push(m.get(i, j).re);
                im.push(m.get(i, j).im);
            }
        }
        json!({"name": m.name, "form": m.form.code(), "type": m.precision.code(), "nrows": m.nrows,
               "ncols": m.ncols, "re": re, "im": if m.is_complex() { json!(im) } else { Value::Null }})
    };
    for binary in [false, true] {
        for sparse in [Sparsity::Dense, Sparsity::NonBigmat, Sparsity::Bigmat] {
            for (precision, single) in [
                (WritePrecision::Double, false),
                (WritePrecision::Single, true),
            ] {
                for big_endian in [false, true] {
                    if big_endian && !binary {
                        continue;
                    }
                    let opts = Op4WriteOptions {
                        binary,
                        sparse,
                        precision,
                        big_endian,
                    };
                    let path = dir.join(format!(
                        "{binary}_{sparse:?}_{precision:?}_{big_endian}.op4"
                    ));
                    op4::write(&path, &refs, &opts).unwrap();
                    let ms: Vec<Value> = mats
                        .iter()
                        .map(|m| {
                            let mut e = entry(&if single { to_single(m) } else { m.clone() });
                            e["type"] = json!(
                                m.precision.with_complex(m.is_complex()).code()
                                    - if single { 1 } else { 0 }
                            );
                            e
                        })
                        .collect();
                    files.push(
                        json!({"file": path, "format": "op4", "binary": binary, "single": single,
                                      "rtol": if single { 1e-7 } else { 1e-12 }, "matrices": ms}),
                    );
                }
            }
        }
    }
    let ds: Vec<DmigMatrix> = ["KDMIG", "RDMIG", "SDMIG", "CDMIG"]
        .iter()
        .map(|n| dmig(n))
        .collect();
    for large_field in [false, true] {
        let set: Vec<&DmigMatrix> = ds
            .iter()
            .filter(|d| large_field || ["KDMIG", "SDMIG"].contains(&d.matrix.name.as_str()))
            .collect();
        let path = dir.join(format!("dmig_{large_field}.pch"));
        punch::write(&path, &set, &PunchWriteOptions { large_field }).unwrap();
        let ms: Vec<Value> = set
            .iter()
            .map(|d| {
                let mut e = entry(&d.matrix);
                e["rows"] = json!(d.rows);
                e["cols"] = json!(d.cols);
                e
            })
            .collect();
        files.push(json!({"file": path, "format": "punch", "single": false, "rtol": 1e-12, "matrices": ms}));
    }
    let manifest = dir.join("manifest.json");
    std::fs::write(
        &manifest,
        serde_json::to_string(&json!({ "files": files })).unwrap(),
    )
    .unwrap();
    let out = std::process::Command::new(&python)
        .arg(&script)
        .arg(&manifest)
        .output()
        .unwrap();
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "check_squeal_files.py failed:\n{log}");
    assert!(log.contains("checked"), "{log}");
    std::fs::remove_dir_all(&dir).ok();
}
