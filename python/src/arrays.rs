//! numpy ↔ faer matrices, and the DOF map and gap table as records (lists of dicts, or a
//! pandas DataFrame) in both directions.

use crate::errors::InputError;
use numpy::ndarray::Array2;
use numpy::{AllowTypeChange, IntoPyArray, PyArray2, PyArrayLike1, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use squeal_contact::{FaceKind, FaceTie, Gap, PadSide};
use squeal_pipeline::stages::model::gap_table::{GAP_COLUMNS, PAD_COLUMNS, TIE_COLUMNS};
use squeal_reduction::superelement::{DofKind, ReducedDof, ReducedDofMap};

use squeal_solver::Real;

/// A complex array is refused unless every imaginary part is 0 (then its real part is exact):
/// squeal's K, M, B are real. A structural damping K(1 + iη) has no place in the transient
/// (a time-domain model needs a viscous form) and would otherwise lose its imaginary part to
/// numpy's cast, with only a ComplexWarning.
fn refuse_complex(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<()> {
    let np = obj.py().import("numpy")?;
    if !np.call_method1("iscomplexobj", (obj,))?.is_truthy()? {
        return Ok(());
    }
    let a = np.call_method1("asarray", (obj,))?;
    let abs_max = |x: Bound<'_, PyAny>| -> PyResult<f64> {
        let m = np.call_method1("abs", (x,))?;
        if m.getattr("size")?.extract::<usize>()? == 0 {
            return Ok(0.0);
        }
        m.call_method0("max")?.extract::<f64>()
    };
    let im = abs_max(a.getattr("imag")?)?;
    if im == 0.0 {
        return Ok(());
    }
    let re = abs_max(a.getattr("real")?)?;
    let at: Vec<usize> = np
        .call_method1(
            "unravel_index",
            (
                np.call_method1("argmax", (np.call_method1("abs", (a.getattr("imag")?,))?,))?,
                a.getattr("shape")?,
            ),
        )?
        .extract()?;
    Err(InputError::new_err(format!(
        "<arrays>.{name}: complex entries (largest |Im| = {im:e} at {at:?}, {:.3e} of the \
         largest |Re| = {re:e}): squeal's K, M and B are real. A structural damping \
         K(1 + i eta) is not supported (the transient is in the time domain): give its \
         viscous equivalent as B = (eta / omega) K at a reference angular frequency omega, \
         as NASTRAN's GE/W4 does",
        if re > 0.0 { im / re } else { f64::INFINITY }
    )))
}

/// A 2-D float array (anything numpy converts) as a faer matrix; complex entries are refused
/// ([`refuse_complex`]).
pub fn mat_from_py(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<faer::Mat<Real>> {
    refuse_complex(obj, name)?;
    let a: PyArrayLike2<'_, Real, AllowTypeChange> = obj.extract().map_err(|e| {
        InputError::new_err(format!("<arrays>.{name}: not a 2-D float array ({e})"))
    })?;
    let v = a.as_array();
    Ok(faer::Mat::from_fn(v.nrows(), v.ncols(), |i, j| v[[i, j]]))
}

/// A 1-D float array as a vector.
pub fn vec_from_py(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Real>> {
    refuse_complex(obj, name)?;
    let a: PyArrayLike1<'_, Real, AllowTypeChange> = obj.extract().map_err(|e| {
        InputError::new_err(format!("<arrays>.{name}: not a 1-D float array ({e})"))
    })?;
    Ok(a.as_array().to_vec())
}

/// A faer matrix as a numpy array (copied).
pub fn mat_to_py<'py>(py: Python<'py>, m: &faer::Mat<Real>) -> Bound<'py, PyArray2<Real>> {
    Array2::from_shape_fn((m.nrows(), m.ncols()), |(i, j)| m[(i, j)]).into_pyarray(py)
}

/// Rows of records: a DataFrame (`to_dict("records")`) or any iterable of mappings.
fn records<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let obj = if obj.hasattr("to_dict")? && !obj.is_instance_of::<PyDict>() {
        obj.call_method1("to_dict", ("records",))?
    } else {
        obj.clone()
    };
    obj.try_iter()?.collect()
}

fn field<'py>(
    row: &Bound<'py, PyAny>,
    key: &str,
    what: &str,
    i: usize,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let has = row
        .call_method1("__contains__", (key,))
        .map_err(|_| InputError::new_err(format!("<arrays>.{what}: row {i} is not a mapping")))?;
    if !has.extract::<bool>()? {
        return Ok(None);
    }
    let v = row.get_item(key)?;
    // pandas fills absent values of a column with None or NaN.
    let missing = v.is_none() || v.extract::<f64>().is_ok_and(|x| x.is_nan());
    Ok(if missing { None } else { Some(v) })
}

