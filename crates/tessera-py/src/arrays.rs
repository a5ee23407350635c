//! numpy arrays checked (dimensions, shape, dtype) and copied into Tessera's layouts, with
//! messages that name the argument. Arrays are indexed `[x, y, z]` as nibabel and
//! scikit-image index them; Tessera stores x fastest, so a Fortran-ordered array is read
//! straight through and a C-ordered one is read transposed (one copy either way: the data
//! then belongs to the GPU upload).

use numpy::ndarray::{ArrayViewD, Axis};
use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use tessera_data::Samples;

use crate::errors::DataError;

/// `value` as a numpy array of `ndim` dimensions whose dtype kind is one of `kinds`
/// (numpy's letters: `u` unsigned, `i` signed, `f` float, `b` bool).
fn numpy_array<'py>(
    value: &Bound<'py, PyAny>,
    what: &str,
    ndim: usize,
    kinds: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let numpy = PyModule::import(value.py(), "numpy")?;
    let array = numpy
        .call_method1("asarray", (value,))
        .map_err(|e| DataError::new_err(format!("{what}: not an array ({e})")))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != ndim {
        return Err(DataError::new_err(format!(
            "{what}: expected {ndim} dimensions, got {} (shape {shape:?})",
            shape.len()
        )));
    }
    if shape.contains(&0) {
        return Err(DataError::new_err(format!(
            "{what}: the array is empty (shape {shape:?})"
        )));
    }
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if !kinds.contains(kind.as_str()) {
        let name: String = dtype.getattr("name")?.extract()?;
        return Err(DataError::new_err(format!(
            "{what}: dtype {name} is not supported here"
        )));
    }
    Ok(array)
}

/// The array's dtype name (`uint8`, `float64`, ...).
fn dtype_name(array: &Bound<'_, PyAny>) -> PyResult<String> {
    array.getattr("dtype")?.getattr("name")?.extract()
}

/// `array` converted to float32 where it is not already (a copy only then).
fn as_f32<'py>(array: Bound<'py, PyAny>) -> PyResult<PyReadonlyArrayDyn<'py, f32>> {
    let array = if dtype_name(&array)? == "float32" {
        array
    } else {
        array.call_method1("astype", ("float32",))?
    };
    Ok(array.extract()?)
}

/// The shape of a checked array.
fn shape_of<T: numpy::Element>(array: &PyReadonlyArrayDyn<'_, T>) -> Vec<usize> {
    array.shape().to_vec()
}

/// Elements with the first axis varying fastest (Fortran order), as Tessera stores grids.
fn first_axis_fastest<T: Copy>(view: ArrayViewD<'_, T>) -> Vec<T> {
    view.reversed_axes().iter().copied().collect()
}

fn dims3(shape: &[usize], what: &str) -> PyResult<[u32; 3]> {
    let mut dims = [0u32; 3];
    for (d, &n) in dims.iter_mut().zip(shape) {
        *d = u32::try_from(n)
            .map_err(|_| DataError::new_err(format!("{what}: {n} samples along an axis")))?;
    }
    Ok(dims)
}

/// A volume's samples from a 3-D array: uint8, uint16 and float32 as they are; other integer
/// and float types as float32 (named in the returned note).
pub fn volume_samples(value: &Bound<'_, PyAny>) -> PyResult<([u32; 3], Samples, Option<String>)> {
    let what = "volume array";
    let array = numpy_array(value, what, 3, "uif")?;
    let dtype = dtype_name(&array)?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    let dims = dims3(&shape, what)?;
    let (samples, note) = match dtype.as_str() {
        "uint8" => {
            let a: PyReadonlyArrayDyn<'_, u8> = array.extract()?;
            (Samples::U8(first_axis_fastest(a.as_array())), None)
        }
        "uint16" => {
            let a: PyReadonlyArrayDyn<'_, u16> = array.extract()?;
            (Samples::U16(first_axis_fastest(a.as_array())), None)
        }
        other => {
            let a = as_f32(array)?;
            let note = (other != "float32").then(|| format!("{other} samples kept as float32"));
            (Samples::F32(first_axis_fastest(a.as_array())), note)
        }
    };
    Ok((dims, samples, note))
}

