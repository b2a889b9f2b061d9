//! Python values ↔ TOML values, and results ↔ plain Python objects (dicts, lists, scalars).

use crate::errors::SceneError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A Python value as a TOML value: bool, int, float, str, list/tuple, dict (string keys);
/// `where_` names the place in errors (a scene key, `dict`).
pub fn to_toml(obj: &Bound<'_, PyAny>, where_: &str) -> PyResult<toml::Value> {
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(obj.extract().map_err(|_| {
            SceneError::new_err(format!("{where_}: integer {obj} does not fit in 64 bits"))
        })?));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut t = toml::map::Map::new();
        for (k, v) in d.iter() {
            let key: String = k
                .extract()
                .map_err(|_| SceneError::new_err(format!("{where_}: key {k} is not a string")))?;
            let inner = format!("{where_}.{key}");
            if v.is_none() {
                continue; // None = not given (the default).
            }
            t.insert(key, to_toml(&v, &inner)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            out.push(to_toml(&v?, &format!("{where_}[{i}]"))?);
        }
        return Ok(toml::Value::Array(out));
    }
    // numpy scalars and other numbers: through float / int.
    if obj.hasattr("__index__")? {
        return Ok(toml::Value::Integer(
            obj.call_method0("__index__")?.extract()?,
        ));
    }
    if obj.hasattr("__float__")? {
        return Ok(toml::Value::Float(
            obj.call_method0("__float__")?.extract()?,
        ));
    }
    Err(SceneError::new_err(format!(
        "{where_}: {} is not a TOML value (bool, int, float, str, list, dict)",
        obj.repr()?
    )))
}

/// The text of a value as `--set key=value` takes it.
pub fn value_text(obj: &Bound<'_, PyAny>, key: &str) -> PyResult<String> {
    Ok(to_toml(obj, key)?.to_string())
}

/// A TOML value as a Python object.
pub fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(toml_to_py(py, x)?)?;
            }
            l.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, toml_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// A result as plain Python objects (dict, list, str, int, float, bool, None), made straight
/// from the Rust value by `pythonize` (no JSON text), then shaped as the CLI's JSON file of the
/// same value reads back with `json.load`: a tuple becomes a list and a non-finite float None
/// (serde_json writes NaN and ±inf as `null`), so `squeal.cea(...).report` and `cea.json` agree.
pub fn to_py<'py, T: serde::Serialize + ?Sized>(
    py: Python<'py>,
    v: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let obj = pythonize::pythonize(py, v).map_err(|e| {
        pyo3::exceptions::PyValueError::new_err(format!("converting a result to Python: {e}"))
    })?;
    json_shaped(obj)
}

/// `obj` with its tuples as lists and its NaN/±inf as None, in place for dicts and lists.
fn json_shaped(obj: Bound<'_, PyAny>) -> PyResult<Bound<'_, PyAny>> {
    let py = obj.py();
    if let Ok(f) = obj.cast::<PyFloat>() {
        return Ok(match f.value().is_finite() {
            true => obj,
            false => py.None().into_bound(py),
        });
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let keys: Vec<_> = d.keys().iter().collect();
        for k in keys {
            if let Some(v) = d.get_item(&k)? {
                d.set_item(k, json_shaped(v)?)?;
            }
        }
        return Ok(obj);
    }
    if let Ok(l) = obj.cast::<PyList>() {
        for i in 0..l.len() {
            l.set_item(i, json_shaped(l.get_item(i)?)?)?;
        }
        return Ok(obj);
    }
    if let Ok(t) = obj.cast::<PyTuple>() {
        let items = t.iter().map(json_shaped).collect::<PyResult<Vec<_>>>()?;
        return Ok(PyList::new(py, items)?.into_any());
    }
    Ok(obj)
}

/// A Python value (dicts and lists as [`to_py`] makes them) as the Rust value `T` (by
/// `pythonize::depythonize`); the error is the deserialiser's message.
pub fn from_py<T: serde::de::DeserializeOwned>(obj: &Bound<'_, PyAny>) -> Result<T, String> {
    pythonize::depythonize(obj).map_err(|e| e.to_string())
}
