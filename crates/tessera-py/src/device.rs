//! The Vulkan device. Objects made on it (renderers) keep it alive; the GPU work of a call
//! runs with the interpreter's lock released, and the device's own lock keeps two Python
//! threads from submitting at once (Vulkan's queue needs that).

use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tessera_gpu::{Gpu, GpuOptions};

use crate::errors::{from_gpu, guarded, GpuError};

/// A Vulkan device: `Device()` takes the best one, `Device(index)` the one `devices()` lists
/// at `index`. `validation=True` turns the Khronos validation layer on (slow; for
/// debugging); `timeout` is the longest one GPU submission may run, in seconds.
#[pyclass(module = "tessera", frozen)]
pub struct Device {
    pub(crate) gpu: Arc<Mutex<Gpu>>,
}

impl Device {
    /// The device, locked; a lock poisoned by a panic elsewhere is still usable, since every
    /// GPU call waits for its own work to finish.
    pub fn lock(gpu: &Mutex<Gpu>) -> MutexGuard<'_, Gpu> {
        gpu.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

#[pymethods]
impl Device {
    #[new]
    #[pyo3(signature = (index=None, validation=false, timeout=60.0))]
    fn new(py: Python<'_>, index: Option<usize>, validation: bool, timeout: f64) -> PyResult<Self> {
        if !(timeout.is_finite() && timeout > 0.0) {
            return Err(crate::errors::DataError::new_err(format!(
                "timeout {timeout}: a positive number of seconds"
            )));
        }
        let options = GpuOptions {
            device_index: index,
            validation,
            timeout: Some(Duration::from_secs_f64(timeout)),
            pipeline_statistics: false,
        };
        let gpu = py.detach(|| {
            guarded("opening the device", || {
                Gpu::new(&options).map_err(from_gpu)
            })
        })?;
        Ok(Device {
            gpu: Arc::new(Mutex::new(gpu)),
        })
    }

    /// The device's name, as the driver reports it.
    #[getter]
    fn name(&self) -> String {
        Device::lock(&self.gpu).caps().device_name.clone()
    }

    /// What the device can do (mesh shaders, ray tracing, 64-bit atomics, ...) as JSON.
    fn _capabilities_json(&self) -> PyResult<String> {
        serde_json::to_string(Device::lock(&self.gpu).caps())
            .map_err(|e| GpuError::new_err(e.to_string()))
    }

    /// Device memory in use, from the allocator's bookkeeping, as a dict:
    /// `allocated_bytes` and `allocations` held by live buffers and images (they return to
    /// the same level once renderers and data are dropped), `reserved_bytes` and `blocks` of
    /// device memory kept to place them in (kept for reuse after they go).
    fn memory<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let report = Device::lock(&self.gpu).memory_report();
        let dict = PyDict::new(py);
        dict.set_item("allocated_bytes", report.allocated_bytes)?;
        dict.set_item("allocations", report.allocations)?;
        dict.set_item("reserved_bytes", report.reserved_bytes)?;
        dict.set_item("blocks", report.blocks)?;
        Ok(dict)
    }

    /// Error messages the validation layer reported so far (empty when it is off).
    fn validation_errors(&self) -> Vec<String> {
        Device::lock(&self.gpu).validation_errors()
    }

    fn __repr__(&self) -> String {
        format!("tessera.Device({:?})", self.name())
    }
}

/// The Vulkan devices present, in the order `Device(index)` counts them: a list of
/// `(index, name, type)`.
#[pyfunction]
fn devices(py: Python<'_>) -> PyResult<Vec<(usize, String, String)>> {
    let listed = py.detach(|| {
        guarded("listing the devices", || {
            tessera_gpu::list_devices().map_err(from_gpu)
        })
    })?;
    Ok(listed
        .into_iter()
        .map(|d| (d.index, d.name, d.device_type))
        .collect())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Device>()?;
    m.add_function(wrap_pyfunction!(devices, m)?)?;
    Ok(())
}
