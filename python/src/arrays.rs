//! NumPy helpers: what an array holds, and any array-like of real numbers
//! as a float64 array (read in place when it already is one).

use pyo3::prelude::*;

use crate::errors::type_error;

/// The dtype kind of a NumPy array or scalar (`f`, `i`, `u`, `b`), or
/// MxTypeError when it holds anything but real numbers.
pub fn real_dtype(py: Python<'_>, arr: &Bound<'_, PyAny>, what: &str) -> PyResult<String> {
    let dtype = arr.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if matches!(kind.as_str(), "f" | "i" | "u" | "b") {
        Ok(kind)
    } else {
        Err(type_error(
            py,
            format!(
                "`{what}` must hold real numbers, found dtype {}",
                dtype.str()?
            ),
        ))
    }
}

/// A float64 array from any array-like of real numbers (bool, int, float).
pub fn f64_array<'py>(
    py: Python<'py>,
    obj: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<Bound<'py, numpy::PyArrayDyn<f64>>> {
    if let Ok(a) = obj.cast::<numpy::PyArrayDyn<f64>>() {
        return Ok(a.clone());
    }
    let np = py.import("numpy")?;
    let arr = np
        .getattr("asarray")?
        .call1((obj,))
        .map_err(|e| type_error(py, format!("`{what}` must be an array of numbers ({e})")))?;
    let kind = real_dtype(py, &arr, what)?;
    let arr = if kind == "f"
        && arr
            .getattr("dtype")?
            .getattr("itemsize")?
            .extract::<usize>()?
            == 8
    {
        arr
    } else {
        arr.call_method1("astype", ("float64",))?
    };
    Ok(arr.cast_into::<numpy::PyArrayDyn<f64>>()?)
}
