//! The gap table of a stored model: CSV with a header naming its columns, or JSON (a `GapSet`
//! as `squeal reduce` writes it, or a list of gaps).
//!
//! CSV columns are read by name, in any order: `pad_grid, rotor_grid, x, y, z, nx, ny, nz,
//! area, p0, temperature`, all required; an unknown, missing or repeated column is an error
//! naming it. A surface-paired table (`[[contact]] pairing = "surface"`) adds the five
//! columns of [`TIE_COLUMNS`]: `face` (the face's index in the rotor face set), `xi`, `eta`
//! (its face coordinates), `face_grids` (the face's 4 or 8 grids, space-separated, in the
//! face's order: corners counterclockwise, then mid-sides) and `weights` (the shape-function
//! values N_a(ξ, η) of those grids, space-separated). All five or none: a table without them
//! pairs coincident grids (weight 1 on `rotor_grid`); a row with an empty `face` is such a
//! pair in a tied table. The weights must be the face's shape functions at (ξ, η) to 1e-9
//! (they then sum to 1: G rows sum to zero), and `rotor_grid` must be the face grid of
//! largest weight. A mortar table on quadratic pad faces adds the two columns of
//! [`PAD_COLUMNS`], `pad_grids` and `pad_weights` (the gap's pad side û = Σ w_k u_k, empty
//! for a gap on its pad grid alone). The first line must be that header: a first line of numbers is an error (read
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
use squeal_contact::{FaceKind, FaceTie, Gap, GapSet, PadSide};
use std::collections::HashMap;
use std::path::Path;

use squeal_solver::Real;

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

/// The optional columns of a surface-paired gap table (all five or none).
pub const TIE_COLUMNS: [&str; 5] = ["face", "xi", "eta", "face_grids", "weights"];

/// The optional columns of a table whose gaps have a pad side over several pad grids (mortar
/// on quadratic pad faces; both or none): the grids and their weights, space-separated.
pub const PAD_COLUMNS: [&str; 2] = ["pad_grids", "pad_weights"];

/// The gap table as CSV (the columns of [`GAP_COLUMNS`], and those of [`TIE_COLUMNS`] when a
/// gap is tied to a face); numbers in Rust's shortest round-trip form, so reading it back
/// gives the same gaps (sliding velocities and DOFs are not stored).
pub fn gaps_csv(gaps: &[Gap]) -> String {
    let tied = gaps.iter().any(|g| g.tie.is_some());
    let sided = gaps.iter().any(|g| g.pad_side.is_some());
    let mut out = GAP_COLUMNS.join(",");
    if tied {
        out.push(',');
        out.push_str(&TIE_COLUMNS.join(","));
    }
    if sided {
        out.push(',');
        out.push_str(&PAD_COLUMNS.join(","));
    }
    out.push('\n');
    for g in gaps {
        let row = [
            g.pad_node.to_string(),
            g.rotor_node.to_string(),
            format!("{:?}", g.coords[0]),
            format!("{:?}", g.coords[1]),
            format!("{:?}", g.coords[2]),
            format!("{:?}", g.normal[0]),
            format!("{:?}", g.normal[1]),
            format!("{:?}", g.normal[2]),
            format!("{:?}", g.area),
            format!("{:?}", g.p0),
            format!("{:?}", g.temperature),
        ];
        out.push_str(&row.join(","));
        if tied {
            match &g.tie {
                Some(t) => {
                    let ids: Vec<String> = t.nodes.iter().map(|n| n.to_string()).collect();
                    let ws: Vec<String> = t.weights.iter().map(|w| format!("{w:?}")).collect();
                    // A mortar tie's face is written `mortar:<face>` (its grids are any
                    // rotor grids of non-zero mortar weight).
                    let face = if t.mortar {
                        format!("mortar:{}", t.face)
                    } else {
                        t.face.to_string()
                    };
                    out.push_str(&format!(
                        ",{},{:?},{:?},{},{}",
                        face,
                        t.xi[0],
                        t.xi[1],
                        ids.join(" "),
                        ws.join(" ")
                    ));
                }
                None => out.push_str(",,,,,"),
            }
        }
        if sided {
            match &g.pad_side {
                Some(p) => {
                    let ids: Vec<String> = p.nodes.iter().map(|n| n.to_string()).collect();
                    let ws: Vec<String> = p.weights.iter().map(|w| format!("{w:?}")).collect();
                    out.push_str(&format!(",{},{}", ids.join(" "), ws.join(" ")));
                }
                None => out.push_str(",,"),
            }
        }
        out.push('\n');
    }
    out
}

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
        if !GAP_COLUMNS.contains(name) && !TIE_COLUMNS.contains(name) && !PAD_COLUMNS.contains(name)
        {
            return Err(format!(
                "line {hl}, column {}: unknown column `{name}` (the columns are {}; a \
                 surface-paired table adds {}, and {})",
                i + 1,
                GAP_COLUMNS.join(", "),
                TIE_COLUMNS.join(", "),
                PAD_COLUMNS.join(", ")
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
    let n_tie = TIE_COLUMNS
        .iter()
        .filter(|c| column.contains_key(*c))
        .count();
    if n_tie != 0 && n_tie != TIE_COLUMNS.len() {
        let missing: Vec<&str> = TIE_COLUMNS
            .iter()
            .copied()
            .filter(|c| !column.contains_key(c))
            .collect();
        return Err(format!(
            "line {hl}: a surface-paired table has all of the columns `{}`; missing `{}`",
            TIE_COLUMNS.join("`, `"),
            missing.join("`, `")
        ));
    }
    let tied = n_tie > 0;
    let sided = match PAD_COLUMNS.map(|c| column.contains_key(c)) {
        [true, true] => true,
        [false, false] => false,
        _ => {
            return Err(format!(
                "line {hl}: a table with pad sides has both columns `{}`",
                PAD_COLUMNS.join("`, `")
            ))
        }
    };
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
            tie: if tied && !at("face").is_empty() {
                Some(read_tie(ln, &f, &column)?)
            } else {
                None
            },
            rotor_rows: Vec::new(),
            pad_side: if sided && !at("pad_grids").is_empty() {
                Some(read_pad_side(ln, &f, &column)?)
            } else {
                None
            },
            friction: None,
        });
        places.push(format!("line {ln}"));
    }
    Ok((gaps, places))
}