fn bad(what: &str, i: usize, key: &str, msg: impl std::fmt::Display) -> PyErr {
    InputError::new_err(format!("<arrays>.{what}: row {i}, key `{key}`: {msg}"))
}

/// The DOF map from records `{component, kind: "grid"|"modal", grid, comp | index,
/// shared_with}` (what `squeal.reduce` returns).
pub fn dofmap_from_py(obj: &Bound<'_, PyAny>) -> PyResult<ReducedDofMap> {
    let mut dofs = Vec::new();
    for (i, row) in records(obj)?.iter().enumerate() {
        let get = |k: &str| field(row, k, "dofs", i);
        let req = |k: &str| get(k)?.ok_or_else(|| bad("dofs", i, k, "missing"));
        let component: String = req("component")?
            .extract()
            .map_err(|e| bad("dofs", i, "component", e))?;
        let kind: String = req("kind")?
            .extract()
            .map_err(|e| bad("dofs", i, "kind", e))?;
        let int = |k: &str| -> PyResult<u64> {
            let v = req(k)?;
            v.extract::<u64>()
                .or_else(|_| {
                    v.extract::<f64>()
                        .ok()
                        .filter(|x| x.fract() == 0.0 && *x >= 0.0)
                        .map(|x| x as u64)
                        .ok_or(())
                })
                .map_err(|_| bad("dofs", i, k, format!("{v} is not a non-negative integer")))
        };
        let kind = match kind.as_str() {
            "grid" => {
                let comp = int("comp")?;
                if !(1..=6).contains(&comp) {
                    return Err(bad("dofs", i, "comp", format!("{comp} is not in 1..=6")));
                }
                DofKind::Grid {
                    grid: int("grid")?,
                    comp: comp as u8,
                }
            }
            "modal" => DofKind::Modal {
                index: int("index")? as usize,
            },
            "interface" => DofKind::Interface {
                index: int("index")? as usize,
            },
            other => {
                return Err(bad(
                    "dofs",
                    i,
                    "kind",
                    format!("`{other}`: expected `grid`, `modal` or `interface`"),
                ))
            }
        };
        let shared_with: Vec<String> = match get("shared_with")? {
            Some(v) => v.extract().map_err(|e| bad("dofs", i, "shared_with", e))?,
            None => Vec::new(),
        };
        dofs.push(ReducedDof {
            component,
            shared_with,
            kind,
        });
    }
    Ok(ReducedDofMap::new(dofs))
}

/// The DOF map as records.
pub fn dofmap_to_py<'py>(py: Python<'py>, map: &ReducedDofMap) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for d in &map.dofs {
        let r = PyDict::new(py);
        r.set_item("component", &d.component)?;
        let (kind, grid, comp, index) = match d.kind {
            DofKind::Grid { grid, comp } => ("grid", Some(grid), Some(comp), None),
            DofKind::Modal { index } => ("modal", None, None, Some(index)),
            DofKind::Interface { index } => ("interface", None, None, Some(index)),
        };
        r.set_item("kind", kind)?;
        r.set_item("grid", grid)?;
        r.set_item("comp", comp)?;
        r.set_item("index", index)?;
        r.set_item("shared_with", d.shared_with.clone())?;
        out.append(r)?;
    }
    Ok(out)
}

/// Extra gap columns `squeal.reduce` returns and `from_arrays` ignores (the sliding velocity
/// is the scene's `[rotor]` ω × r).
const DERIVED_GAP_COLUMNS: [&str; 3] = ["vx_slide", "vy_slide", "vz_slide"];

