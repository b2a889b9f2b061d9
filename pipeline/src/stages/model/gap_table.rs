//! The gap table of a stored model: CSV with a header naming its columns, or JSON (a `GapSet`
//! as `squeal reduce` writes it, or a list of gaps).
//!
//! CSV columns are read by name, in any order: `pad_grid, rotor_grid, x, y, z, nx, ny, nz,
//! area, p0, temperature`, all required; an unknown, missing or repeated column is an error
//! naming it. The first line must be that header: a first line of numbers is an error (read
//! by position it could swap pad and rotor, and read as a header it would lose a gap). The
//! normal (nx, ny, nz) is normalised.
//!
//! Every gap is checked, in both formats: coordinates and temperature finite, normal finite and
//! nonzero (a unit vector in JSON, which is used as written), area finite and > 0, P0 finite and
//! ≥ 0 (a compressive preload pressure, [Paper eq. (1)]: a negative one would make the
//! friction force drive the slip), pad and rotor grids different, and no pad grid twice (a
//! repeated gap doubles its area). Errors name the file, the line (CSV) or gap index (JSON),
//! the column and the value: `gaps.csv: line 3, column `area`: -0.5 must be > 0`.

use crate::error::PipelineError;
use squeal_contact::{Gap, GapSet};
use std::collections::HashMap;
use std::path::Path;

type Real = f64;

/// The CSV columns, all required.
pub const GAP_COLUMNS: [&str; 11] = [
    "pad_grid",
    "rotor_grid",
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "area",
    "p0",
    "temperature",
];

/// Reads and checks a gap table (CSV by its `.csv` extension, else JSON).
pub fn read_gaps(path: &Path) -> Result<Vec<Gap>, PipelineError> {
    let text = std::fs::read_to_string(path).map_err(|source| PipelineError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let bad = |message: String| PipelineError::Input {
        path: path.to_path_buf(),
        message,
    };
    let csv = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let (gaps, places) = if csv {
        parse_csv(&text).map_err(bad)?
    } else {
        let gaps = match serde_json::from_str::<GapSet>(&text) {
            Ok(set) => set.gaps,
            Err(_) => serde_json::from_str::<Vec<Gap>>(&text)
                .map_err(|e| bad(format!("not a gap table (GapSet or list of gaps): {e}")))?,
        };
        let places = (0..gaps.len()).map(|i| format!("gap {i}")).collect();
        (gaps, places)
    };
    check_gaps(&gaps, &places, !csv, true).map_err(bad)?;
    Ok(gaps)
}

/// Parses the CSV text: the gaps and, for each, where it was read ("line N").
fn parse_csv(text: &str) -> Result<(Vec<Gap>, Vec<String>), String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_start_matches('\u{feff}').trim()))
        .filter(|(_, l)| !l.is_empty());
    let (hl, header) = lines
        .next()
        .ok_or_else(|| format!("empty; expected the header `{}`", GAP_COLUMNS.join(",")))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    if names.iter().all(|f| f.parse::<Real>().is_ok()) {
        return Err(format!(
            "line {hl}: `{header}` is data, not a header; the first line must name the columns \
             (`{}`, in any order)",
            GAP_COLUMNS.join(",")
        ));
    }
    let mut column: HashMap<&str, usize> = HashMap::new();
    for (i, name) in names.iter().enumerate() {
        if !GAP_COLUMNS.contains(name) {
            return Err(format!(
                "line {hl}, column {}: unknown column `{name}` (the columns are {})",
                i + 1,
                GAP_COLUMNS.join(", ")
            ));
        }
        if let Some(first) = column.insert(name, i) {
            return Err(format!(
                "line {hl}: column `{name}` appears twice (columns {} and {})",
                first + 1,
                i + 1
            ));
        }
    }
    let missing: Vec<&str> = GAP_COLUMNS
        .iter()
        .copied()
        .filter(|c| !column.contains_key(c))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "line {hl}: missing column(s) `{}` in the header",
            missing.join("`, `")
        ));
    }
    let mut gaps = Vec::new();
    let mut places = Vec::new();
    for (ln, line) in lines {
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        if f.len() != names.len() {
            return Err(format!(
                "line {ln}: {} fields, the header has {}",
                f.len(),
                names.len()
            ));
        }
        let at = |c: &str| f[column[c]];
        let num = |c: &str| -> Result<Real, String> {
            at(c)
                .parse()
                .map_err(|_| format!("line {ln}, column `{c}`: `{}` is not a number", at(c)))
        };
        let id = |c: &str| -> Result<u64, String> {
            at(c)
                .parse()
                .map_err(|_| format!("line {ln}, column `{c}`: `{}` is not a grid id", at(c)))
        };
        let nrm = [num("nx")?, num("ny")?, num("nz")?];
        let len = nrm.iter().map(|x| x * x).sum::<Real>().sqrt();
        if !(len > 0.0 && len.is_finite()) {
            return Err(format!(
                "line {ln}, columns `nx, ny, nz`: normal {nrm:?} is zero or not finite"
            ));
        }
        gaps.push(Gap {
            pad_node: id("pad_grid")?,
            rotor_node: id("rotor_grid")?,
            coords: [num("x")?, num("y")?, num("z")?],
            pad_dofs: [None; 3],
            rotor_dofs: [None; 3],
            normal: nrm.map(|x| x / len),
            area: num("area")?,
            v_slide: [0.0; 3],
            p0: num("p0")?,
            temperature: num("temperature")?,
            tie: None,
        });
        places.push(format!("line {ln}"));
    }
    Ok((gaps, places))
}

