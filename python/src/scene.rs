//! `squeal.Scene`: a typed, validated scene in memory.

use crate::args;
use crate::arrays;
use crate::errors::{to_py, SceneError};
use crate::values::{to_toml, toml_to_py, value_text};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use squeal_pipeline::scene::{ModelSource, StoredArrays};
use squeal_pipeline::Scene;
use std::path::PathBuf;

/// A squeal scene (the TOML file's tables, typed and validated).
///
/// Build one with `Scene.from_file`, `Scene.from_toml`, `Scene.from_dict` or
/// `Scene.from_arrays` (a stored reduced model given as numpy arrays: no files); change values
/// with `scene.set("friction.law.mu0", 0.5)`, which returns a new scene (the keys are those of
/// `squeal ... --set`). Scenes pickle (for Dask workers), arrays included.
#[pyclass(name = "Scene", module = "squeal", frozen)]
#[derive(Clone)]
pub struct PyScene {
    pub inner: Scene,
}

/// `key=value` texts of a dict argument `arg` of `func` (keys: dotted scene keys).
fn overrides(func: &str, arg: &str, set: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let mut out = Vec::new();
    if let Some(d) = set.filter(|d| !d.is_none()) {
        let d = args::str_dict(func, arg, d, "dotted scene key")?;
        for (k, v) in d.iter() {
            let key: String = k.extract()?;
            out.push(format!("{key}={}", value_text(&v, &key)?));
        }
    }
    Ok(out)
}

/// The `base_dir` argument: a path, default ".".
fn base_dir_arg(func: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<PathBuf> {
    match v {
        Some(v) if !v.is_none() => args::path(func, "base_dir", v),
        _ => Ok(PathBuf::from(".")),
    }
}

#[pymethods]
impl PyScene {
    /// Reads a scene file; `set` overrides values as `--set key=value` does.
    #[staticmethod]
    #[pyo3(signature = (path, set=None))]
    fn from_file(path: &Bound<'_, PyAny>, set: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let path = args::path("Scene.from_file", "path", path)?;
        let o = overrides("Scene.from_file", "set", set)?;
        Scene::load(&path, &o)
            .map(|inner| Self { inner })
            .map_err(|e| to_py(&e))
    }

    /// A scene from TOML text; relative paths in it are resolved against `base_dir`.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir=None, set=None))]
    fn from_toml(
        text: &Bound<'_, PyAny>,
        base_dir: Option<&Bound<'_, PyAny>>,
        set: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let f = "Scene.from_toml";
        let text = args::string(f, "text", text, "a str (the scene's TOML text)")?;
        let base_dir = base_dir_arg(f, base_dir)?;
        let o = overrides(f, "set", set)?;
        Scene::from_toml_str(&text, base_dir, &o)
            .map(|inner| Self { inner })
            .map_err(|e| to_py(&e))
    }

    /// A scene from a dict with the TOML file's structure (None values are left out).
    #[staticmethod]
    #[pyo3(signature = (data, base_dir=None, set=None))]
    fn from_dict(
        data: &Bound<'_, PyAny>,
        base_dir: Option<&Bound<'_, PyAny>>,
        set: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let f = "Scene.from_dict";
        let data = args::str_dict(f, "data", data, "scene table name")?;
        let doc = to_toml(data.as_any(), "data")?;
        let text = toml::to_string(&doc)
            .map_err(|e| SceneError::new_err(format!("data: cannot be written as TOML: {e}")))?;
        let base_dir = base_dir_arg(f, base_dir)?;
        let o = overrides(f, "set", set)?;
        Scene::from_toml_str(&text, base_dir, &o)
            .map(|inner| Self { inner })
            .map_err(|e| to_py(&e))
    }

    /// A scene over a stored reduced model given in memory (no files): `K`, `M` (n × n),
    /// optional `B` (n × n, element damping) and `p_brake` (n, the unit brake load), the DOF
    /// map `dofs` (n records `{component, kind, grid, comp}` or `{component, kind: "modal",
    /// index}`) and the gap table `gaps` (records with the columns `pad_grid, rotor_grid, x, y,
    /// z, nx, ny, nz, area, p0, temperature`; unit normals), as `squeal.reduce` returns them.
    /// `toml` holds the rest of the scene (`[friction]`, `[rotor]`, `[transient]`, `[cea]`, …)
    /// as TOML text or a dict.
    #[staticmethod]
    #[pyo3(signature = (K, M, dofs, gaps=None, B=None, p_brake=None, toml=None, base_dir=None, set=None))]
    #[allow(non_snake_case)]
    fn from_arrays(
        K: &Bound<'_, PyAny>,
        M: &Bound<'_, PyAny>,
        dofs: &Bound<'_, PyAny>,
        gaps: Option<&Bound<'_, PyAny>>,
        B: Option<&Bound<'_, PyAny>>,
        p_brake: Option<&Bound<'_, PyAny>>,
        toml: Option<&Bound<'_, PyAny>>,
        base_dir: Option<&Bound<'_, PyAny>>,
        set: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let f = "Scene.from_arrays";
        let text = match toml {
            None => String::new(),
            Some(t) if t.is_none() => String::new(),
            Some(t) if t.is_instance_of::<PyDict>() => {
                let doc = to_toml(t, "toml")?;
                toml::to_string(&doc).map_err(|e| {
                    SceneError::new_err(format!("toml: cannot be written as TOML: {e}"))
                })?
            }
            Some(t) => args::string(f, "toml", t, "TOML text (str), a dict or None")?,
        };
        let base_dir = base_dir_arg(f, base_dir)?;
        let a = StoredArrays {
            k: arrays::mat_from_py(K, "K")?,
            m: arrays::mat_from_py(M, "M")?,
            b: B.map(|b| arrays::mat_from_py(b, "B")).transpose()?,
            p_brake: p_brake
                .map(|p| arrays::vec_from_py(p, "p_brake"))
                .transpose()?,
            dofs: arrays::dofmap_from_py(dofs)?,
            gaps: gaps
                .map(arrays::gaps_from_py)
                .transpose()?
                .unwrap_or_default(),
        };
        let o = overrides(f, "set", set)?;
        Scene::with_arrays(&text, base_dir, &o, a)
            .map(|inner| Self { inner })
            .map_err(|e| to_py(&e))
    }

    /// A copy with `key` set to `value` (a dotted key as `--set` writes it:
    /// `friction.law.mu0`, `components.0.geometry.thickness`); the whole scene is validated
    /// again and an invalid key or value raises SceneError naming it.
    fn set(&self, key: &Bound<'_, PyAny>, value: &Bound<'_, PyAny>) -> PyResult<Self> {
        let key = args::string(
            "Scene.set",
            "key",
            key,
            "a str (a dotted scene key such as \"friction.law.mu0\")",
        )?;
        let mut s = self.inner.clone();
        s.set(&key, &value_text(value, &key)?)
            .map_err(|e| to_py(&e))?;
        Ok(Self { inner: s })
    }

    /// A copy with several keys set together (validated once all are set: values that must
    /// change together, such as both pads' arc); `values` maps dotted keys to values.
    fn set_many(&self, values: &Bound<'_, PyAny>) -> PyResult<Self> {
        let mut s = self.inner.clone();
        s.set_all(&overrides("Scene.set_many", "values", Some(values))?)
            .map_err(|e| to_py(&e))?;
        Ok(Self { inner: s })
    }

    /// The scene as TOML, every default filled in (what `squeal check` prints).
    fn to_toml(&self) -> String {
        self.inner.resolved_toml()
    }

    /// The scene as a dict, every default filled in.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v: toml::Value = toml::from_str(&self.inner.resolved_toml())
            .map_err(|e| SceneError::new_err(e.to_string()))?;
        toml_to_py(py, &v)
    }

    /// The folder relative paths of the scene are resolved against.
    #[getter]
    fn base_dir(&self) -> PathBuf {
        self.inner.base_dir.clone()
    }

    /// Where the reduced model comes from: `mesh`, `op4`, `punch` or `arrays`.
    #[getter]
    fn model_source(&self) -> &'static str {
        match self.inner.model.from {
            ModelSource::Mesh => "mesh",
            ModelSource::Op4 => "op4",
            ModelSource::Punch => "punch",
            ModelSource::Arrays => "arrays",
        }
    }

    /// Names of the scene's components.
    #[getter]
    fn components(&self) -> Vec<String> {
        self.inner
            .components
            .iter()
            .map(|c| c.name.clone())
            .collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(title={:?}, model={}, components={:?})",
            self.inner.title,
            self.model_source(),
            self.components()
        )
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner
    }

    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let f = py.import("squeal._squeal")?.getattr("scene_from_state")?;
        let arrays = match &self.inner.model.arrays {
            Some(a) => {
                let a = &a.0;
                let d = PyDict::new(py);
                d.set_item("K", arrays::mat_to_py(py, &a.k))?;
                d.set_item("M", arrays::mat_to_py(py, &a.m))?;
                d.set_item("B", a.b.as_ref().map(|b| arrays::mat_to_py(py, b)))?;
                d.set_item("p_brake", a.p_brake.clone())?;
                d.set_item("dofs", arrays::dofmap_to_py(py, &a.dofs)?)?;
                d.set_item("gaps", arrays::gaps_to_py(py, &a.gaps)?)?;
                d.into_any()
            }
            None => py.None().into_bound(py),
        };
        let args = PyTuple::new(
            py,
            [
                self.to_toml().into_pyobject(py)?.into_any(),
                self.inner.base_dir.clone().into_pyobject(py)?.into_any(),
                arrays,
            ],
        )?;
        Ok((f, args))
    }
}

