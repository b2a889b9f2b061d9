//! Reading DMIG matrices from punch / bulk-data text.
//!
//! Header card `DMIG NAME 0 IFO TIN TOUT POLAR – NCOL`, then one card per column
//! `DMIG NAME GJ CJ – G1 C1 A1 B1 G2 C2 A2 B2 …` (B only for complex TIN 3, 4; with POLAR = 1,
//! A is the amplitude and B the phase in degrees). IFO 1 (square) and 6 (symmetric, one
//! triangle given) use the union of row and column DOFs for both; IFO 2 (rectangular) sorts
//! rows and columns apart; IFO 9 numbers the columns 1…NCOL (component 0).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use faer::Mat;

use super::cards::{dmig_cards, Card};
use super::number::parse_real;
use super::{DmigMatrix, Dof};
use crate::matrix::{Cplx, MatrixData, MatrixForm, NamedMatrix, Precision};

/// Error of the reader: line, matrix, reason.
pub(crate) type PunchError = (usize, String, String);

struct Head {
    line: usize,
    ifo: i64,
    precision: Precision,
    polar: bool,
    ncol: i64,
}

struct Entry {
    line: usize,
    row: Dof,
    col: Dof,
    value: Cplx,
}

fn int_field(f: &[String], k: usize, what: &str, default: Option<i64>) -> Result<i64, String> {
    let s = f.get(k).map(String::as_str).unwrap_or("");
    if s.is_empty() {
        return default.ok_or_else(|| format!("{what} (field {}) is blank", k + 2));
    }
    s.parse()
        .map_err(|_| format!("{what} (field {}) `{s}` is not an integer", k + 2))
}

/// Parses every DMIG matrix of a punch text, in the order of their header cards.
pub(crate) fn read_text(text: &str) -> Result<Vec<DmigMatrix>, PunchError> {
    let mut heads: Vec<(String, Head)> = Vec::new();
    let mut entries: HashMap<String, Vec<Entry>> = HashMap::new();
    let mut columns: Vec<(String, Card)> = Vec::new();
    for card in dmig_cards(text) {
        let name = card
            .fields
            .first()
            .cloned()
            .unwrap_or_default()
            .to_ascii_uppercase();
        if name.is_empty() {
            return Err((card.line, name, "card without a matrix name".into()));
        }
        let err = |e: String| (card.line, name.clone(), e);
        if card.fields.get(1).map(String::as_str) == Some("0") {
            if heads.iter().any(|(n, _)| *n == name) {
                return Err(err("second header card for the same matrix".into()));
            }
            let f = &card.fields;
            // Fields 2..9 make the whole header; a continuation with data after them is the
            // rest of a column card whose first line is missing (it would be dropped).
            if let Some(k) = (8..f.len()).find(|&k| !f[k].is_empty()) {
                return Err((
                    card.field_lines[k],
                    name.clone(),
                    format!(
                        "continuation line with `{}` after the header card (line {}), which has \
                         no continuation: the first line of a column card is missing",
                        f[k], card.line
                    ),
                ));
            }
            let ifo = int_field(f, 2, "IFO", None).map_err(err)?;
            if ![1, 2, 6, 9].contains(&ifo) {
                return Err(err(format!("IFO = {ifo} is not 1, 2, 6 or 9")));
            }
            let tin = int_field(f, 3, "TIN", None).map_err(err)?;
            let precision = Precision::from_code(tin)
                .ok_or_else(|| err(format!("TIN = {tin} is not 1, 2, 3 or 4")))?;
            let polar = int_field(f, 5, "POLAR", Some(0)).map_err(err)? != 0;
            let ncol = int_field(f, 7, "NCOL", Some(0)).map_err(err)?;
            heads.push((
                name,
                Head {
                    line: card.line,
                    ifo,
                    precision,
                    polar,
                    ncol,
                },
            ));
        } else {
            columns.push((name, card));
        }
    }
    for (name, card) in columns {
        let head = heads
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, h)| h)
            .ok_or_else(|| {
                (
                    card.line,
                    name.clone(),
                    "column card before (or without) a header card".to_string(),
                )
            })?;
        let list = entries.entry(name.clone()).or_default();
        parse_column(&card, head, list).map_err(|e| (card.line, name.clone(), e))?;
    }
    heads
        .into_iter()
        .map(|(name, head)| {
            let list = entries.remove(&name).unwrap_or_default();
            assemble(&name, &head, &list).map_err(|(l, e)| (l, name.clone(), e))
        })
        .collect()
}

fn dof(grid: i64, comp: i64) -> Result<Dof, String> {
    if grid < 1 || !(0..=6).contains(&comp) {
        return Err(format!(
            "({grid}, {comp}) is not a grid/scalar point and component 0..6"
        ));
    }
    Ok((grid as u64, comp as u8))
}