/// The pad-side columns of CSV line `ln` (fields `f`, column index by name).
fn read_pad_side(ln: usize, f: &[&str], column: &HashMap<&str, usize>) -> Result<PadSide, String> {
    let at = |c: &str| f[column[c]];
    let nodes = at("pad_grids")
        .split_whitespace()
        .map(|x| {
            x.parse::<u64>()
                .map_err(|_| format!("line {ln}, column `pad_grids`: `{x}` is not a grid id"))
        })
        .collect::<Result<Vec<u64>, String>>()?;
    let weights = at("pad_weights")
        .split_whitespace()
        .map(|x| {
            x.parse::<Real>()
                .map_err(|_| format!("line {ln}, column `pad_weights`: `{x}` is not a number"))
        })
        .collect::<Result<Vec<Real>, String>>()?;
    Ok(PadSide {
        nodes,
        weights,
        dofs: Vec::new(),
    })
}

/// The tie columns of CSV line `ln` (fields `f`, column index by name).
fn read_tie(ln: usize, f: &[&str], column: &HashMap<&str, usize>) -> Result<FaceTie, String> {
    let at = |c: &str| f[column[c]];
    let num = |c: &str| -> Result<Real, String> {
        at(c)
            .parse()
            .map_err(|_| format!("line {ln}, column `{c}`: `{}` is not a number", at(c)))
    };
    let (mortar, face_text) = match at("face").strip_prefix("mortar:") {
        Some(rest) => (true, rest),
        None => (false, at("face")),
    };
    let face = face_text.parse::<u64>().map_err(|_| {
        format!(
            "line {ln}, column `face`: `{}` is not a face index (or `mortar:` and one)",
            at("face")
        )
    })?;
    let nodes = at("face_grids")
        .split_whitespace()
        .map(|x| {
            x.parse::<u64>()
                .map_err(|_| format!("line {ln}, column `face_grids`: `{x}` is not a grid id"))
        })
        .collect::<Result<Vec<u64>, String>>()?;
    let weights = at("weights")
        .split_whitespace()
        .map(|x| {
            x.parse::<Real>()
                .map_err(|_| format!("line {ln}, column `weights`: `{x}` is not a number"))
        })
        .collect::<Result<Vec<Real>, String>>()?;
    let kind = if mortar {
        FaceKind::Quad4
    } else {
        FaceKind::from_n_nodes(nodes.len()).ok_or_else(|| {
            format!(
                "line {ln}, column `face_grids`: {} grids; a face has 3 (tri3), 4 (quad4), 6 \
                 (tri6) or 8 (quad8)",
                nodes.len()
            )
        })?
    };
    Ok(FaceTie {
        face,
        kind,
        xi: [num("xi")?, num("eta")?],
        nodes,
        weights,
        distance: 0.0,
        dofs: Vec::new(),
        mortar,
        coords: Vec::new(),
    })
}