/// Unpickles a scene (`Scene.__reduce__`).
#[pyfunction]
pub fn scene_from_state(
    text: &str,
    base_dir: PathBuf,
    arrays: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyScene> {
    match arrays {
        None => Scene::from_toml_str(text, base_dir, &[])
            .map(|inner| PyScene { inner })
            .map_err(|e| to_py(&e)),
        Some(d) => {
            let get = |k: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
                Ok(d.get_item(k)?.filter(|v| !v.is_none()))
            };
            // The resolved TOML says from = "arrays": drop it, with_arrays sets it.
            let mut doc: toml::Value =
                toml::from_str(text).map_err(|e| SceneError::new_err(e.to_string()))?;
            if let Some(m) = doc.get_mut("model").and_then(|m| m.as_table_mut()) {
                m.remove("from");
            }
            let text = toml::to_string(&doc).map_err(|e| SceneError::new_err(e.to_string()))?;
            let req =
                |k: &str| get(k)?.ok_or_else(|| SceneError::new_err(format!("state: no {k}")));
            let text = text.into_pyobject(d.py())?.into_any();
            let base_dir = base_dir.into_pyobject(d.py())?.into_any();
            PyScene::from_arrays(
                &req("K")?,
                &req("M")?,
                &req("dofs")?,
                get("gaps")?.as_ref(),
                get("B")?.as_ref(),
                get("p_brake")?.as_ref(),
                Some(&text),
                Some(&base_dir),
                None,
            )
        }
    }
}