/// The value checks of the module documentation; `places[i]` says where gap i was read;
/// `unique_pads`: the same gap (pad grid, rotor grid, normal) twice is an error.
pub(crate) fn check_gaps(
    gaps: &[Gap],
    places: &[String],
    unit_normal: bool,
    unique_pads: bool,
) -> Result<(), String> {
    // Every earlier gap of each pad grid (a pad grid may carry several).
    let mut pads: HashMap<u64, Vec<usize>> = HashMap::new();
    for (i, g) in gaps.iter().enumerate() {
        let at = &places[i];
        for (c, v) in ["x", "y", "z"].iter().zip(g.coords) {
            if !v.is_finite() {
                return Err(format!("{at}, column `{c}`: {v} must be finite"));
            }
        }
        let len = g.normal.iter().map(|x| x * x).sum::<Real>().sqrt();
        if !(len.is_finite() && len > 0.0) {
            return Err(format!(
                "{at}, `normal`: {:?} is zero or not finite",
                g.normal
            ));
        }
        if unit_normal && (len - 1.0).abs() > 1e-6 {
            return Err(format!(
                "{at}, `normal`: {:?} has length {len}; it must be a unit vector",
                g.normal
            ));
        }
        if !(g.area.is_finite() && g.area > 0.0) {
            return Err(format!(
                "{at}, column `area`: {} must be finite and > 0",
                g.area
            ));
        }
        if !(g.p0.is_finite() && g.p0 >= 0.0) {
            return Err(format!(
                "{at}, column `p0`: {} must be finite and >= 0 (a compressive preload pressure)",
                g.p0
            ));
        }
        if !g.temperature.is_finite() {
            return Err(format!(
                "{at}, column `temperature`: {} must be finite",
                g.temperature
            ));
        }
        if g.pad_node == g.rotor_node {
            return Err(format!(
                "{at}: pad grid and rotor grid are both {}",
                g.pad_node
            ));
        }
        // A pad grid may carry several gaps (e.g. two faces at a corner), but the same
        // pad/rotor pair with the same normal twice is one constraint written twice: G would
        // lose rank and a multiplier would be undetermined.
        let earlier = pads.entry(g.pad_node).or_default();
        if unique_pads {
            // Same direction to round-off (|n̂_a − n̂_b| ≤ 1e-12): normals 1e-6 rad apart are a
            // nearly redundant pair the solver must handle, not a duplicate. Checked against
            // every earlier gap of the pad grid, not only the last (fuzzing found a duplicate
            // with another gap of the same pad grid between them).
            let twice = earlier.iter().copied().find(|&first| {
                let f = &gaps[first];
                let (na, nb) = (norm3(f.normal), norm3(g.normal));
                let apart = (0..3)
                    .map(|k| (f.normal[k] / na - g.normal[k] / nb).powi(2))
                    .sum::<Real>()
                    .sqrt();
                f.rotor_node == g.rotor_node && apart <= 1e-12
            });
            if let Some(first) = twice {
                return Err(format!(
                    "{at}: pad grid {} already has this gap ({}): the same pad grid, rotor grid \
                     {} and normal twice",
                    g.pad_node, places[first], g.rotor_node
                ));
            }
        }
        earlier.push(i);
    }
    Ok(())
}

fn norm3(v: [Real; 3]) -> Real {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
