//! Every failure reaches Python as a `tessera.TesseraError`: `DataError` for input that is
//! wrong (files, arrays, options), `GpuError` for the device. A panic is caught at the
//! boundary and raised as `TesseraError`, so no Rust panic unwinds into the interpreter.

use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    tessera,
    TesseraError,
    PyException,
    "Any error Tessera raises."
);
create_exception!(
    tessera,
    DataError,
    TesseraError,
    "Input Tessera cannot use: a file, an array or an option."
);
create_exception!(
    tessera,
    GpuError,
    TesseraError,
    "The Vulkan device failed, or has no way to run what was asked."
);

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("TesseraError", py.get_type::<TesseraError>())?;
    m.add("DataError", py.get_type::<DataError>())?;
    m.add("GpuError", py.get_type::<GpuError>())?;
    Ok(())
}

/// The exception for a technique's error, with the message the CLI prints.
pub fn from_tessera(error: tessera::Error) -> PyErr {
    match error {
        tessera::Error::Gpu(e) => GpuError::new_err(e.to_string()),
        tessera::Error::Data(e) => DataError::new_err(e.to_string()),
        tessera::Error::Invalid(message) => DataError::new_err(message),
    }
}

pub fn from_data(error: tessera_data::DataError) -> PyErr {
    DataError::new_err(error.to_string())
}

pub fn from_gpu(error: tessera_gpu::GpuError) -> PyErr {
    GpuError::new_err(error.to_string())
}

/// Runs `work`, turning a panic into a `TesseraError` that says what was being done.
pub fn guarded<T>(doing: &str, work: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        let reason = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".to_string());
        Err(TesseraError::new_err(format!(
            "internal error while {doing}: {reason} (please report it)"
        )))
    })
}