/// Checks a tied gap: weights = the face's shape functions at (ξ, η) to 1e-9 (so they sum to
/// one), `rotor_grid` the face grid of largest weight, the pad grid not on the face.
fn check_tie(g: &Gap, t: &FaceTie, at: &str) -> Result<(), String> {
    let nn = t.kind.n_nodes();
    if t.mortar {
        // Mortar weights: any rotor grids, finite, summing to one.
        let sum: Real = t.weights.iter().sum();
        if t.nodes.is_empty() || t.nodes.len() != t.weights.len() || !(sum - 1.0).abs().le(&1e-9) {
            return Err(format!(
                "{at}, columns `face_grids, weights`: a mortar tie needs as many weights as \
                 grids (found {} and {}), summing to 1 (sum {sum})",
                t.nodes.len(),
                t.weights.len()
            ));
        }
    } else if t.nodes.len() != nn || t.weights.len() != nn {
        return Err(format!(
            "{at}: a {:?} face has {nn} grids and weights, found {} grids and {} weights",
            t.kind,
            t.nodes.len(),
            t.weights.len()
        ));
    }
    if !(t.xi[0].is_finite() && t.xi[1].is_finite()) {
        return Err(format!(
            "{at}, columns `xi, eta`: {:?} must be finite",
            t.xi
        ));
    }
    let (n, _) = t.kind.shape(t.xi);
    for a in (0..nn).filter(|_| !t.mortar) {
        let diff = (t.weights[a] - n[a]).abs();
        if diff.is_nan() || diff > 1e-9 {
            return Err(format!(
                "{at}, column `weights`: weight {} of grid {} is {}, but the {:?} shape \
                 function at (xi, eta) = ({}, {}) is {} (the weights must be N_a(xi, eta))",
                a + 1,
                t.nodes[a],
                t.weights[a],
                t.kind,
                t.xi[0],
                t.xi[1],
                n[a]
            ));
        }
    }
    let wmax = t
        .weights
        .iter()
        .copied()
        .fold(Real::NEG_INFINITY, Real::max);
    let main = t
        .nodes
        .iter()
        .zip(&t.weights)
        .find(|(_, &w)| w == wmax)
        .map(|(&n, _)| n);
    if !t
        .nodes
        .iter()
        .zip(&t.weights)
        .any(|(&n, &w)| n == g.rotor_node && w == wmax)
    {
        return Err(format!(
            "{at}, column `rotor_grid`: {} must be the face grid of largest weight ({})",
            g.rotor_node,
            main.unwrap_or_default()
        ));
    }
    if t.nodes.contains(&g.pad_node) {
        return Err(format!(
            "{at}: pad grid {} is also a grid of its rotor face",
            g.pad_node
        ));
    }
    Ok(())
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
        if let Some(t) = &g.tie {
            check_tie(g, t, at)?;
        }
        if let Some(p) = &g.pad_side {
            let sum: Real = p.weights.iter().sum();
            if p.nodes.len() != p.weights.len()
                || !p.nodes.contains(&g.pad_node)
                || !(sum - 1.0).abs().le(&1e-9)
            {
                return Err(format!(
                    "{at}, columns `pad_grids, pad_weights`: a pad side needs as many weights as \
                     grids (found {} and {}), the pad grid {} among them, and weights summing \
                     to 1 (sum {sum})",
                    p.nodes.len(),
                    p.weights.len(),
                    g.pad_node
                ));
            }
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
