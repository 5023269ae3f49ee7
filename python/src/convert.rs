//! Values between Rust and Python: JSON values to Python objects, and behaviors from a
//! Python dict of component name to real value (a number or a label), parsed by the
//! behavior space as the service parses them.

use crate::error;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};
use serde_json::Value;
use trustcbr::cbr_core::{Behavior, BehaviorSpace};

/// A JSON value as a Python object (dicts, lists, floats, ints, strings, `None`).
pub fn to_py<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any(),
            _ => PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN)).into_any(),
        },
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, to_py(py, v)?)?;
            }
            dict.into_any()
        }
    })
}

/// A component's value given in Python, as the text the space parses: a label, or a
/// number in the shortest form that reads back.
fn value_text(name: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    if value.is_instance_of::<PyBool>() {
        return Err(error(format_args!(
            "component `{name}`: expected a number or a label, got a bool"
        )));
    }
    if value.is_instance_of::<PyString>() {
        return value.extract::<String>();
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(value.extract::<i64>()?.to_string());
    }
    match value.extract::<f64>() {
        Ok(x) => Ok(x.to_string()),
        Err(_) => Err(error(format_args!(
            "component `{name}`: expected a number or a label, got {}",
            value.get_type().name()?
        ))),
    }
}

/// A behavior space's components by name, for messages (`speed, padding`).
pub fn component_names(space: &BehaviorSpace) -> String {
    space
        .components()
        .iter()
        .map(|c| c.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A behavior from a dict of component name to real value; the error names the component
/// and its allowed values, as the service's do.
pub fn behavior_from_py(space: &BehaviorSpace, dict: &Bound<'_, PyAny>) -> PyResult<Behavior> {
    let dict = dict.cast::<PyDict>().map_err(|_| {
        error(format_args!(
            "a behavior is a dict of component name to value (components: {})",
            component_names(space)
        ))
    })?;
    let mut pairs: Vec<(String, String)> = Vec::with_capacity(dict.len());
    for (k, v) in dict.iter() {
        let name: String = k
            .extract()
            .map_err(|_| error("a behavior's keys are component names (str)"))?;
        let text = value_text(&name, &v)?;
        pairs.push((name, text));
    }
    space
        .from_named_values(pairs.iter().map(|(n, v)| (n.as_str(), v.as_str())))
        .map_err(error)
}