/// `N × 3` points as float32 triples.
pub fn points(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f32; 3]>> {
    let array = as_f32(numpy_array(value, what, 2, "uif")?)?;
    let shape = shape_of(&array);
    if shape[1] != 3 {
        return Err(DataError::new_err(format!(
            "{what}: expected shape (N, 3), got {shape:?}"
        )));
    }
    let view = array.as_array();
    Ok(view
        .axis_iter(Axis(0))
        .map(|p| [p[0], p[1], p[2]])
        .collect())
}

/// A voxel-to-world affine, shape (4, 4) (its last row ignored) or (3, 4), as float64 rows.
pub fn affine_rows(value: &Bound<'_, PyAny>, what: &str) -> PyResult<[[f64; 4]; 3]> {
    let array = numpy_array(value, what, 2, "uif")?.call_method1("astype", ("float64",))?;
    let array: numpy::PyReadonlyArray2<'_, f64> = array.extract()?;
    let view = array.as_array();
    if !matches!(view.shape(), [3 | 4, 4]) {
        return Err(DataError::new_err(format!(
            "{what}: expected shape (4, 4) or (3, 4), got {:?}",
            view.shape()
        )));
    }
    Ok([0, 1, 2].map(|r| [0, 1, 2, 3].map(|c| view[[r, c]])))
}

/// `M × 4` vertex indices, each checked against `vertex_count`.
pub fn tets(value: &Bound<'_, PyAny>, what: &str, vertex_count: usize) -> PyResult<Vec<[u32; 4]>> {
    let array = numpy_array(value, what, 2, "ui")?.call_method1("astype", ("int64",))?;
    let array: PyReadonlyArrayDyn<'_, i64> = array.extract()?;
    let shape = shape_of(&array);
    if shape[1] != 4 {
        return Err(DataError::new_err(format!(
            "{what}: expected shape (M, 4), got {shape:?}"
        )));
    }
    let view = array.as_array();
    let mut out = Vec::with_capacity(shape[0]);
    for (t, row) in view.axis_iter(Axis(0)).enumerate() {
        let mut tet = [0u32; 4];
        for (slot, &index) in tet.iter_mut().zip(row.iter()) {
            if index < 0 || index as u64 >= vertex_count as u64 {
                return Err(DataError::new_err(format!(
                    "{what}: tet {t} uses vertex {index}, but there are {vertex_count} points"
                )));
            }
            *slot = index as u32;
        }
        out.push(tet);
    }
    Ok(out)
}

/// One float per item, `count` of them.
pub fn per_item(value: &Bound<'_, PyAny>, what: &str, count: usize) -> PyResult<Vec<f32>> {
    let array = as_f32(numpy_array(value, what, 1, "uif")?)?;
    let values: Vec<f32> = array.as_array().iter().copied().collect();
    if values.len() != count {
        return Err(DataError::new_err(format!(
            "{what}: {} values for {count} items",
            values.len()
        )));
    }
    Ok(values)
}

/// SH coefficients `(X, Y, Z, K)` in NIfTI's order (x fastest, the coefficient axis last and
/// slowest): dims and values.
pub fn coefficients(value: &Bound<'_, PyAny>) -> PyResult<([u32; 3], u32, Vec<f32>)> {
    let what = "coefficient array";
    let array = as_f32(numpy_array(value, what, 4, "uif")?)?;
    let shape = shape_of(&array);
    let dims = dims3(&shape[..3], what)?;
    let components = u32::try_from(shape[3])
        .map_err(|_| DataError::new_err(format!("{what}: {} coefficients", shape[3])))?;
    Ok((dims, components, first_axis_fastest(array.as_array())))
}
