//! Python objects into what the library reads: a job or scene as text with the name its
//! errors will carry, and a frame array as RGB888 bytes.

use numpy::prelude::*;
use numpy::{PyArray1, PyArray3, PyUntypedArray};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::BindError;

/// A job or scene as the library parses it: the text and the name its errors give.
pub(crate) struct Source {
    /// TOML (or, for a raster job named `*.json`, JSON) text.
    pub text: String,
    /// What errors call it: the path, the caller's `name`, or `<what>`.
    pub name: String,
}

/// Reads `obj`, the argument `arg` (a `kind` such as "raster job"): a `str` is the file's
/// text, an `os.PathLike` names the file, a `dict` is the file's content (written as TOML
/// so that it meets the same parser and the same messages as a file). `name` overrides
/// the name errors use.
pub(crate) fn source(
    obj: &Bound<'_, PyAny>,
    arg: &str,
    kind: &str,
    name: Option<String>,
) -> Result<Source, BindError> {
    if let Ok(s) = obj.cast::<PyString>() {
        let text: String = s
            .extract()
            .map_err(|e| BindError::Value(format!("{arg}: {e}")))?;
        return Ok(Source {
            text,
            name: name.unwrap_or_else(|| format!("<{kind}>")),
        });
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let value = toml_value(d.as_any(), arg)?;
        let text = toml::to_string(&value)
            .map_err(|e| BindError::Value(format!("{arg}: cannot be written as TOML: {e}")))?;
        return Ok(Source {
            text,
            name: name.unwrap_or_else(|| format!("<{kind} dict>")),
        });
    }
    // os.PathLike: whatever os.fspath accepts besides str (pathlib.Path, bytes paths).
    if obj.hasattr("__fspath__").unwrap_or(false) {
        let path: std::path::PathBuf = obj
            .extract()
            .map_err(|e| BindError::Type(format!("{arg}: {e}")))?;
        let text = std::fs::read_to_string(&path)
            .map_err(|e| BindError::Value(format!("cannot read {}: {e}", path.display())))?;
        return Ok(Source {
            text,
            name: name.unwrap_or_else(|| path.display().to_string()),
        });
    }
    Err(BindError::Type(format!(
        "{arg}: expected the {kind} as TOML text (str), a path (os.PathLike) or a dict, got {}",
        type_name(obj)
    )))
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "an object".into())
}