/// The gap table from records with the CSV gap table's columns (`pad_grid, rotor_grid, x, y,
/// z, nx, ny, nz, area, p0, temperature`); the values are checked when the model is built.
pub fn gaps_from_py(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Gap>> {
    let mut gaps = Vec::new();
    for (i, row) in records(obj)?.iter().enumerate() {
        if let Ok(d) = row.cast::<PyDict>() {
            for k in d.keys() {
                let k: String = k.extract()?;
                if !GAP_COLUMNS.contains(&k.as_str())
                    && !DERIVED_GAP_COLUMNS.contains(&k.as_str())
                    && !TIE_COLUMNS.contains(&k.as_str())
                    && !PAD_COLUMNS.contains(&k.as_str())
                    && k != "mortar"
                {
                    return Err(bad(
                        "gaps",
                        i,
                        &k,
                        format!(
                            "unknown column (the columns are {})",
                            GAP_COLUMNS.join(", ")
                        ),
                    ));
                }
            }
        }
        let req = |k: &str| field(row, k, "gaps", i)?.ok_or_else(|| bad("gaps", i, k, "missing"));
        let num = |k: &str| -> PyResult<Real> {
            let v = req(k)?;
            v.extract::<Real>()
                .map_err(|_| bad("gaps", i, k, format!("{v} is not a number")))
        };
        let id = |k: &str| -> PyResult<u64> {
            let v = req(k)?;
            v.extract::<u64>()
                .map_err(|_| bad("gaps", i, k, format!("{v} is not a grid id")))
        };
        gaps.push(Gap {
            pad_node: id("pad_grid")?,
            rotor_node: id("rotor_grid")?,
            coords: [num("x")?, num("y")?, num("z")?],
            pad_dofs: [None; 3],
            rotor_dofs: [None; 3],
            normal: [num("nx")?, num("ny")?, num("nz")?],
            area: num("area")?,
            v_slide: [0.0; 3],
            p0: num("p0")?,
            temperature: num("temperature")?,
            tie: match field(row, "face", "gaps", i)? {
                None => None,
                Some(face) => {
                    let face = face.extract::<u64>().map_err(|_| {
                        bad("gaps", i, "face", format!("{face} is not a face index"))
                    })?;
                    let nodes: Vec<u64> = req("face_grids")?
                        .extract()
                        .map_err(|_| bad("gaps", i, "face_grids", "not a list of grid ids"))?;
                    let weights: Vec<Real> = req("weights")?
                        .extract()
                        .map_err(|_| bad("gaps", i, "weights", "not a list of numbers"))?;
                    let mortar = match field(row, "mortar", "gaps", i)? {
                        None => false,
                        Some(v) => v
                            .extract::<bool>()
                            .map_err(|_| bad("gaps", i, "mortar", format!("{v} is not a bool")))?,
                    };
                    let kind = if mortar {
                        FaceKind::Quad4
                    } else {
                        FaceKind::from_n_nodes(nodes.len()).ok_or_else(|| {
                            bad(
                                "gaps",
                                i,
                                "face_grids",
                                format!("{} grids (3, 4, 6 or 8)", nodes.len()),
                            )
                        })?
                    };
                    Some(FaceTie {
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
            },
            rotor_rows: Vec::new(),
            pad_side: match field(row, "pad_grids", "gaps", i)? {
                None => None,
                Some(v) => Some(PadSide {
                    nodes: v
                        .extract()
                        .map_err(|_| bad("gaps", i, "pad_grids", "not a list of grid ids"))?,
                    weights: req("pad_weights")?
                        .extract()
                        .map_err(|_| bad("gaps", i, "pad_weights", "not a list of numbers"))?,
                    dofs: Vec::new(),
                }),
            },
            friction: None,
        });
    }
    Ok(gaps)
}

/// The gap table as records (the CSV columns and the sliding velocity).
pub fn gaps_to_py<'py>(py: Python<'py>, gaps: &[Gap]) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for g in gaps {
        let r = PyDict::new(py);
        r.set_item("pad_grid", g.pad_node)?;
        r.set_item("rotor_grid", g.rotor_node)?;
        for (k, v) in ["x", "y", "z"].iter().zip(g.coords) {
            r.set_item(*k, v)?;
        }
        for (k, v) in ["nx", "ny", "nz"].iter().zip(g.normal) {
            r.set_item(*k, v)?;
        }
        r.set_item("area", g.area)?;
        r.set_item("p0", g.p0)?;
        r.set_item("temperature", g.temperature)?;
        for (k, v) in DERIVED_GAP_COLUMNS.iter().zip(g.v_slide) {
            r.set_item(*k, v)?;
        }
        if let Some(t) = &g.tie {
            r.set_item("face", t.face)?;
            r.set_item("xi", t.xi[0])?;
            r.set_item("eta", t.xi[1])?;
            r.set_item("face_grids", t.nodes.clone())?;
            r.set_item("weights", t.weights.clone())?;
            if t.mortar {
                r.set_item("mortar", true)?;
            }
        }
        if let Some(p) = &g.pad_side {
            r.set_item("pad_grids", p.nodes.clone())?;
            r.set_item("pad_weights", p.weights.clone())?;
        }
        out.append(r)?;
    }
    Ok(out)
}