fn parse_column(card: &Card, head: &Head, out: &mut Vec<Entry>) -> Result<(), String> {
    let f = &card.fields;
    let gj = int_field(f, 1, "GJ", None)?;
    let cj = int_field(f, 2, "CJ", Some(0))?;
    let col = dof(gj, cj)?;
    let complex = head.precision.is_complex();
    for (g, group) in f.get(4..).unwrap_or(&[]).chunks(4).enumerate() {
        if group.iter().all(String::is_empty) {
            continue;
        }
        let at = 4 + 4 * g;
        let gi = int_field(f, at, "GI", None)?;
        let ci = int_field(f, at + 1, "CI", Some(0))?;
        let real = |k: usize, what: &str| -> Result<f64, String> {
            let s = f.get(at + k).map(String::as_str).unwrap_or("");
            parse_real(s).ok_or_else(|| {
                format!(
                    "{what} (field {}) `{s}` of row ({gi}, {ci}) is not a finite real",
                    at + k + 2
                )
            })
        };
        let a = real(2, "A")?;
        let value = if complex {
            let b = real(3, "B")?;
            if head.polar {
                Cplx::from_polar(a, b.to_radians())
            } else {
                Cplx::new(a, b)
            }
        } else {
            if f.get(at + 3).is_some_and(|s| !s.is_empty()) {
                return Err(format!(
                    "imaginary part given for row ({gi}, {ci}) of a real matrix (TIN {})",
                    head.precision.code()
                ));
            }
            Cplx::new(a, 0.0)
        };
        out.push(Entry {
            line: card.line,
            row: dof(gi, ci)?,
            col,
            value,
        });
    }
    Ok(())
}

fn assemble(name: &str, head: &Head, list: &[Entry]) -> Result<DmigMatrix, (usize, String)> {
    let sorted = |it: &mut dyn Iterator<Item = Dof>| -> Vec<Dof> {
        it.collect::<BTreeSet<_>>().into_iter().collect()
    };
    let (rows, cols, form) = match head.ifo {
        1 | 6 => {
            let all = sorted(&mut list.iter().flat_map(|e| [e.row, e.col]));
            let form = if head.ifo == 1 {
                MatrixForm::Square
            } else {
                MatrixForm::Symmetric
            };
            (all.clone(), all, form)
        }
        2 => (
            sorted(&mut list.iter().map(|e| e.row)),
            sorted(&mut list.iter().map(|e| e.col)),
            MatrixForm::Rectangular,
        ),
        _ => {
            if let Some(e) = list
                .iter()
                .find(|e| e.col.1 != 0 || e.col.0 as i64 > head.ncol)
            {
                return Err((
                    e.line,
                    format!(
                        "IFO 9 column ({}, {}) is not a column number 1..={} with component 0",
                        e.col.0, e.col.1, head.ncol
                    ),
                ));
            }
            let cols = (1..=head.ncol.max(0) as u64).map(|k| (k, 0)).collect();
            (
                sorted(&mut list.iter().map(|e| e.row)),
                cols,
                MatrixForm::PseudoIdentity,
            )
        }
    };
    let (m, n) = (rows.len(), cols.len());
    if m.saturating_mul(n) > crate::op4::MAX_DENSE_ENTRIES {
        return Err((
            head.line,
            format!("{m} x {n} matrix exceeds the dense size limit"),
        ));
    }
    let ri: BTreeMap<Dof, usize> = rows.iter().enumerate().map(|(k, d)| (*d, k)).collect();
    let ci: BTreeMap<Dof, usize> = cols.iter().enumerate().map(|(k, d)| (*d, k)).collect();
    let mut a = Mat::<Cplx>::zeros(m, n);
    // Value, line and whether it was placed as the mirror of a symmetric entry.
    let mut given: HashMap<(usize, usize), (Cplx, usize, bool)> = HashMap::new();
    for e in list {
        let (i, j) = (ri[&e.row], ci[&e.col]);
        let v = e.value;
        let mut places = vec![(i, j)];
        if head.ifo == 6 && i != j {
            places.push((j, i));
        }
        for (p, q) in places {
            let mirror = (p, q) != (i, j);
            if let Some(&(old, line, old_mirror)) = given.get(&(p, q)) {
                if old != v {
                    let what = if mirror || old_mirror {
                        "given in both triangles"
                    } else {
                        "given twice"
                    };
                    return Err((e.line, format!(
                        "entry row ({}, {}) column ({}, {}) {what} with different values: {} (line {line}) and {}",
                        e.row.0, e.row.1, e.col.0, e.col.1, fmt_c(old), fmt_c(v))));
                }
            }
            given.insert((p, q), (v, e.line, mirror));
            a[(p, q)] = v;
        }
    }
    let data = if head.precision.is_complex() {
        MatrixData::Complex(a)
    } else {
        MatrixData::Real(Mat::from_fn(m, n, |i, j| a[(i, j)].re))
    };
    let matrix = NamedMatrix {
        name: name.to_string(),
        nrows: m,
        ncols: n,
        form,
        precision: head.precision,
        data,
    };
    Ok(DmigMatrix { matrix, rows, cols })
}

fn fmt_c(z: Cplx) -> String {
    if z.im == 0.0 {
        format!("{}", z.re)
    } else {
        format!("{}{:+}i", z.re, z.im)
    }
}