/// A Python value as TOML: dicts, lists and tuples, str, bool, int and float (and what
/// converts to int or float losslessly, such as numpy scalars). `at` is the key path, for
/// the message when a value has no TOML form (None, a set, an object).
fn toml_value(obj: &Bound<'_, PyAny>, at: &str) -> Result<toml::Value, BindError> {
    // bool before int: Python's True is an int too.
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if obj.is_instance_of::<PyInt>() {
        let i: i64 = obj
            .extract()
            .map_err(|_| BindError::Value(format!("{at}: integer outside 64 bits")))?;
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(f) = obj.cast::<PyFloat>() {
        return Ok(toml::Value::Float(f.value()));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        let s: String = s
            .extract()
            .map_err(|e| BindError::Value(format!("{at}: {e}")))?;
        return Ok(toml::Value::String(s));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key = k.cast::<PyString>().map_err(|_| {
                BindError::Type(format!(
                    "{at}: keys must be str, got {} {}",
                    type_name(&k),
                    k.repr().map(|r| r.to_string()).unwrap_or_default()
                ))
            })?;
            let key: String = key
                .extract()
                .map_err(|e| BindError::Value(format!("{at}: {e}")))?;
            let value = toml_value(&v, &format!("{at}[{key:?}]"))?;
            table.insert(key, value);
        }
        return Ok(toml::Value::Table(table));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items = obj
            .try_iter()
            .map_err(|e| BindError::Type(format!("{at}: {e}")))?
            .enumerate()
            .map(|(i, item)| {
                let item = item.map_err(|e| BindError::Type(format!("{at}[{i}]: {e}")))?;
                toml_value(&item, &format!("{at}[{i}]"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        return Ok(toml::Value::Array(items));
    }
    // numpy scalars and other numbers: an exact integer first, then a float.
    if obj.hasattr("__index__").unwrap_or(false) {
        if let Ok(i) = obj.extract::<i64>() {
            return Ok(toml::Value::Integer(i));
        }
    }
    if obj.hasattr("__float__").unwrap_or(false) {
        if let Ok(f) = obj.extract::<f64>() {
            return Ok(toml::Value::Float(f));
        }
    }
    Err(BindError::Type(format!(
        "{at}: {} has no TOML form (use dict, list, str, bool, int or float)",
        type_name(obj)
    )))
}

/// An RGB frame argument: a numpy array of dtype `uint8` and shape (H, W, 3), any strides.
/// Returns its width, height and RGB888 bytes in row-major order; anything else is refused
/// naming `arg`, as `TypeError` (not a uint8 array) or [`crate::Error`] (a wrong shape).
pub(crate) fn rgb_frame(
    obj: &Bound<'_, PyAny>,
    arg: &str,
) -> Result<(u32, u32, Vec<u8>), BindError> {
    let py = obj.py();
    let untyped = obj.cast::<PyUntypedArray>().map_err(|_| {
        BindError::Type(format!(
            "{arg}: expected a numpy array of dtype uint8 and shape (H, W, 3), got {}",
            type_name(obj)
        ))
    })?;
    let dtype = untyped.dtype();
    if !dtype.is_equiv_to(&numpy::dtype::<u8>(py)) {
        return Err(BindError::Type(format!(
            "{arg}: dtype is {}, expected uint8 (an RGB888 frame)",
            dtype.str().map(|s| s.to_string()).unwrap_or_default()
        )));
    }
    let shape = untyped.shape();
    let (h, w) = match *shape {
        [h, w, 3] if h > 0 && w > 0 => (h, w),
        _ => {
            return Err(BindError::Value(format!(
                "{arg}: shape is {shape:?}, expected (H, W, 3) with H, W ≥ 1"
            )))
        }
    };
    let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(BindError::Value(format!(
            "{arg}: shape {shape:?} is larger than a frame can be"
        )));
    };
    let typed = obj
        .cast::<PyArray3<u8>>()
        .map_err(|e| BindError::Type(format!("{arg}: {e}")))?;
    let view = typed
        .try_readonly()
        .map_err(|e| BindError::Value(format!("{arg}: {e}")))?;
    // Logical (C) order whatever the strides: a transposed or sliced array is fine.
    let bytes = view.as_array().iter().copied().collect();
    Ok((width, height, bytes))
}

/// Reads `obj`, the argument `arg`, as a ray tracer's register image if it is a numpy
/// array (1-D uint32, `SCENE_WORDS` words in scene-memory order: what
/// `RenderFrame.regs` holds), or `None` if it is not an array at all (then it is a scene).
pub(crate) fn register_image(
    obj: &Bound<'_, PyAny>,
    arg: &str,
) -> Result<Option<[u32; protocol::axi_lite::SCENE_WORDS]>, BindError> {
    let py = obj.py();
    let Ok(untyped) = obj.cast::<PyUntypedArray>() else {
        return Ok(None);
    };
    let words = protocol::axi_lite::SCENE_WORDS;
    let dtype = untyped.dtype();
    if !dtype.is_equiv_to(&numpy::dtype::<u32>(py)) {
        return Err(BindError::Type(format!(
            "{arg}: dtype is {}, expected uint32 (a register image of {words} words)",
            dtype.str().map(|s| s.to_string()).unwrap_or_default()
        )));
    }
    if untyped.shape() != [words] {
        return Err(BindError::Value(format!(
            "{arg}: shape is {:?}, a register image is ({words},)",
            untyped.shape()
        )));
    }
    let typed = obj
        .cast::<PyArray1<u32>>()
        .map_err(|e| BindError::Type(format!("{arg}: {e}")))?;
    let view = typed
        .try_readonly()
        .map_err(|e| BindError::Value(format!("{arg}: {e}")))?;
    let mut image = [0u32; protocol::axi_lite::SCENE_WORDS];
    for (dst, &src) in image.iter_mut().zip(view.as_array().iter()) {
        *dst = src;
    }
    Ok(Some(image))
}
