//! The harness GPU tests share: a device opened with the validation layer whose errors are
//! checked after everything the test made was dropped (so releasing objects is checked too),
//! the device features a test needs, and skips reported by the test's name on the terminal and
//! in a log that `make test` prints at the end, so a skip is never a silent pass; and seeded
//! random test data ([`Rng`]).
//!
//! ```ignore
//! let Some(gpu) = TestGpu::with(&[Need::MeshShaders]) else { return };
//! // ... create objects, render, compare with the CPU reference ...
//! // dropped here: objects first (declared later), then the device, after a validation check
//! ```

mod random;

pub use random::Rng;
use std::io::Write;
use std::ops::Deref;
use std::path::PathBuf;
use tessera_gpu::{Capabilities, Gpu, GpuOptions};

/// Environment variable naming the file skipped tests are appended to.
pub const SKIP_LOG_VARIABLE: &str = "TESSERA_SKIP_LOG";

/// A device feature a test needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Need {
    /// Task and mesh shaders.
    MeshShaders,
    /// Multiview in mesh shaders.
    MultiviewMeshShaders,
    /// 64-bit integer atomics on storage buffers.
    BufferInt64Atomics,
    /// 32-bit float atomic add on storage buffers.
    BufferFloatAtomics,
    Tessellation,
    /// Ray-tracing pipelines with acceleration structures.
    RayTracingPipeline,
}

impl Need {
    fn met(self, caps: &Capabilities) -> bool {
        match self {
            Need::MeshShaders => caps.mesh_shader && caps.task_shader,
            Need::MultiviewMeshShaders => caps.mesh_multiview,
            Need::BufferInt64Atomics => caps.buffer_int64_atomics,
            Need::BufferFloatAtomics => caps.buffer_float32_atomic_add,
            Need::Tessellation => caps.tessellation,
            Need::RayTracingPipeline => caps.ray_tracing_pipeline && caps.acceleration_structure,
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Need::MeshShaders => "task/mesh shaders",
            Need::MultiviewMeshShaders => "multiview mesh shaders",
            Need::BufferInt64Atomics => "64-bit buffer atomics",
            Need::BufferFloatAtomics => "float buffer atomics",
            Need::Tessellation => "tessellation shaders",
            Need::RayTracingPipeline => "ray-tracing pipelines",
        }
    }
}

/// The running test's name (libtest names each test's thread after it).
pub fn test_name() -> String {
    std::thread::current()
        .name()
        .unwrap_or("unnamed test")
        .to_string()
}

/// Reports the running test (or the part of it named by `what`) as skipped because of
/// `reason`: on the terminal even when output is captured, and in the skip log.
pub fn skip(what: &str, reason: &str) {
    let name = test_name();
    let line = if what.is_empty() {
        format!("{name}: {reason}")
    } else {
        format!("{name} ({what}): {reason}")
    };
    // Written past libtest's capture (which takes only the print macros), so a skip shows
    // among the passing tests.
    let _ = writeln!(std::io::stderr(), "SKIPPED {line}");
    if let Some(path) = std::env::var_os(SKIP_LOG_VARIABLE) {
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path);
        if let Ok(mut file) = file {
            let _ = writeln!(file, "{line}");
        }
    }
}

/// A device with the validation layer on; when dropped (after the objects a test made), it
/// fails the test on any validation error.
pub struct TestGpu {
    gpu: Gpu,
}

impl TestGpu {
    /// The default device. Panics when none opens: every GPU test needs one (CI installs
    /// lavapipe).
    pub fn new() -> TestGpu {
        let gpu = Gpu::new(&GpuOptions {
            device_index: None,
            validation: true,
            ..GpuOptions::default()
        })
        .unwrap_or_else(|e| panic!("cannot open a Vulkan device for tests: {e}"));
        TestGpu { gpu }
    }

    /// The default device if it has every one of `needs`; else the test is reported as
    /// skipped, naming what the device lacks, and `None` returned.
    pub fn with(needs: &[Need]) -> Option<TestGpu> {
        let gpu = TestGpu::new();
        let missing: Vec<&str> = needs
            .iter()
            .filter(|n| !n.met(gpu.caps()))
            .map(|n| n.describe())
            .collect();
        if missing.is_empty() {
            return Some(gpu);
        }
        let reason = format!("{} lacks {}", gpu.caps().device_name, missing.join(", "));
        skip("", &reason);
        None
    }

    /// Whether the device has `need` (for tests that run part of their work without it).
    pub fn has(&self, need: Need) -> bool {
        need.met(self.caps())
    }

    /// Fails now on validation errors seen so far.
    pub fn assert_clean(&self) {
        let errors = self.gpu.validation_errors();
        assert!(
            errors.is_empty(),
            "{} validation error(s):\n{}",
            errors.len(),
            errors.join("\n")
        );
    }
}

impl Default for TestGpu {
    fn default() -> Self {
        TestGpu::new()
    }
}

impl Deref for TestGpu {
    type Target = Gpu;
    fn deref(&self) -> &Gpu {
        &self.gpu
    }
}

impl Drop for TestGpu {
    fn drop(&mut self) {
        // A test that already failed keeps its own message.
        if !std::thread::panicking() {
            self.assert_clean();
        }
    }
}

/// Where the fetch scripts (`make test`'s dependencies: `scripts/fetch-*.sh`) put real data:
/// `path` under `$TESSERA_DATA`, else under `$XDG_CACHE_HOME/tessera/data`, else under
/// `~/.cache/tessera/data`.
pub fn data_file(path: &str) -> PathBuf {
    let base = std::env::var_os("TESSERA_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            std::env::var_os("XDG_CACHE_HOME")
                .map(PathBuf::from)
                .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
                .unwrap_or_else(|| PathBuf::from("/tmp"))
                .join("tessera/data")
        });
    base.join(path)
}
