//! Bad matrix files are errors naming the file, the line and the matrix, and what other
//! writers produce is read (issue 14): an empty OP4, pyNastran's ASCII sparse OP4, a DMIG
//! continuation whose card's first line is missing.

use std::path::{Path, PathBuf};

use faer::Mat;
use num_complex::Complex;
use serde_json::Value;
use squeal_reduction::op4;
use squeal_reduction::punch::{self, DmigMatrix, PunchWriteOptions};
use squeal_reduction::{MatrixForm, NamedMatrix, Precision};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An empty .op4 was accepted as "no matrices" (and `squeal` exited 0).
#[test]
fn op4_without_a_matrix_is_an_error_naming_the_file() {
    let d = tmp("faults-op4-empty");
    for (name, bytes) in [("empty.op4", &b""[..]), ("blank.op4", &b"\n  \n\n"[..])] {
        let p = d.join(name);
        std::fs::write(&p, bytes).unwrap();
        let e = op4::read(&p).unwrap_err().to_string();
        assert!(
            e.contains(name) && e.contains("no matrix in the file"),
            "{e}"
        );
    }
}

/// pyNastran's ASCII sparse OP4 (string headers carrying the column's word count) could not be
/// read although pyNastran reads it. File and exact values: `scripts/make_pynastran_sparse.py`
/// (pyNastran 1.4.1), read back by pyNastran before it was kept.
#[test]
fn pynastran_ascii_sparse_op4_is_read() {
    let truth: Value = serde_json::from_str(
        &std::fs::read_to_string(data_dir().join("op4/pynastran_ascii_sparse.json")).unwrap(),
    )
    .unwrap();
    let mats = op4::read(data_dir().join("op4/pynastran_ascii_sparse.op4")).unwrap();
    let names: Vec<&str> = mats.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["RD", "RS", "ZD"]);
    for m in &mats {
        let t = &truth["matrices"][&m.name];
        let (r, c) = (
            t["nrows"].as_u64().unwrap() as usize,
            t["ncols"].as_u64().unwrap() as usize,
        );
        assert_eq!((m.nrows, m.ncols), (r, c), "{}", m.name);
        let re: Vec<f64> = t["re"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let im: Vec<f64> = t
            .get("im")
            .map(|v| {
                v.as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect()
            })
            .unwrap_or_else(|| vec![0.0; r * c]);
        let mut nonzeros = 0;
        for j in 0..c {
            for i in 0..r {
                let want = Complex::new(re[j * r + i], im[j * r + i]);
                let got = m.get(i, j);
                if m.precision.is_single() {
                    // 17 digits of a float32 value: equal once rounded to float32, as
                    // pyNastran (dtype float32) reads them.
                    assert_eq!(got.re as f32, want.re as f32, "{} ({i}, {j})", m.name);
                } else {
                    assert_eq!(got, want, "{} ({i}, {j})", m.name);
                }
                nonzeros += (want != Complex::new(0.0, 0.0)) as usize;
            }
        }
        assert!(nonzeros >= 5, "{}", m.name);
    }
    assert_eq!(mats[1].precision, Precision::RealSingle);
    assert!(mats[2].is_complex());
    // The lenient reading is only for files consistent with pyNastran's writer: a string
    // header whose L is neither its own nor its column's word count is still an error.
    let text = std::fs::read_to_string(data_dir().join("op4/pynastran_ascii_sparse.op4")).unwrap();
    let bad = text.replacen("  589829\n", "  655365\n", 1);
    assert_ne!(bad, text);
    let e = op4::read_bytes_named(bad.as_bytes(), "bad.op4")
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.op4:line") && e.contains("`RD`"), "{e}");
}

fn symmetric_dmig() -> DmigMatrix {
    let a = Mat::from_fn(3, 3, |i, j| {
        [[4.0, 1.0, 0.5], [1.0, 5.0, 2.0], [0.5, 2.0, 6.0]][i][j]
    });
    DmigMatrix {
        matrix: NamedMatrix::real("KAA", a).with_form(MatrixForm::Symmetric),
        rows: vec![(1, 1), (1, 2), (2, 3)],
        cols: vec![(1, 1), (1, 2), (2, 3)],
    }
}

/// A continuation line whose parent card is missing was appended to the header card and
/// dropped: an entry was lost without a word.
#[test]
fn dmig_continuation_without_its_card_is_an_error_naming_the_line() {
    for large_field in [true, false] {
        let text =
            punch::write_string(&[&symmetric_dmig()], &PunchWriteOptions { large_field }).unwrap();
        assert_eq!(punch::read_str(&text).unwrap()[0], symmetric_dmig());
        let lines: Vec<&str> = text.lines().collect();
        // Line 2 is the first column card's first line; line 3 continues it.
        assert!(
            lines[1].starts_with("DMIG") && !lines[2].starts_with("DMIG"),
            "{text}"
        );
        let cut = [&lines[..1], &lines[2..]].concat().join("\n");
        let e = punch::read_bytes_named(cut.as_bytes(), "k.pch")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("k.pch:2:")
                && e.contains("`KAA`")
                && e.contains("first line of a column card is missing"),
            "large field {large_field}: {e}"
        );
    }
}
